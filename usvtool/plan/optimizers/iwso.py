"""Improved White Shark Optimizer (Liang & Liu 2023, J. Mar. Sci. Eng. 11, 1386, section 2.2).

WSO (see :mod:`.wso`) with three changes:

* initialisation, eq. 7 and text: a circle-map population (:mod:`.chaotic`) and a uniformly
  random population, both evaluated; the best ``pop`` of the ``2 pop`` form the first
  population;
* adaptive weight factor, eqs. 8-9: ``alpha_i = 0.2 + 1 / (0.6 + exp(-(f_i / mu')^k))`` where
  ``f_i`` is shark ``i``'s current cost, ``mu'`` the best cost of the first population and
  ``k`` the iteration (1-based). The converted eq. 8 reads ``e^{(-f/mu')^k}``; a negative base
  raised to ``k`` would flip sign every iteration, so we read the minus sign as outside the
  power. The ratio is taken on magnitudes ``|f_i| / |mu'|`` so it is defined for any sign of
  cost. Hence ``alpha`` lies in [0.825, 1.867]: about 1.867 for sharks worse than ``mu'``
  (ratio > 1) and 0.825 for better ones as ``k`` grows. Eq. 9 replaces eq. 4 for every shark
  (Algorithm 1 loops over all ``P``): ``alpha w ~xor w0 + u a + l b`` if ``rand < mv``, else
  ``(1 - alpha) w + v / f``. Both branches scale positions towards the coordinate origin, so
  IWSO (like SSA) favours problems whose optimum is at the origin;
* simplex, eqs. 10-15: after each evaluation the best shark ``x_g`` and the second best ``x_b``
  give the centroid ``x_c = (x_g + x_b) / 2``; every other shark is the abandoned vertex
  ``x_s`` of its own Nelder-Mead move, all at once: reflection ``x_r = (1 + delta) x_c -
  delta x_s`` (eq. 11); if ``f(x_r) < f(x_g)`` expansion ``x_e = (1 - chi) x_c + chi x_r``
  (eq. 12, keep the better of ``x_e``, ``x_r``); else if ``f(x_r) < f(x_s)`` outside
  contraction ``x_oc = x_c + phi (x_r - x_c)`` (eq. 13, the better of ``x_oc``, ``x_r``); else
  inside contraction ``x_ic = x_c - phi (x_r - x_c)`` (eq. 14), kept if better than ``x_s``,
  otherwise shrinkage towards the best, ``x_g + xi (x_s - x_g)`` (eq. 15). The paper gives only
  ``delta = 1``; ``chi = 2``, ``phi = xi = 0.5`` are Nelder & Mead's values.

Every point is clipped to the box and evaluated, and all evaluations count: ``2 pop`` for the
start, then about ``3 pop`` per iteration (shark moves, reflections, second points, shrinks).
"""

from __future__ import annotations

import numpy as np

from usvtool.plan.optimizers.base import POSITIVE, Param, Range
from usvtool.plan.optimizers.chaotic import chaotic_population, circle_step
from usvtool.plan.optimizers.wso import WSO


class IWSO(WSO):
    name = "iwso"
    # Nelder & Mead's conditions: reflection > 0, expansion > 1, contraction and shrinkage
    # in (0, 1)
    parameters = {
        **WSO.parameters,
        "delta": Param(1.0, "Nelder-Mead's reflection", POSITIVE),
        "chi": Param(2.0, "Nelder-Mead's expansion", Range(1.0, open_low=True)),
        "phi": Param(0.5, "Nelder-Mead's contraction", Range(0.0, 1.0, True, True)),
        "xi": Param(0.5, "Nelder-Mead's shrinkage", Range(0.0, 1.0, True, True)),
    }

    def _initial(self) -> tuple[np.ndarray, np.ndarray]:
        """Eq. 7: circle-map and random populations together; keep the best ``pop``."""
        chaos = chaotic_population(circle_step, self.pop, self.lower, self.upper, self.rng)
        both = np.vstack([chaos, self.uniform()])
        F = self.evaluate(both)
        keep = np.argsort(F, kind="stable")[: self.pop]
        self._mu_prime = max(abs(float(F[keep[0]])), np.finfo(float).tiny)
        return both[keep], F[keep]

    def _move(self, W, V, F, freq: float, mv: float, k: int) -> np.ndarray:
        """Eqs. 8-9: eq. 4 with positions weighted by the adaptive factor ``alpha``."""
        with np.errstate(over="ignore"):
            ratio = np.power(np.abs(F) / self._mu_prime, k)
        alpha = (0.2 + 1.0 / (0.6 + np.exp(-ratio)))[:, None]
        return self._wavy(W, alpha * W, (1.0 - alpha) * W + V / freq, mv)

    def _refine(self, W: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Eqs. 10-15: one vectorised Nelder-Mead move per shark other than the best two."""
        if W.shape[0] < 3:
            return W, F
        p = self.params
        order = np.argsort(F, kind="stable")
        x_g = W[order[0]]
        x_c = (x_g + W[order[1]]) / 2.0
        s = order[2:]
        x_s, f_s = W[s], F[s]
        x_r = self.clip((1.0 + p["delta"]) * x_c - p["delta"] * x_s)
        f_r = self.evaluate(x_r)
        expand = f_r < F[order[0]]
        outside = ~expand & (f_r < f_s)
        inside = ~expand & ~outside
        step = x_r - x_c
        second = np.where(
            expand[:, None],
            (1.0 - p["chi"]) * x_c + p["chi"] * x_r,
            np.where(outside[:, None], x_c + p["phi"] * step, x_c - p["phi"] * step),
        )
        second = self.clip(second)
        f_2 = self.evaluate(second)
        new_x, new_f = x_r.copy(), f_r.copy()
        take = np.where(inside, f_2 < f_s, np.where(expand, f_2 <= f_r, f_2 < f_r))
        new_x[take], new_f[take] = second[take], f_2[take]
        shrink = inside & ~take
        if shrink.any():
            x_shrunk = self.clip(x_g + p["xi"] * (x_s[shrink] - x_g))
            new_x[shrink], new_f[shrink] = x_shrunk, self.evaluate(x_shrunk)
        W, F = W.copy(), F.copy()
        W[s], F[s] = new_x, new_f
        return W, F
