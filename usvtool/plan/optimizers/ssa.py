"""Sparrow Search Algorithm (Xue & Shen 2020), as written in the ISSA paper (Liu, Zhang, Ma &
Pan 2023, J. Mar. Sci. Eng. 11, 2292, eqs. 1-3).

Each iteration sorts the sparrows by cost (rank ``i = 1`` is the best) and runs three phases,
each evaluated at once and followed by greedy selection (a sparrow keeps its new position only
if it is better, as in Xue & Shen's reference code, whose updates start from each sparrow's
best position):

* producers, the best 20 % (eq. 1): with one warning value ``R2 ~ U(0, 1)`` per iteration,
  ``x exp(-i / (alpha iter_max))`` (``alpha ~ U(0, 1]`` per producer) if ``R2 < ST``, else
  ``x + Q L`` (``Q ~ N(0, 1)``, ``L`` a row of ones). The ISSA paper prints this branch as
  ``X · R × λ``, a product; we keep Xue & Shen's sum, which the ISSA paper does not claim
  to change and in which the row of ones has a role (it spreads the scalar step over the
  coordinates; in a product it would do nothing). Xue & Shen use 20 % producers; the ISSA
  paper's Table 1 lists 0.3 discoverers, 0.2 followers and 0.15 scouts, which do not add up
  as a partition, so we keep the original 20 %;
* followers, the rest (eq. 2): rank ``i > n/2`` flies off, ``Q exp((x_worst - x) / i^2)``;
  the others join the best position ``x_P`` after the producer phase,
  ``x_P + |x - x_P| A+ L`` with ``A`` a row of random +-1 and ``A+ = A^T (A A^T)^-1 = A^T / d``,
  i.e. the same scalar step added to every coordinate;
* scouts, 15 % drawn at random (eq. 3, 10-20 % in the paper): ``x_best + beta |x - x_best|``
  (``beta ~ N(0, 1)`` per coordinate, as Xue & Shen's code draws it) if ``f > f_g``, else
  ``x + K |x - x_worst| / ((f - f_w) + zeta)`` with ``K ~ U(-1, 1)``.

``x_worst``/``f_w`` are taken at the start of the iteration, ``x_best``/``f_g`` are the best so
far. Positions are clipped to the box before evaluation (neither paper gives a rule; Xue &
Shen's code clips; :mod:`.ssa_redraw` is the variant that redraws instead). The producer move
``x exp(-i / (alpha iter_max))`` and the fly-off ``Q exp(...)`` pull towards the coordinate
origin, which is why SSA excels on benchmarks whose optimum is there.
"""

from __future__ import annotations

import numpy as np

from usvtool.plan.optimizers.base import Optimizer


class SSA(Optimizer):
    name = "ssa"
    defaults = {"producers": 0.2, "scouts": 0.15, "safety": 0.8, "zeta": 1e-50}

    def _run(self) -> None:
        X = self._initial()
        F = self.evaluate(X)
        for t in range(1, self.iters + 1):
            X, F = self._step(X, F, t)
            self.record(t - 1)

    def _initial(self) -> np.ndarray:
        return self.uniform()

    def _step(self, X: np.ndarray, F: np.ndarray, t: int) -> tuple[np.ndarray, np.ndarray]:
        """One SSA iteration (eqs. 1-3) on the population sorted by cost."""
        p, rng = self.params, self.rng
        n, d = X.shape
        order = np.argsort(F, kind="stable")
        X, F = X[order], F[order]
        rank = np.arange(1, n + 1, dtype=float)[:, None]
        x_worst, f_worst = X[-1].copy(), F[-1]
        n_p = min(n, max(1, round(p["producers"] * n)))
        n_s = min(n, max(1, round(p["scouts"] * n)))

        # producers, eq. 1
        prod = slice(0, n_p)
        if rng.random() < p["safety"]:
            alpha = 1.0 - rng.random((n_p, 1))  # in (0, 1]
            cand = X[prod] * np.exp(-rank[prod] / (alpha * self.iters))
        else:
            cand = X[prod] + rng.standard_normal((n_p, 1))
        self._greedy(X, F, np.arange(n_p), cand)

        # followers, eq. 2
        if n_p < n:
            fol = np.arange(n_p, n)
            x_p = X[np.argmin(F)]
            Q = rng.standard_normal((fol.size, 1))
            with np.errstate(over="ignore"):
                away = Q * np.exp((x_worst - X[fol]) / rank[fol] ** 2)
            A = rng.choice([-1.0, 1.0], (fol.size, d))
            join = x_p + (np.abs(X[fol] - x_p) * A).sum(axis=1, keepdims=True) / d
            self._greedy(X, F, fol, np.where(rank[fol] > n / 2, away, join))

        # scouts, eq. 3
        sc = rng.choice(n, n_s, replace=False)
        edge = (F[sc] > self.best_f)[:, None]
        beta = rng.standard_normal((n_s, d))
        K = rng.uniform(-1.0, 1.0, (n_s, 1))
        to_best = self.best_x + beta * np.abs(X[sc] - self.best_x)
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            escape = X[sc] + K * np.abs(X[sc] - x_worst) / ((F[sc] - f_worst)[:, None] + p["zeta"])
        self._greedy(X, F, sc, np.where(edge, to_best, escape))
        return X, F

    def _greedy(self, X: np.ndarray, F: np.ndarray, idx: np.ndarray, cand: np.ndarray) -> None:
        """Clip and evaluate ``cand``; sparrows ``idx`` keep the candidates that are better.

        Overflowing steps are clipped to the bound; an undefined one (``0 * inf``) stays put.
        """
        cand = self.clip(np.where(np.isnan(cand), X[idx], cand))
        f = self.evaluate(cand)
        better = f < F[idx]
        X[idx[better]], F[idx[better]] = cand[better], f[better]
