"""White Shark Optimizer (Braik, Hammouri, Atwan, Al-Betar & Awadallah 2022).

Equations as numbered in the IWSO paper (Liang & Liu 2023, section 2.1), with Braik et al.'s
parameter formulas:

* velocity, eq. 3: ``v <- mu [v + p1 c1 (w_gbest - w) + p2 c2 (w_best[nu] - w)]`` with
  ``mu = 2 / |2 - tau - sqrt(tau^2 - 4 tau)|`` (0.7188 for tau = 4.11),
  ``p1 = p_max + (p_max - p_min) exp(-(4k/K)^2)``, ``p2 = p_min + (p_max - p_min) exp(-(4k/K)^2)``,
  ``c1, c2 ~ U(0, 1)`` per coordinate and ``nu`` a random shark whose best position is followed;
* position, eq. 4: with probability ``mv = 1 / (a0 + exp((K/2 - k) / a1))`` the shark takes
  ``w ~xor w0 + u a + l b`` where ``a = w > u``, ``b = w < l``, ``w0 = a xor b`` (the negation
  operator keeps in-bound coordinates and sets the others to the violated bound), otherwise
  ``w + v / f`` with the wavy frequency ``f = f_min + (f_max - f_min) / (f_max + f_min)``;
* fish school, eqs. 5-6: with probability ``s_s = |1 - exp(-a2 k / K)|`` per shark,
  ``w' = w_gbest + r1 D sgn(r2 - 0.5)`` with ``D = |rand (w_gbest - w)|``; the first shark
  takes ``w'``, the others ``(w + w') / (2 rand)`` (the papers' text; Braik et al.'s reference
  code multiplies by rand instead; ``s_s <= a2 = 0.0005`` makes the branch rare either way).

Positions are clipped to the box before every evaluation (Algorithm 1, step 23); each shark
keeps its best position found so far (``w_best``) and the global best is the best ever seen.
"""

from __future__ import annotations

import numpy as np

from usvtool.plan.optimizers.base import NON_NEGATIVE, POSITIVE, Optimizer, Param, Range


def constants(p: dict) -> tuple[float, float]:
    """The constriction ``mu`` (from ``tau``) and the wavy frequency ``f``."""
    tau = p["tau"]
    mu = 2.0 / abs(2.0 - tau - np.sqrt(tau * tau - 4.0 * tau))
    return mu, p["f_min"] + (p["f_max"] - p["f_min"]) / (p["f_max"] + p["f_min"])


def schedule(p: dict, k: int, K: int) -> tuple[float, float, float, float]:
    """``p1``, ``p2``, ``mv`` and ``s_s`` at iteration ``k`` of ``K``."""
    decay = np.exp(-((4.0 * k / K) ** 2))
    p1 = p["p_max"] + (p["p_max"] - p["p_min"]) * decay
    p2 = p["p_min"] + (p["p_max"] - p["p_min"]) * decay
    mv = 1.0 / (p["a0"] + np.exp((K / 2.0 - k) / p["a1"]))
    s_s = abs(1.0 - np.exp(-p["a2"] * k / K))
    return p1, p2, mv, s_s


class WSO(Optimizer):
    name = "wso"
    # f_min, f_max > 0 keep the wavy frequency f > 0 (eq. 4 divides by it); tau >= 4 keeps
    # mu's square root real (Clerc's constriction); a0 >= 0 keeps mv's divisor > 0 and a1
    # divides; a2 >= 0 keeps s_s in [0, 1)
    parameters = {
        "f_min": Param(0.07, "the wavy frequency's low end", POSITIVE),
        "f_max": Param(0.75, "the wavy frequency's high end", POSITIVE),
        "tau": Param(4.11, "the acceleration coefficient (Clerc's constriction)", Range(4.0)),
        "p_min": Param(0.5, "the low end of the velocity weights p1, p2"),
        "p_max": Param(1.5, "the high end of the velocity weights p1, p2"),
        "a0": Param(6.25, "the constant of mv's divisor", NON_NEGATIVE),
        "a1": Param(100.0, "the time scale of mv's exponential", POSITIVE),
        "a2": Param(0.0005, "the rate of s_s", NON_NEGATIVE),
    }

    def _run(self) -> None:
        n, K = self.pop, self.iters
        mu, freq = constants(self.params)
        W, F = self._initial()
        V = np.zeros_like(W)
        best_W, best_F = W.copy(), F.copy()
        for k in range(1, K + 1):
            p1, p2, mv, s_s = schedule(self.params, k, K)
            nu = self.rng.integers(0, n, n)
            c1, c2 = self.rng.random((2, n, self.dim))
            V = mu * (V + p1 * c1 * (self.best_x - W) + p2 * c2 * (best_W[nu] - W))
            W = self._move(W, V, F, freq, mv, k)
            W = self.clip(self._school(W, s_s))
            F = self.evaluate(W)
            W, F = self._refine(W, F)
            better = F < best_F
            best_W[better], best_F[better] = W[better], F[better]
            self.record(k - 1)

    # -- steps that IWSO replaces ------------------------------------------------------------

    def _initial(self) -> tuple[np.ndarray, np.ndarray]:
        """A uniformly random population and its costs."""
        W = self.uniform()
        return W, self.evaluate(W)

    def _move(self, W, V, F, freq: float, mv: float, k: int) -> np.ndarray:
        """Eq. 4: bound operator with probability ``mv``, wavy motion otherwise."""
        return self._wavy(W, W, W + V / freq, mv)

    def _refine(self, W: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Hook for a step after the evaluation (IWSO's simplex); WSO has none."""
        return W, F

    # -- shared pieces --------------------------------------------------------------------

    def _wavy(self, W, kept, moved, mv: float) -> np.ndarray:
        """Eq. 4's choice: ``kept ~xor w0 + u a + l b`` if ``rand < mv`` else ``moved``.

        ``a``, ``b`` and ``w0`` come from the current positions ``W``; ``kept`` is ``W`` in
        eq. 4 and ``alpha W`` in IWSO's eq. 9.
        """
        a = W > self.upper
        b = W < self.lower
        w0 = a ^ b
        bounded = kept * ~w0 + self.upper * a + self.lower * b
        sense = self.rng.random(W.shape[0]) < mv
        return np.where(sense[:, None], bounded, moved)

    def _school(self, W: np.ndarray, s_s: float) -> np.ndarray:
        """Eqs. 5-6, for the sharks whose draw ``r3 < s_s``."""
        n, d = W.shape
        school = self.rng.random(n) < s_s
        if not school.any():
            return W
        r1, r2, r = self.rng.random((3, n, d))
        D = np.abs(r * (self.best_x - W))
        W_prime = self.best_x + r1 * D * np.sign(r2 - 0.5)
        follow = (W + W_prime) / (2.0 * (1.0 - self.rng.random((n, d))))  # rand in (0, 1]
        follow[0] = W_prime[0]
        return np.where(school[:, None], follow, W)
