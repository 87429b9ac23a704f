"""Compiled kernels of the exact collision check (:mod:`usvtool.collision`), with numba.

Written by hand because the check is the project's own definition (closed squares enlarged by
``EPS``, the filter's clearance bound, the lengths inside squares grown by ``pad``) and no
library computes it; compiled because its calls are small and many: the path problem checks 50
routes of a few segments per call, about 16 intervals left by the filter, and a vectorised NumPy
version spent its time on some 60 array calls' overheads, not on arithmetic. The module docstring
of :mod:`usvtool.collision` gives the method; the names here follow it. Imported lazily by
:class:`usvtool.collision.SegmentChecker` when it is made (numba's import costs about 0.3 s)
and by the exact planners (:mod:`usvtool.plan.gridsearch`), whose line of sight is :func:`touches`.

Tables (built by :class:`~usvtool.collision.SegmentChecker`, raveled, rows of ``stride`` = width
+ 2): ``prefix[(r + 1) * stride + c + 1]`` is the number of blocked cells of column ``c`` in
rows ``< r``; ``below`` and ``bands`` (1.0 or 0.0) the grown squares' tables
(:attr:`usvtool.collision.SegmentChecker._grown`, only read when ``d > 0``).

numba's cache keys a compiled function on its own file only: the cached kernels of
:mod:`usvtool.plan.gridsearch` (and of benchmarks/bench_fewest_links.py) that call
:func:`touches`, and those of :mod:`usvtool.plan.cost_kernels` that call :func:`segments`, keep
the old version after an edit of this file alone. After changing it, remove
``usvtool/plan/__pycache__/gridsearch.*.nb*`` and ``cost_kernels.*.nb*`` (or touch those
files); a fresh checkout or install compiles everything anew.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numba import types as nt

from usvtool.kernel_views import borrowed
from usvtool.lazy_kernels import declared

EPS = 1e-9  # usvtool.collision.EPS (not imported: that module imports this one lazily)
# Signatures given (:func:`usvtool.lazy_kernels.declared`): each compiled, or loaded from
# numba's cache, at its first call, or by the checker when it is made (before any timing): a
# plan loads the one or two it calls, not all four at import (0.18 s of CPU a process).
_OPTIONS = {"cache": True, "nogil": True}
_B, _F, _I = nt.boolean, nt.float64, nt.int64
_TABLES = (nt.int32[::1], _I, _F[::1], _F[:, ::1])  # prefix, stride, below, bands
_RESULTS = nt.Tuple((_B[::1], _F[::1]))


@njit(cache=True, nogil=True, inline="always")
def _grown(f, d, at, prefix, stride, below, bands) -> float:
    """The grown length of a column below ``y = row + f`` (``at`` indexes row, column)."""
    if d > 0:
        return below[at] + (
            bands[0, at] * min(f, d)
            + bands[1, at] * min(max(f - d, 0.0), 1.0 - 2.0 * d)
            + bands[2, at] * max(f - (1.0 - d), 0.0)
        )
    count = prefix[at]
    return count + (prefix[at + stride] - count) * f


@njit(cache=True, nogil=True, inline="always")
def _band(f, d, at, prefix, stride, bands) -> float:
    """Whether the point at ``row + f`` (``at``) lies in a grown square (an open one, if ``d``
    is 0: a point on a row edge does not)."""
    if d > 0:
        if f < d:
            return bands[0, at]
        return bands[2, at] if f > 1 - d else bands[1, at]
    return float(prefix[at + stride] - prefix[at]) if f != 0.0 else 0.0


@njit(cache=True, nogil=True, inline="always")
def _oriented(x0, y0, x1, y1):
    """The segment west to east, with its ``dx`` and slope (0 when ``dx`` is 0)."""
    if x1 < x0:
        x0, y0, x1, y1 = x1, y1, x0, y0
    dx = x1 - x0
    return x0, y0, x1, y1, dx, (y1 - y0) / dx if dx > 0 else 0.0


@njit(cache=True, nogil=True, inline="always")
def _touched(x0, y0, x1, y1, dx, slope, g, prefix, stride) -> bool:
    """Whether the oriented segment touches a blocked square enlarged by ``g``, stopping at the
    first touched column (:func:`strips`)."""
    for c in range(int(math.ceil(x0 - (1 + g))), int(math.floor(x1 + g)) + 1):
        cx = c - x0
        ya = y0 + slope * min(max(cx - g, 0.0), dx)
        yb = y1 - slope * min(max(dx - (1 + g) - cx, 0.0), dx)
        r0 = int(math.ceil(min(ya, yb) - (1 + g)))
        r1 = int(math.floor(max(ya, yb) + g))
        base = c + 1 + stride
        if prefix[(r1 + 1) * stride + base] > prefix[r0 * stride + base]:
            return True
    return False


@declared(nt.Tuple((_B, _F))(_F, _F, _F, _F, _F, _B, *_TABLES), **_OPTIONS)
def strips(x0, y0, x1, y1, d, want_inside, prefix, stride, below, bands) -> tuple[bool, float]:
    """``(touches, inside)`` of one segment, column strip by column strip.

    ``touches``: whether the segment touches a blocked square enlarged by ``g = max(d, EPS)`` on
    every side. The segment is oriented west to east, with slope ``k = dy/dx`` (0 when ``dx =
    0``). In the strip of column ``c`` it spans ``y`` from ``y0 + k·max(c - g - x0, 0)`` to ``y1
    - k·max(x1 - c - 1 - g, 0)``: its enlarged strip clipped to its ends. A north-south segment
    (``k = 0``) thus spans all of ``[y0, y1]``. The rows of that span (the supercover) are tested
    against the running counts. Without ``want_inside`` it stops at the first touched column.

    ``inside`` (0 unless ``want_inside`` and it touches): in the strip ``[c - d, c + 1 + d]`` the
    piece spans ``y_lo … y_hi``; with ``G(y)`` the grown length of the column below ``y``
    (``below`` at ``⌊y⌋`` plus the part of row ``⌊y⌋``'s bands below ``y``; with ``d`` 0 the
    running count plus ``blocked(⌊y⌋) (y - ⌊y⌋)``) its length inside is ``(G(y_hi) - G(y_lo))``
    times the length per unit of ``y`` (``√(1 + k²) / |k|``, 1 if north-south); a level piece
    instead takes its width ``√(1 + k²)`` times the band holding ``y_lo``. A north-south piece
    counts in the strips whose interior holds it.
    """
    g = max(d, EPS)
    x0, y0, x1, y1, dx, slope = _oriented(x0, y0, x1, y1)
    touched = _touched(x0, y0, x1, y1, dx, slope, g, prefix, stride)
    if not (touched and want_inside):
        return touched, 0.0

    # the length inside, over all of the segment's strips
    per_y = math.hypot(1.0, slope) / abs(slope) if slope != 0 else 1.0
    level = math.hypot(1.0, slope)
    total = 0.0
    for c in range(int(math.ceil(x0 - (1 + g))), int(math.floor(x1 + g)) + 1):
        cx = c - x0
        if dx == 0 and not (-1.0 - d < cx < d):
            continue  # a north-south piece outside this strip's interior
        ya = y0 + slope * min(max(cx - d, 0.0), dx)
        yb = y1 - slope * min(max(dx - (1 + d) - cx, 0.0), dx)
        lo, hi = min(ya, yb), max(ya, yb)
        base = c + 1 + stride
        row = math.floor(lo)
        f = lo - row
        at = int(row) * stride + base
        band_lo = _band(f, d, at, prefix, stride, bands)
        if hi - lo <= 1e-12:  # a level piece: its width times its band
            if dx > 0:
                width = max(min(dx, cx + (1.0 + d)) - max(cx - d, 0.0), 0.0)
                total += width * level * band_lo
            continue
        row_hi = math.floor(hi)
        at_hi = int(row_hi) * stride + base
        total += (_grown(hi - row_hi, d, at_hi, prefix, stride, below, bands)
                  - _grown(f, d, at, prefix, stride, below, bands)) * per_y  # fmt: skip
    return True, total


@declared(_B(_TABLES[0], _I, _F, _F, _F, _F), **_OPTIONS)
def touches(prefix: np.ndarray, stride: int, x0: float, y0: float, x1: float, y1: float) -> bool:
    """Whether the segment touches a blocked square enlarged by ``EPS``, stopping at the first
    touched column (the exact planners' line of sight)."""
    x0, y0, x1, y1, dx, slope = _oriented(x0, y0, x1, y1)
    return _touched(x0, y0, x1, y1, dx, slope, EPS, prefix, stride)


@declared(_RESULTS(_F[:, ::1], _F[:, ::1], _F, _B, *_TABLES), **_OPTIONS)
def traverse(a, b, d, want_inside, prefix, stride, below, bands) -> tuple[np.ndarray, ...]:
    """:func:`strips` of each segment ``a[i] → b[i]`` (``(k, 2)`` arrays)."""
    k = a.shape[0]
    hit = np.zeros(k, np.bool_)
    inside = np.zeros(k)
    prefix, below, bands = borrowed(prefix), borrowed(below), borrowed(bands)  # not counted
    for i in range(k):
        touch, within = strips(
            a[i, 0], a[i, 1], b[i, 0], b[i, 1], d, want_inside, prefix, stride, below, bands
        )
        hit[i] = touch
        inside[i] = within
    return hit, inside


@njit(inline="always")  # compiled only into its callers
def segments(
    x, y, length, count, clear, samples, margin, d, want_inside, r, prefix, stride, below, bands,
    hit, inside,
) -> None:  # fmt: skip
    """``hit`` and ``inside`` (written) of the first ``count`` segments of :func:`check` from
    their ``samples`` sample points ``x[i]``, ``y[i]`` and their ``length[i]`` (``r``: scratch,
    at least ``samples`` long).

    The loop over the segments is here, not in the callers: an inlined function's array
    arguments are reference-counted at each call (numba's atomic increments and decrements,
    which its pruning left in the callers' loops), some 45 ns a call with these tables, more
    than the check of a segment the filter passes; so the tables are bound once a batch. The
    callers pass the tables borrowed (:func:`usvtool.kernel_views.borrowed`), so that
    :func:`strips`' calls do not count them either."""
    row = stride - 1
    for i in range(count):
        outside = False  # first whether every sample is in the table, then the look-ups
        for j in range(samples):
            cell = int(y[i, j]) * row + int(x[i, j])  # truncation: coordinates >= 0
            outside |= (cell < 0) | (cell >= clear.size)
        if outside:  # no bounds checks in compiled code otherwise
            raise ValueError("segments must lie inside the grid extent")
        n_in = 0
        for j in range(samples):
            r[j] = clear[int(y[i, j]) * row + int(x[i, j])]
            n_in += r[j] < 0
        if n_in:
            hit[i], inside[i] = True, n_in * length[i] / samples if want_inside else 0.0
            continue
        spacing = length[i] / (samples - 1) + margin
        touched = False
        total = 0.0
        for j in range(samples - 1):
            if r[j] + r[j + 1] <= spacing:
                touch, within = strips(x[i, j], y[i, j], x[i, j + 1], y[i, j + 1], d,
                                       want_inside, prefix, stride, below, bands)  # fmt: skip
                if touch:
                    touched = True
                    if not want_inside:
                        break
                    total += within
        hit[i], inside[i] = touched, total


@declared(_RESULTS(_F[:, ::1], _F[:, ::1], _F[::1], _F[::1], _I, _F, _F, _B, *_TABLES),
          **_OPTIONS)  # fmt: skip
def check(
    x, y, length, clear, samples, margin, d, want_inside, prefix, stride, below, bands
) -> tuple[np.ndarray, np.ndarray]:
    """The filter, then :func:`strips` of the intervals it leaves (``SegmentChecker._check``),
    segment by segment (:func:`segments`).

    ``x``, ``y``: ``(k, samples)`` sample points of k segments of lengths ``length``; ``clear``:
    the filter's table (rows of width + 1, -1 on blocked cells); ``margin`` the extra clearance
    the filter demands. Returns ``hit`` and, if ``want_inside``, the length inside (else zeros):
    the share of samples in blocked cells times the length for a segment with such a sample,
    else the sum over its intervals."""
    k = x.shape[0]
    hit = np.zeros(k, np.bool_)
    inside = np.zeros(k)
    # the tables borrowed (usvtool.kernel_views): strips' calls do not count their references
    segments(x, y, length, k, borrowed(clear), samples, margin, d, want_inside, np.empty(samples),
             borrowed(prefix), stride, borrowed(below), borrowed(bands), hit, inside)  # fmt: skip
    return hit, inside
