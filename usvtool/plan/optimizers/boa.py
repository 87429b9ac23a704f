"""Butterfly Optimization Algorithm (Arora & Singh 2019, Soft Computing 23, 715-734).

Fragrance, eq. 1: ``f_i = c I_i^a`` with sensory modality ``c = 0.01`` at the start, power
exponent ``a = 0.1`` and stimulus intensity ``I_i`` the butterfly's cost; we use ``|cost|`` so
that negative costs (F8) give a real fragrance. After each iteration ``c`` grows as in the
authors' reference code, ``c <- c + c_growth / (c T)`` with ``c_growth = 0.025`` (to about 0.22
at the end); the paper states ``c = 0.01``, and kept constant (``c_growth = 0``) it moves each
butterfly about 2 % of the way per iteration, too slowly to converge. With switch probability
``p = 0.8`` per butterfly:

* global search, eq. 2: ``x + (r^2 g* - x) f_i``;
* local search, eq. 3: ``x + (eps^2 x_j - x_k) f_i`` with ``j != k`` random butterflies,

``r, eps ~ U(0, 1)`` scalars per butterfly (reference code), ``g*`` the best position so far.
New positions are clipped to the box and kept if not worse (greedy, reference code). All
butterflies move at once (the reference code updates them one by one). The global move
heads for ``r^2 g*``, a point scaled towards the coordinate origin.
"""

from __future__ import annotations

import numpy as np

from usvtool.plan.optimizers.base import NON_NEGATIVE, POSITIVE, PROBABILITY, Optimizer, Param


class BOA(Optimizer):
    name = "boa"
    # c divides the growth step and stays > 0 as it grows; p is a switch probability
    parameters = {
        "c": Param(0.01, "the sensory modality at the start (eq. 1)", POSITIVE),
        "a": Param(0.1, "the power exponent (eq. 1)"),
        "p": Param(0.8, "the switch probability, global against local search", PROBABILITY),
        "c_growth": Param(0.025, "c's growth per iteration (0: a constant c)", NON_NEGATIVE),
    }

    def _run(self) -> None:
        rng, prm = self.rng, self.params
        n = self.pop
        X = self.uniform()
        F = self.evaluate(X)
        c = prm["c"]
        for t in range(self.iters):
            frag = (c * np.abs(F) ** prm["a"])[:, None]
            r, eps, switch = rng.random((3, n, 1))
            j = rng.integers(0, n, n)
            k = (j + rng.integers(1, n, n)) % n  # k != j
            glob = X + (r * r * self.best_x - X) * frag
            local = X + (eps * eps * X[j] - X[k]) * frag
            cand = self.clip(np.where(switch < prm["p"], glob, local))
            f = self.evaluate(cand)
            keep = f <= F
            X, F = np.where(keep[:, None], cand, X), np.where(keep, f, F)
            c += prm["c_growth"] / (c * self.iters)
            self.record(t)
