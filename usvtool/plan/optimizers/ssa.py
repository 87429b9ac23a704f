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

from usvtool.plan.optimizers.base import POSITIVE, PROBABILITY, Optimizer, Param


class SSA(Optimizer):
    name = "ssa"
    # shares of the population; ST against R2 ~ U(0, 1); zeta keeps eq. 3's divisor off 0
    parameters = {
        "producers": Param(0.2, "the producers' share of the population", PROBABILITY),
        "scouts": Param(0.15, "the scouts' share of the population", PROBABILITY),
        "safety": Param(0.8, "the safety threshold ST against the warning value R2", PROBABILITY),
        "zeta": Param(1e-50, "keeps eq. 3's divisor off 0", POSITIVE),
    }

    def _run(self) -> None:
        X = self._initial()
        F = self.evaluate(X)
        for t in range(1, self.iters + 1):
            X, F = self._step(X, F, t)
            self.record(t - 1)

    def _initial(self) -> np.ndarray:
        return self.uniform()

    def _step(self, X: np.ndarray, F: np.ndarray, t: int) -> tuple[np.ndarray, np.ndarray]:
        """One SSA iteration on the population sorted by cost: the producers (eq. 1), the
        followers (eq. 2) and the scouts (eq. 3), each phase a method that a variant
        overrides (benchmarks/bench_ssa_mealpy.py's mealpy rules), in turn or in its parts."""
        n = X.shape[0]
        order = np.argsort(F, kind="stable")
        X, F = X[order], F[order]
        rank = np.arange(1, n + 1, dtype=float)[:, None]
        worst = X[-1].copy(), F[-1]
        n_p = min(n, max(1, round(self.params["producers"] * n)))
        self._producers(X, F, rank[:n_p])
        if n_p < n:
            self._followers(X, F, rank, n_p, worst[0])
        self._scouts(X, F, worst)
        return X, F

    # -- the producers, eq. 1 -------------------------------------------------------------

    def _producers(self, X: np.ndarray, F: np.ndarray, rank: np.ndarray) -> None:
        """Eq. 1 for the best ``len(rank)`` sparrows: with one warning value ``R2`` per
        iteration, :meth:`_safe_move` if ``R2 < ST``, else :meth:`_alarm_move`."""
        n_p = rank.shape[0]
        if self.rng.random() < self.params["safety"]:
            cand = self._safe_move(X[:n_p], rank)
        else:
            cand = self._alarm_move(X[:n_p])
        self._greedy(X, F, np.arange(n_p), cand)

    def _safe_move(self, X: np.ndarray, rank: np.ndarray) -> np.ndarray:
        """No danger: ``x exp(-i / (alpha iter_max))``, ``alpha ~ U(0, 1]`` per producer."""
        alpha = 1.0 - self.rng.random((X.shape[0], 1))  # in (0, 1]
        return X * np.exp(-rank / (alpha * self.iters))

    def _alarm_move(self, X: np.ndarray) -> np.ndarray:
        """Danger: ``x + Q L`` (``Q ~ N(0, 1)`` per producer, ``L`` a row of ones)."""
        return X + self.rng.standard_normal((X.shape[0], 1))

    # -- the followers, eq. 2 -------------------------------------------------------------

    def _followers(self, X: np.ndarray, F: np.ndarray, rank: np.ndarray, n_p: int,
                   x_worst: np.ndarray) -> None:  # fmt: skip
        """Eq. 2 for the sparrows after the ``n_p`` producers: those :meth:`_flies_off` picks
        fly off, ``Q exp((x_worst - x) / i^2)``; the others join the best position ``x_P``
        after the producer phase, ``x_P + |x - x_P| A+ L``."""
        n, d = X.shape
        fol = np.arange(n_p, n)
        x_p = X[np.argmin(F)]
        Q = self.rng.standard_normal((fol.size, 1))
        with np.errstate(over="ignore"):
            away = Q * np.exp((x_worst - X[fol]) / rank[fol] ** 2)
        A = self.rng.choice([-1.0, 1.0], (fol.size, d))
        join = x_p + (np.abs(X[fol] - x_p) * A).sum(axis=1, keepdims=True) / d
        self._greedy(X, F, fol, np.where(self._flies_off(rank[fol], n), away, join))

    def _flies_off(self, rank: np.ndarray, n: int) -> np.ndarray:
        """The followers that find no food: rank ``i > n/2``."""
        return rank > n / 2

    # -- the scouts, eq. 3 ----------------------------------------------------------------

    def _scouts(self, X: np.ndarray, F: np.ndarray, worst: tuple[np.ndarray, float]) -> None:
        """Eq. 3 for the sparrows :meth:`_scouts_of` picks: those :meth:`_to_best` picks move
        to ``x_best + beta |x - x_best|``, the others escape, ``x + K |x - x_worst| / ((f -
        f_w) + zeta)`` with ``K ~ U(-1, 1)`` per scout."""
        x_worst, f_worst = worst
        sc = self._scouts_of(F)
        edge = self._to_best(F[sc])
        beta = self._beta(sc.size, X.shape[1])
        K = self.rng.uniform(-1.0, 1.0, (sc.size, 1))
        to_best = self.best_x + beta * np.abs(X[sc] - self.best_x)
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            escape = X[sc] + K * np.abs(X[sc] - x_worst) / ((F[sc] - f_worst)[:, None]
                                                            + self.params["zeta"])  # fmt: skip
        self._greedy(X, F, sc, np.where(edge, to_best, escape))

    def _scouts_of(self, F: np.ndarray) -> np.ndarray:
        """The scouts: a share ``scouts`` of the sparrows, drawn at random."""
        n = F.size
        return self.rng.choice(n, min(n, max(1, round(self.params["scouts"] * n))), replace=False)

    def _to_best(self, f: np.ndarray) -> np.ndarray:
        """The scouts at the edge of the population, ``f > f_g``, as a column."""
        return (f > self.best_f)[:, None]

    def _beta(self, n: int, d: int) -> np.ndarray:
        """The step control ``beta ~ N(0, 1)``, per coordinate as Xue & Shen's code draws it."""
        return self.rng.standard_normal((n, d))

    def _greedy(self, X: np.ndarray, F: np.ndarray, idx: np.ndarray, cand: np.ndarray) -> None:
        """Clip and evaluate ``cand``; sparrows ``idx`` keep the candidates that are better.

        Overflowing steps are clipped to the bound; an undefined one (``0 * inf``) stays put.
        """
        cand = self.clip(np.where(np.isnan(cand), X[idx], cand))
        f = self.evaluate(cand)
        better = f < F[idx]
        X[idx[better]], F[idx[better]] = cand[better], f[better]
