"""``de``: differential evolution, DE/rand/1/bin (Storn and Price, "Differential evolution: a
simple and efficient heuristic for global optimization over continuous spaces", J. Global
Optimization 11, 1997): each iteration every individual gets a trial vector mixed, gene by gene
with probability ``cr`` (at least one gene), from the mutant ``a + f (b - c)`` of three other
random individuals, and keeps it when it is no worse."""

from __future__ import annotations

import numpy as np

from usvtool.plan.optimizers.base import PROBABILITY, Optimizer, Range


class DifferentialEvolution(Optimizer):
    name = "de"
    defaults = {"f": 0.5, "cr": 0.9}
    ranges = {"f": Range(0.0, 2.0, open_low=True), "cr": PROBABILITY}

    def _run(self) -> None:
        f, cr, n, rng = self.params["f"], self.params["cr"], self.pop, self.rng
        x = self.uniform()
        cost = self.evaluate(x)
        for t in range(self.iters):
            # three distinct others per individual: a random permutation's shifts of each row
            others = (np.arange(n)[:, None] + rng.integers(1, n, (n, 3))) % n
            a, b, c = x[others[:, 0]], x[others[:, 1]], x[others[:, 2]]
            cross = rng.random(x.shape) < cr
            cross[np.arange(n), rng.integers(0, self.dim, n)] = True
            trial = self.clip(np.where(cross, a + f * (b - c), x))
            trial_cost = self.evaluate(trial)
            better = trial_cost <= cost
            x[better], cost[better] = trial[better], trial_cost[better]
            self.record(t)
