"""Improved Sparrow Search Algorithm (Liu, Zhang, Ma & Pan 2023, J. Mar. Sci. Eng. 11, 2292,
section 2, Algorithm 1).

SSA (see :mod:`.ssa`) with:

* cubic chaotic initialisation, eqs. 4-5 (:mod:`.chaotic`, ``rho = 2.595``);
* a stagnation test, eqs. 6-7: ``sigma = sqrt(sum (f_i - f_a)^2 / f)`` with ``f_a`` the mean
  cost and ``f = max |f_i - f_a|`` if that exceeds 1, else 1. At the start of each iteration
  ``sigma`` is computed on the current costs; if it changed by less than ``1e-3`` since the
  previous iteration the population is taken as stuck in a local optimum;
* then, instead of the SSA phases (Algorithm 1's if/else), a Gaussian random walk of the best
  sparrow, eq. 8: ``pop`` new sparrows ``N(x_best, |(1 - (t / iter_max)^2) (x_best - x_r)|)``,
  ``x_r`` a random sparrow for each, so the spread shrinks as ``t`` grows. Eq. 8 writes the walk
  for ``X_i``, the text applies it to the best individual and calls the result "the perturbed
  new sparrow population": we read it as ``pop`` walkers around the best, each competing
  greedily with the sparrow of the same index, which keeps the ``pop`` evaluations of an
  iteration.
"""

from __future__ import annotations

import numpy as np

from usvtool.plan.optimizers.base import NON_NEGATIVE, Param
from usvtool.plan.optimizers.chaotic import chaotic_population, cubic_step
from usvtool.plan.optimizers.ssa import SSA


def fitness_spread(F: np.ndarray) -> float:
    """Eqs. 6-7: the controlled standard deviation of the costs."""
    dev = F - F.mean()
    top = float(np.abs(dev).max())
    return float(np.sqrt(np.sum(dev * dev) / (top if top > 1.0 else 1.0)))


class ISSA(SSA):
    name = "issa"
    parameters = {
        **SSA.parameters,
        "stagnation": Param(
            1e-3, "the bound on |change of sigma| under which the search stagnates", NON_NEGATIVE
        ),
    }

    def _initial(self) -> np.ndarray:
        return chaotic_population(cubic_step, self.pop, self.lower, self.upper, self.rng)

    def _run(self) -> None:
        self._sigma = None
        super()._run()

    def _step(self, X: np.ndarray, F: np.ndarray, t: int) -> tuple[np.ndarray, np.ndarray]:
        sigma = fitness_spread(F)
        stuck = self._sigma is not None and abs(sigma - self._sigma) < self.params["stagnation"]
        self._sigma = sigma
        if not stuck:
            return super()._step(X, F, t)
        n = X.shape[0]
        best = X[np.argmin(F)]
        partner = X[self.rng.integers(0, n, n)]
        scale = np.abs((1.0 - (t / self.iters) ** 2) * (best - partner))
        X, F = X.copy(), F.copy()
        self._greedy(X, F, np.arange(n), self.rng.normal(best, scale))
        return X, F
