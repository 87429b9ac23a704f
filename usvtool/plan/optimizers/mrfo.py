"""Manta Ray Foraging Optimization (Zhao, Zhang & Wang 2020, Eng. Appl. Artif. Intell. 87).

Each iteration ``t`` (1-based, of ``T``), every manta ray chooses with probability 1/2:

* chain foraging, eqs. 1-2: ``x_i + r (x_{i-1} - x_i) + alpha (x_best - x_i)`` with
  ``alpha = 2 r' sqrt(|log r'|)`` (``r, r'`` per coordinate, ``x_0`` read as ``x_best``);
* cyclone foraging, eqs. 4-7: ``x_ref + r (x_{i-1} - x_i) + beta (x_ref - x_i)`` with
  ``beta = 2 exp(r1 (T - t + 1) / T) sin(2 pi r1)``; ``x_ref`` is ``x_best`` if ``t / T > rand``
  (exploitation) and otherwise a random point of the box (exploration), and ``x_0 = x_ref``.

The new positions are evaluated and kept if better (greedy selection, reference code); then
somersault foraging, eq. 8: ``x_i + S (r2 x_best - r3 x_i)`` with ``S = 2``, evaluated and
kept if better. ``x_{i-1}`` is the previous ray's position at the start of the phase (all rays
move at once). Positions are clipped to the box; the reference code instead redraws violating
coordinates at random. Two evaluations of the population per iteration.
"""

from __future__ import annotations

import numpy as np

from usvtool.plan.optimizers.base import POSITIVE, Optimizer, Param


class MRFO(Optimizer):
    name = "mrfo"
    parameters = {"somersault": Param(2.0, "the somersault factor S (eq. 8)", POSITIVE)}

    def _run(self) -> None:
        rng = self.rng
        n, d, T = self.pop, self.dim, self.iters
        X = self.uniform()
        F = self.evaluate(X)
        for t in range(1, T + 1):
            best = self.best_x
            r, r_alpha = rng.random((2, n, d))
            r_alpha = 1.0 - r_alpha  # in (0, 1] so that log is finite
            alpha = 2.0 * r_alpha * np.sqrt(np.abs(np.log(r_alpha)))
            prev = np.roll(X, 1, axis=0)
            prev[0] = best
            chain = X + r * (prev - X) + alpha * (best - X)

            r1 = rng.random((n, 1))
            beta = 2.0 * np.exp(r1 * (T - t + 1) / T) * np.sin(2.0 * np.pi * r1)
            exploit = (t / T > rng.random(n))[:, None]
            ref = np.where(exploit, best, self.uniform(n))
            prev_c = np.roll(X, 1, axis=0)
            prev_c[0] = ref[0]
            r_c = rng.random((n, d))
            cyclone = ref + r_c * (prev_c - X) + beta * (ref - X)

            cyclonic = (rng.random(n) < 0.5)[:, None]
            X, F = self._greedy(X, F, np.where(cyclonic, cyclone, chain))

            r2, r3 = rng.random((2, n, 1))
            X, F = self._greedy(X, F, X + self.params["somersault"] * (r2 * self.best_x - r3 * X))
            self.record(t - 1)

    def _greedy(self, X, F, cand) -> tuple[np.ndarray, np.ndarray]:
        cand = self.clip(cand)
        f = self.evaluate(cand)
        better = f < F
        return np.where(better[:, None], cand, X), np.where(better, f, F)
