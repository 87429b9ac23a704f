"""Whale Optimization Algorithm (Mirjalili & Lewis 2016, Adv. Eng. Softw. 95, 51-67).

Per whale and iteration: ``A = 2 a r1 - a``, ``C = 2 r2`` (scalars, as in the reference code),
``a`` decreasing linearly from 2 to 0 (eq. 2.3), and ``p ~ U(0, 1)``:

* ``p < 0.5`` and ``|A| < 1``, encircling (eqs. 2.1-2.2): ``x <- x* - A |C x* - x|``;
* ``p < 0.5`` and ``|A| >= 1``, search for prey (eqs. 2.7-2.8): the same about a random whale;
* ``p >= 0.5``, bubble-net spiral (eq. 2.5): ``x <- |x* - x| e^(b l) cos(2 pi l) + x*`` with
  ``b = 1`` and ``l = (a2 - 1) rand + 1``, ``a2`` decreasing linearly from -1 to -2 (reference
  code), so ``l`` is in [-2, 1] late and [-1, 1] early.

``x*`` is the best position found so far. All whales move at once from the same population
(the reference code updates in place, whale after whale). Positions are clipped to the box.
"""

from __future__ import annotations

import numpy as np

from usvtool.plan.optimizers.base import Optimizer, Param


class WOA(Optimizer):
    name = "woa"
    parameters = {"b": Param(1.0, "the logarithmic spiral's shape")}

    def _run(self) -> None:
        rng = self.rng
        X = self.uniform()
        self.evaluate(X)
        n = self.pop
        for t in range(self.iters):
            a = 2.0 * (1.0 - t / self.iters)
            a2 = -1.0 - t / self.iters
            r1, r2, p, u = rng.random((4, n, 1))
            A = 2.0 * a * r1 - a
            C = 2.0 * r2
            target = np.where(np.abs(A) < 1.0, self.best_x, X[rng.integers(0, n, n)])
            encircle = target - A * np.abs(C * target - X)
            l = (a2 - 1.0) * u + 1.0  # noqa: E741 (the paper's name)
            spiral = (
                np.abs(self.best_x - X) * np.exp(self.params["b"] * l) * np.cos(2.0 * np.pi * l)
                + self.best_x
            )
            X = self.clip(np.where(p < 0.5, encircle, spiral))
            self.evaluate(X)
            self.record(t)
