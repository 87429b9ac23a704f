"""SSA with mealpy's bounds rule: a coordinate that leaves the box is redrawn uniformly in it.

Everything else is :class:`~usvtool.plan.optimizers.ssa.SSA` (the ISSA paper's eqs. 1-3, as
Xue & Shen code them). Neither paper says what happens at the bounds; Xue & Shen's reference
code clips (their ``Bounds``), as :class:`SSA` does. mealpy 3.0.3's ``DevSSA.amend_solution``
(inherited by ``OriginalSSA``) redraws each out-of-bounds coordinate from ``U(lower, upper)``
instead, keeping the others. On the path problem the fixed-size steps of eq. 2's fly-off
``Q exp((x_worst - x) / i^2)`` (``|Q|`` of order 1 against a box under one start-goal distance
wide), of eq. 1's ``x + Q L`` and of eq. 3 leave the box often: clipped, they land on its faces,
routes along the map's edges that the greedy selection rejects; redrawn, they are partial random
restarts that keep the search exploring. On env1 this rule alone is mealpy's advantage (runs
within 5 % of the optimum: 24 -> 66 of 100 seeds); on env2 it does not help
(docs/optimizers.md, "SSA against mealpy").
"""

from __future__ import annotations

import numpy as np

from usvtool.plan.optimizers.ssa import SSA


class SSARedraw(SSA):
    name = "ssa-redraw"

    def clip(self, X: np.ndarray) -> np.ndarray:
        """``X`` with every coordinate outside the box redrawn uniformly inside it.

        Random numbers are drawn only for those coordinates, so a run in which no candidate
        leaves the box is the very run of :class:`SSA` with the same seed.
        """
        out = (X < self.lower) | (X > self.upper)
        if not out.any():
            return X
        rows, cols = np.nonzero(out)
        X = X.copy()
        span = self.upper[cols] - self.lower[cols]
        X[rows, cols] = self.lower[cols] + self.rng.random(rows.size) * span
        return X
