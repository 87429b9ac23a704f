"""Whether NumPy's float64 math is the C library's on this machine, and the comparison of a
compiled kernel with its NumPy reference that follows from it.

numba's kernels (and Python's ``math``) call the C library's ``atan2``, ``pow``, ``exp``, ``sin``,
``cos``; NumPy calls the same functions
unless it dispatches to its own SIMD implementations, as it does on AVX-512 machines
(``numpy.show_runtime()``: ``X86_V4``), whose results differ from the C library's by up to an
ulp. Where NumPy's results are the C library's, a kernel must give its reference's bits; where
they are not, the same values to within :data:`ULPS` units in the last place of the array's
largest value (a result near zero that is a difference of larger terms, a speed less its loss,
keeps their absolute error, not its own ulps; the kernels' tests see at most 2 on an AVX-512
EPYC).
"""

from __future__ import annotations

import math

import numpy as np


def numpy_is_libm() -> bool:
    """NumPy's float64 arctan2, power, exp, sin and cos give the C library's bits (Python's
    ``math``) on 10 000 seeded arguments."""
    rng = np.random.default_rng(0)
    a, b = rng.uniform(-5, 5, 10_000), rng.uniform(-5, 5, 10_000)
    checks = ((np.arctan2(a, b), map(math.atan2, a, b)),
              (np.abs(a) ** b, (abs(x) ** y for x, y in zip(a, b, strict=True))),
              (np.exp(a), map(math.exp, a)), (np.sin(a), map(math.sin, a)),
              (np.cos(a), map(math.cos, a)))  # fmt: skip
    return all(np.array_equal(got, np.fromiter(want, float)) for got, want in checks)


#: Units in the last place (of the array's largest value) a kernel may differ from its NumPy
#: reference: 0 where NumPy is the C library (the same bits), else 4.
ULPS = 0 if numpy_is_libm() else 4


def assert_close_bits(got, want, what: str = "") -> None:
    """``got`` and ``want`` of one shape, float for float the same bits (-0.0 not 0.0) when
    :data:`ULPS` is 0, else within ULPS ulps of the largest finite ``|want|``, NaN where the
    other is NaN, infinities equal."""
    got, want = np.asarray(got, float), np.asarray(want, float)
    assert got.shape == want.shape, (what, got.shape, want.shape)
    if ULPS == 0:
        differ = np.flatnonzero(got.view(np.int64) != want.view(np.int64))
        assert differ.size == 0, (what, differ[:5], got.ravel()[differ[:5]],
                                  want.ravel()[differ[:5]])  # fmt: skip
        return
    assert np.array_equal(np.isnan(got), np.isnan(want)), what
    finite = np.isfinite(want)
    assert np.array_equal(got[~finite & ~np.isnan(want)], want[~finite & ~np.isnan(want)]), what
    if finite.any():
        tolerance = ULPS * np.spacing(np.abs(want[finite]).max())
        worst = np.abs(got[finite] - want[finite]).max()
        assert worst <= tolerance, (what, worst, tolerance)
