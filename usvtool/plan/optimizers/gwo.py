"""Grey Wolf Optimizer (Mirjalili, Mirjalili & Lewis 2014, Adv. Eng. Softw. 69, 46-61).

Leaders alpha, beta, delta are the three best positions found so far. Each wolf moves to the
mean of three guided points (eqs. 3.3-3.7):
``D_l = |C_l x_l - x|``, ``X_l = x_l - A_l D_l``, ``x <- (X_alpha + X_beta + X_delta) / 3`` with
``A = 2 a r1 - a``, ``C = 2 r2`` (``r1, r2 ~ U(0, 1)`` per coordinate and leader) and ``a``
decreasing linearly from 2 to 0 over the iterations (eqs. 3.3-3.4). Positions are clipped to
the box. The reference code overwrites a leader without demoting it to the rank below; we keep
the paper's definition (the three best solutions seen so far).
"""

from __future__ import annotations

import numpy as np

from usvtool.plan.optimizers.base import NON_NEGATIVE, Optimizer, Param


class GWO(Optimizer):
    name = "gwo"
    # a decreases from a_start to 0 (eq. 3.3)
    parameters = {"a_start": Param(2.0, "a at the start, decreasing to 0 (eq. 3.3)", NON_NEGATIVE)}

    def _run(self) -> None:
        X = self.uniform()
        F = self.evaluate(X)
        leaders, leader_f = self._leaders(X, F, X[:0], F[:0])
        for t in range(self.iters):
            a = self.params["a_start"] * (1.0 - t / self.iters)
            r1, r2 = self.rng.random((2, 3, *X.shape))
            A = 2.0 * a * r1 - a
            C = 2.0 * r2
            L = leaders[:, None, :]
            X = self.clip(np.mean(L - A * np.abs(C * L - X), axis=0))
            F = self.evaluate(X)
            leaders, leader_f = self._leaders(X, F, leaders, leader_f)
            self.record(t)

    @staticmethod
    def _leaders(X, F, leaders, leader_f) -> tuple[np.ndarray, np.ndarray]:
        """The three best of the old leaders and the new wolves (fewer if the pack is smaller)."""
        allx = np.vstack([leaders, X])
        allf = np.concatenate([leader_f, F])
        top = np.argsort(allf, kind="stable")[:3]
        if top.size < 3:  # a pack of two: the best wolf doubles as delta
            top = np.resize(top, 3)
        return allx[top], allf[top]
