"""Chaotic maps for population initialisation.

* circle map, IWSO paper eq. 7: ``w_{i+1} = mod(w_i + 0.2 - 0.5/(2 pi) sin(2 pi w_i), 1)``;
* cubic map, ISSA paper eq. 4: ``c_{n+1} = rho c_n (1 - c_n^2)`` with ``rho = 2.595``, which
  keeps ``c`` in (0, 1) since ``max rho c (1 - c^2) = rho 2 / (3 sqrt 3) = 0.9989``.

How an ``(n, d)`` population gets distinct values (our reading; the papers do not say): every
dimension ``j`` is its own chain, started at a value ``x0_j`` drawn from the optimizer's seeded
generator, and the chain is iterated along the individuals, so individual ``i`` holds the
``(i + 1)``-th iterate. One chain reshaped row-major would correlate consecutive dimensions of an
individual, and the ISSA paper's single empirical start ``c0 = 0.315`` would make every run's
initial population identical whatever the seed; ``x0`` can still be given explicitly. The unit
values are mapped to the box by ISSA eq. 5: ``x = lower + (upper - lower) c``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

CUBIC_RHO = 2.595
# start values are kept off the maps' degenerate points (0 is a fixed point of both maps)
_START_LOW, _START_HIGH = 0.01, 0.99


def circle_step(w: np.ndarray) -> np.ndarray:
    """One step of the circle map (IWSO eq. 7)."""
    return np.mod(w + 0.2 - 0.5 / (2 * np.pi) * np.sin(2 * np.pi * w), 1.0)


def cubic_step(c: np.ndarray, rho: float = CUBIC_RHO) -> np.ndarray:
    """One step of the cubic map (ISSA eq. 4)."""
    return rho * c * (1.0 - c * c)


def chain(step: Callable[[np.ndarray], np.ndarray], x0, n: int) -> np.ndarray:
    """The ``n`` iterates after ``x0`` (shape ``(d,)``) as an ``(n, d)`` array."""
    x = np.atleast_1d(np.asarray(x0, float))
    out = np.empty((n, x.size))
    for i in range(n):
        x = step(x)
        out[i] = x
    return out


def chaotic_population(
    step: Callable[[np.ndarray], np.ndarray],
    n: int,
    lower: np.ndarray,
    upper: np.ndarray,
    rng: np.random.Generator,
    x0=None,
) -> np.ndarray:
    """An ``(n, d)`` population in the box from one chain per dimension (ISSA eq. 5 mapping).

    ``x0`` (shape ``(d,)``) defaults to values drawn uniformly in [0.01, 0.99] from ``rng``.
    """
    lower = np.asarray(lower, float)
    upper = np.asarray(upper, float)
    if x0 is None:
        x0 = rng.uniform(_START_LOW, _START_HIGH, lower.size)
    unit = chain(step, np.broadcast_to(np.asarray(x0, float), lower.shape), n)
    return lower + (upper - lower) * unit
