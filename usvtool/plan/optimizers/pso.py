"""Particle Swarm Optimization (Kennedy & Eberhart 1995; inertia weight of Shi & Eberhart 1998).

``v <- w v + c1 r1 (p_best - x) + c2 r2 (g_best - x)``, ``x <- x + v``, with ``r1, r2 ~ U(0, 1)``
per coordinate, the inertia ``w`` decreasing linearly from ``w_start`` to ``w_end`` over the
iterations, velocities clamped to ``+-vmax (upper - lower)`` and positions clipped to the box.
Velocities start at zero.

* ``pso``: the standard setting, ``w`` 0.9 -> 0.4, ``c1 = c2 = 2.0``, ``vmax = 0.2``;
* ``pso-issa``: the ISSA paper's Table 2, ``c1 = c2 = 2.5`` and a constant ``w = 1``. The paper
  names no velocity limit, but with ``w = 1`` and ``c1 + c2 = 5`` the velocities of unclamped
  PSO grow without bound, so we keep the same 20 % clamp as ``pso``.
"""

from __future__ import annotations

import numpy as np

from usvtool.plan.optimizers.base import NON_NEGATIVE, POSITIVE, Optimizer, Param


class PSO(Optimizer):
    name = "pso"
    # acceleration weights of the pulls (r1, r2 >= 0); vmax a share of the box's span
    parameters = {
        "w_start": Param(0.9, "the inertia weight at the start"),
        "w_end": Param(0.4, "the inertia weight at the end"),
        "c1": Param(2.0, "the pull toward the particle's own best", NON_NEGATIVE),
        "c2": Param(2.0, "the pull toward the swarm's best", NON_NEGATIVE),
        "vmax": Param(0.2, "the largest speed, a share of the box's span", POSITIVE),
    }

    def _run(self) -> None:
        p = self.params
        vmax = p["vmax"] * (self.upper - self.lower)
        X = self.uniform()
        F = self.evaluate(X)
        V = np.zeros_like(X)
        P, PF = X.copy(), F.copy()
        for t in range(self.iters):
            w = p["w_start"] + (p["w_end"] - p["w_start"]) * t / max(self.iters - 1, 1)
            r1, r2 = self.rng.random((2, *X.shape))
            V = w * V + p["c1"] * r1 * (P - X) + p["c2"] * r2 * (self.best_x - X)
            V = np.clip(V, -vmax, vmax)
            X = self.clip(X + V)
            F = self.evaluate(X)
            better = F < PF
            P[better], PF[better] = X[better], F[better]
            self.record(t)


class PSOISSA(PSO):
    name = "pso-issa"
    parameters = {"w_start": 1.0, "w_end": 1.0, "c1": 2.5, "c2": 2.5}  # PSO's, other defaults
