"""Compiled kernels of the path problem's cost (:class:`usvtool.plan.problem.PathProblem`) and
of the guided problem's decoder (:class:`usvtool.plan.guided.GuidedProblem`), with numba.

The optimizers evaluate a population of 50-100 routes of a few segments each per iteration, and
as NumPy array operations (segments, lengths, turn angles, the collision check's samples and
glue, the sums) an evaluation spent 0.1-0.3 ms, much of it on some 40 calls' overheads. Here a
population is decoded in one call (:func:`decode_waypoints`, :func:`decode_columns`,
:func:`decode_guided`: the guided repair's checks made waypoint by waypoint as its choices need
them) and its cost computed in two (:func:`route_terms`, :func:`combine`) around one NumPy call,
``arctan2`` of the turns: NumPy's SIMD ``arctan2`` (SVML on AVX-512 machines) need not give the
C library's bits (it did not, on 8 % of random turns), so it stays NumPy's, called on the same
values. The kernels are compiled, or loaded from numba's cache, when a problem is made
(:func:`warm`).

Bit for bit. The kernels repeat the NumPy expressions they stand for operation by operation, so
that every cost is the same float as before (the optimizers are chaotic: a last-bit change
changes every route). Three of those expressions are not what they look like, measured on this
project's NumPy (2.4, AVX-512):

- ``np.abs`` of a complex segment is not the C library's ``hypot`` (``np.hypot``, which it is)
  but NumPy's SIMD ``larger · sqrt(fma(r, r, 1))``, ``r = smaller / larger`` (0 when both are
  0): :func:`cabs`.
- the complex product ``(a + bi)(c - di)`` of the turn angles is ``fma(a, c, b·d) + i fma(a,
  -d, b·c)`` (NumPy's SIMD ``muladdsub``): :func:`turn_product`.
- the collision check's samples ``ends @ basis`` (a BLAS product of inner size 2) are
  ``fma(b, t, a·(1 - t))`` (:func:`sample`).

numba contracts no multiply-add by itself (no ``fastmath``), so the fused ones are written out
(:func:`fma`, LLVM's ``llvm.fma``). The sums over a route are NumPy's ``sum(axis=-1)`` of a
contiguous row: its pairwise summation (:func:`pairwise_sum`). tests/plan/test_cost_kernels.py
compares everything with the NumPy path (``PathProblem._cost_python``), bit for bit.

The collision check is :func:`usvtool.collision_kernels.segments` (the filter and the strips of
:meth:`usvtool.collision.SegmentChecker.guide`), of a route's segments at once (the tables
reference-counted once a route, not once a segment: see there). numba's cache keys a kernel on its
own file only: after changing :mod:`usvtool.collision_kernels`, remove
``usvtool/plan/__pycache__/cost_kernels.*.nb*`` (or touch this file).

Speed (benchmarks/bench_cost.py: CPU time, the least of 5 repeats, on this shared 2-core
machine; the populations a plan evaluates, recorded from the run). One evaluation, NumPy path →
compiled: IWSO on env2 (100 routes of 4 segments) 103 → 52 µs, ISSA (50 routes) 135 → 87 µs,
IWSO with 11 waypoints 206 → 119 µs, IWSO+g (decode and cost) 315 → 58 µs, ISSA ``columns`` on
grid20 (100 routes of 21 segments) 626 → 483 µs. What is left is mostly the collision check's
own work (its 4-24 samples per segment looked up in the clearance table, the strips near
land), compiled before. Whole plans (``plan_route``, without the process start): wso 0.079 →
0.063 s, iwso 0.205 → 0.133 s, ssa 0.158 → 0.104 s, issa 0.103 → 0.081 s, pso 0.107 → 0.074 s,
gwo 0.120 → 0.089 s, mrfo 0.154 → 0.104 s, iwso+g 0.640 → 0.280 s, ssa ``columns`` 0.550 →
0.396 s, issa ``columns`` 0.377 → 0.323 s. A ``usvtool plan`` process also loads these kernels
from the cache: 0.02-0.035 s of CPU. Then a route's segments checked at once rather than one
call each (2026-12-06; a profile of the batch of ``make report`` had put a tenth of its CPU in
numba's reference counts, most of it here): the evaluations of a grid20 ``columns`` plan (184,
100 routes of 21 segments) 35.7 → 17.7 ms, of an env1 WSO plan (124) 15.8 → 14.2 ms, the two
versions interleaved in one process (least of 15), the same bits; and with the tables borrowed
(:mod:`usvtool.kernel_views`), measured again on a faster hour, 10.6 → 7.1 ms and 8.7 → 7.9 ms.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numba import types as nt
from numba.extending import intrinsic

from usvtool.collision_kernels import segments
from usvtool.kernel_views import borrowed
from usvtool.measures import RIGHT_ANGLE_COST

_F, _I = nt.float64, nt.int64
_OPTIONS = {"cache": True, "nogil": True}
HALF_PI = np.pi / 2  # turn_cost's divisor, as NumPy computes it


@intrinsic
def fma(typingctx, a, b, c):
    """``a · b + c`` with one rounding (LLVM's ``llvm.fma``: the instruction, or the C
    library's correctly rounded ``fma``)."""
    sig = _F(_F, _F, _F)

    def codegen(context, builder, signature, args):
        return builder.fma(*args)

    return sig, codegen


@njit(inline="always")
def cabs(re, im) -> float:
    """``np.abs`` of the complex ``re + i im`` as NumPy's SIMD loop computes it."""
    re, im = abs(re), abs(im)
    larger, smaller = max(re, im), min(re, im)
    ratio = smaller / larger if larger != 0.0 else 0.0
    return math.sqrt(fma(ratio, ratio, 1.0)) * larger


@njit(inline="always")
def turn_product(a, b, c, d) -> tuple[float, float]:
    """``(a + bi) · conj(c + di)`` as NumPy's SIMD complex product computes it."""
    return fma(a, c, b * d), fma(a, -d, b * c)


@njit(_F(_F[::1], _I, _I), **_OPTIONS)  # a signature: recursive, and cached (without: crashes)
def pairwise_sum(a, start, n) -> float:
    """NumPy's pairwise sum of ``a[start : start + n]`` (``pairwise_sum`` in its
    loops_utils.h.src): under 8 values in order; up to 128 in 8 running sums combined as
    ``((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))``, then the rest in order; more in two
    halves (the first a multiple of 8 long)."""
    if n < 8:
        res = -0.0
        for i in range(start, start + n):
            res += a[i]
        return res
    if n <= 128:
        r0, r1, r2, r3 = a[start], a[start + 1], a[start + 2], a[start + 3]
        r4, r5, r6, r7 = a[start + 4], a[start + 5], a[start + 6], a[start + 7]
        whole = n - n % 8
        for i in range(start + 8, start + whole, 8):
            r0 += a[i]
            r1 += a[i + 1]
            r2 += a[i + 2]
            r3 += a[i + 3]
            r4 += a[i + 4]
            r5 += a[i + 5]
            r6 += a[i + 6]
            r7 += a[i + 7]
        res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
        for i in range(start + whole, start + n):
            res += a[i]
        return res
    n2 = n // 2
    n2 -= n2 % 8
    return pairwise_sum(a, start, n2) + pairwise_sum(a, start + n2, n - n2)


@njit(inline="always")
def row_sum(a, start, n) -> float:
    """``sum(axis=-1)`` of one row: the reduction's identity 0 plus the pairwise sum."""
    return 0.0 + pairwise_sum(a, start, n)


@njit(inline="always")
def sample(a, b, t0, t1) -> float:
    """One coordinate of the sample ``(1 - t) a + t b`` of a segment ``a → b`` as
    ``SegmentChecker._check``'s BLAS product ``ends @ basis`` gives it, ``t0 = 1 - t`` and ``t1
    = t`` its basis column: ``fma(b, t1, a · t0)``."""
    return fma(b, t1, a * t0)


@njit(**_OPTIONS)
def decode_waypoints(X, base, origin, scale, ends) -> np.ndarray:
    """``PathProblem.decode`` (``waypoints``): start, ``((x + base) - origin) / scale`` per
    waypoint, goal."""
    n, k = X.shape[0], base.shape[0]
    routes = np.empty((n, k + 2, 2))
    for i in range(n):
        routes[i, 0, 0], routes[i, 0, 1] = ends[0, 0], ends[0, 1]
        for j in range(k):
            for c in range(2):
                routes[i, j + 1, c] = (X[i, 2 * j + c] + base[j, c] - origin[c]) / scale[c]
        routes[i, k + 1, 0], routes[i, k + 1, 1] = ends[1, 0], ends[1, 1]
    return routes


@njit(**_OPTIONS)
def decode_columns(X, line, height, ends) -> np.ndarray:
    """``PathProblem.decode`` (``columns``): start, ``(j + 0.5, clip(floor(line_j - x_j), 0,
    height - 1) + 0.5)`` per column ``j``, goal."""
    n, k = X.shape
    top = float(height - 1)
    routes = np.empty((n, k + 2, 2))
    for i in range(n):
        routes[i, 0, 0], routes[i, 0, 1] = ends[0, 0], ends[0, 1]
        for j in range(k):
            v = math.floor(line[j] - X[i, j])
            if not math.isnan(v):  # np.clip keeps NaN
                v = min(max(v, 0.0), top)
            routes[i, j + 1, 0] = j + 0.5
            routes[i, j + 1, 1] = v + 0.5
        routes[i, k + 1, 0], routes[i, k + 1, 1] = ends[1, 0], ends[1, 1]
    return routes


@njit(**_OPTIONS)
def route_terms(
    routes, check, basis, clear, samples, margin, d, prefix, stride, below, bands
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per route of ``routes`` ``(n, m, 2)``: its length (the sum of ``np.abs`` of its
    segments), the length inside the squares grown by ``d`` and the number of segments touching
    them (:meth:`usvtool.collision.SegmentChecker.guide`: the samples of every segment
    (:func:`sample`), then :func:`usvtool.collision_kernels.segments` of the route's; skipped
    unless ``check``: zeros), and the complex products whose angles are its turn angles (``(n,
    m - 2)``; ``1`` where :func:`usvtool.measures.turn_angles` gives 0: a degenerate segment, or
    none before it)."""
    n, m = routes.shape[0], routes.shape[1]
    s = m - 1
    length = np.empty(n)
    inside = np.empty(n)  # np.empty and set below: np.zeros is more to compile
    hits = np.empty(n, np.int64)
    turn = np.empty((n, max(m - 2, 0)), np.complex128)
    seg_len = np.empty(s)
    seg_in = np.empty(s)  # set before read (check)
    seg_hit = np.empty(s, np.bool_)
    xs, ys, r = np.empty((s, samples)), np.empty((s, samples)), np.empty(samples)
    # the tables borrowed (usvtool.kernel_views): the helpers' calls do not count references
    clear, prefix, below, bands = borrowed(clear), borrowed(prefix), borrowed(below), \
        borrowed(bands)  # fmt: skip
    for i in range(n):
        last = -1  # the last non-degenerate segment so far
        lx = ly = 0.0
        for j in range(s):
            ax, ay = routes[i, j, 0], routes[i, j, 1]
            bx, by = routes[i, j + 1, 0], routes[i, j + 1, 1]
            dx, dy = bx - ax, by - ay
            seg_len[j] = cabs(dx, dy)
            if check:
                for q in range(samples):
                    xs[j, q] = sample(ax, bx, basis[0, q], basis[1, q])
                    ys[j, q] = sample(ay, by, basis[0, q], basis[1, q])
            real = dx != 0.0 or dy != 0.0
            if j > 0:
                if real and last >= 0:
                    re, im = turn_product(dx, dy, lx, ly)
                    turn[i, j - 1] = complex(re, im)
                else:
                    turn[i, j - 1] = 1.0
            if real:
                last, lx, ly = j, dx, dy
        hits[i] = 0
        if check:
            segments(xs, ys, seg_len, s, clear, samples, margin, d, True, r, prefix, stride,
                     below, bands, seg_hit, seg_in)  # fmt: skip
            for j in range(s):
                hits[i] += seg_hit[j]
        length[i] = row_sum(seg_len, 0, s)
        inside[i] = row_sum(seg_in, 0, s) if check else 0.0
    return length, inside, hits, turn


@njit(**_OPTIONS)
def combine(length, inside, hits, angle, cell, turn_weight, inside_weight, penalty) -> np.ndarray:
    """The cost of each route from :func:`route_terms` and ``angle = arctan2`` of its turns:
    ``cell · (L + w · T + inside_weight · L_in) + penalty · n_col`` with ``T`` the ISSA turning
    energy (:func:`usvtool.measures.turn_cost`), in ``PathProblem.cost``'s order."""
    n, k = angle.shape
    cost = np.empty(n)
    row = np.empty(k)
    for i in range(n):
        for j in range(k):
            row[j] = abs(angle[i, j])
        turning = RIGHT_ANGLE_COST * row_sum(row, 0, k) / HALF_PI
        free = length[i] + turn_weight * turning
        cost[i] = cell * (free + inside_weight * inside[i]) + penalty * hits[i]
    return cost


@njit(inline="always")
def free(
    ax,
    ay,
    bx,
    by,
    blocked,
    basis,
    xs,
    ys,
    r,
    clear,
    samples,
    margin,
    d,
    prefix,
    stride,
    below,
    bands,
    one,
    hit,
    within,
) -> bool:
    """``GuidedProblem._free`` of one segment: in the grid, neither end in a blocked cell (the
    one holding it), and touching no blocked square grown by ``d``
    (:func:`usvtool.collision_kernels.segments` of its samples, :func:`sample`, in the first
    rows of ``xs``, ``ys``; its length ``np.hypot``'s, the C library's ``hypot``, in ``one``;
    ``hit`` and ``within`` scratch)."""
    h, w = blocked.shape
    if not (0.0 <= ax <= w and 0.0 <= ay <= h and 0.0 <= bx <= w and 0.0 <= by <= h):
        return False
    if blocked[min(int(ay), h - 1), min(int(ax), w - 1)]:
        return False
    if blocked[min(int(by), h - 1), min(int(bx), w - 1)]:
        return False
    one[0] = math.hypot(bx - ax, by - ay)
    for q in range(samples):
        xs[0, q] = sample(ax, bx, basis[0, q], basis[1, q])
        ys[0, q] = sample(ay, by, basis[0, q], basis[1, q])
    segments(xs, ys, one, 1, clear, samples, margin, d, False, r, prefix, stride, below, bands,
             hit, within)  # fmt: skip
    return not hit[0]


@njit(**_OPTIONS)
def decode_guided(
    X, station, frame, cell, blocked, basis, clear, samples, margin, d, prefix, stride, below, bands
) -> np.ndarray:
    """``GuidedProblem.decode``: the moved waypoints ``w_j = s_j + (x_j0 f_j0 + x_j1 f_j1) /
    cell`` (``frame`` ``(K, 2, 2)``), each kept where it sees the next station and the previous
    waypoint (the kept one, else its station) sees it (:func:`free`), else its station.

    The checks are made as the choices need them, waypoint by waypoint: the NumPy decoder makes
    more, all at once, and chooses from them the same way; a segment's answer does not depend
    on the others'."""
    n = X.shape[0]
    k = station.shape[0] - 2
    routes = np.empty((n, k + 2, 2))
    xs, ys, r = np.empty((1, samples)), np.empty((1, samples)), np.empty(samples)
    one, hit, within = np.empty(1), np.empty(1, np.bool_), np.empty(1)
    # the tables borrowed (usvtool.kernel_views): free's calls do not count their references
    blocked, basis, clear = borrowed(blocked), borrowed(basis), borrowed(clear)
    prefix, below, bands = borrowed(prefix), borrowed(below), borrowed(bands)
    for i in range(n):
        routes[i, 0, 0], routes[i, 0, 1] = station[0, 0], station[0, 1]
        routes[i, k + 1, 0], routes[i, k + 1, 1] = station[k + 1, 0], station[k + 1, 1]
        for j in range(k):
            x0, x1 = X[i, 2 * j], X[i, 2 * j + 1]
            wx = station[j + 1, 0] + (x0 * frame[j, 0, 0] + x1 * frame[j, 1, 0]) / cell
            wy = station[j + 1, 1] + (x0 * frame[j, 0, 1] + x1 * frame[j, 1, 1]) / cell
            # w_j → s_j+1, then (if free) from the previous waypoint (w_j-1 where kept, else
            # s_j-1) → w_j: one call of the inlined check in a loop, not two copies to compile
            ax, ay, bx, by = wx, wy, station[j + 2, 0], station[j + 2, 1]
            for _ in range(2):
                keep = free(ax, ay, bx, by, blocked, basis, xs, ys, r, clear, samples, margin, d,
                            prefix, stride, below, bands, one, hit, within)  # fmt: skip
                if not keep:
                    break
                ax, ay, bx, by = routes[i, j, 0], routes[i, j, 1], wx, wy
            if keep:
                routes[i, j + 1, 0], routes[i, j + 1, 1] = wx, wy
            else:
                routes[i, j + 1, 0] = station[j + 1, 0]
                routes[i, j + 1, 1] = station[j + 1, 1]
    return routes


def warm(kind: str) -> None:
    """Compile the kernels a problem of ``kind`` (its encoding, ``waypoints`` or ``columns``, or
    ``guided``) calls, or load them from numba's cache, once per process: when the problem is
    made, not in a first call inside a timing (their signatures are not given: loading every
    kernel at import cost 0.19 s of CPU a process, a plan needs three or four of them; and given
    one, :func:`route_terms`'s code took 1.3-1.5 times as long on the same populations, measured,
    for no reason found). The arguments have the types of the problems' calls."""
    if kind in _WARM:
        return
    ends = np.zeros((2, 2))
    routes = np.zeros((1, 3, 2))
    if kind == "waypoints":
        decode_waypoints(np.zeros((1, 2)), np.zeros((1, 2)), np.zeros(2), np.ones(2), ends)
    elif kind == "columns":
        decode_columns(np.zeros((1, 1)), np.zeros(1), 1, ends)
    else:
        decode_guided(np.zeros((0, 2)), np.zeros((3, 2)), np.zeros((1, 2, 2)), 1.0,
                      np.zeros((1, 1), np.bool_), *_NO_CHECK)  # fmt: skip
    length, inside, hits, turn = route_terms(routes, False, *_NO_CHECK)
    combine(length, inside, hits, np.zeros((1, 1)), 1.0, 1.0, 1.0, 1.0)
    _WARM.add(kind)


_WARM: set[str] = set()
#: A check's arguments (``SegmentChecker.kernel_args``) of the right types, never read.
_NO_CHECK = (np.zeros((2, 4)), np.zeros(4), 4, 0.0, 0.0, np.zeros(4, np.int32), 2, np.zeros(0),
             np.zeros((3, 0)))  # fmt: skip
