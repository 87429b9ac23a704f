"""Compiled kernels of the exact planners (:mod:`usvtool.plan.exact`), with numba.

Written by hand because no maintained library searches a 10 M-cell grid under the project's
diagonal rule: scikit-image's ``MCP`` and ``route_through_array`` (compiled Dijkstra) let a
diagonal move cut between two blocked cells, and scipy's ``csgraph`` needs the graph built as a
sparse matrix first (seconds on 12.5 M cells, and the whole grid for one query). Imported
lazily by :mod:`usvtool.plan.exact`: numba's import costs about 0.3 s.

Grids are passed padded: a one-cell frame of blocked cells round the grid, raveled, so that a
cell's eight neighbours are at fixed index offsets and need no bounds test.

8-connected A* (:func:`cell_path`)
    Moves of 1 (N, E, S, W) and √2 (diagonals, only when both side cells are free: the move
    passes through the shared corner of four cells), the octile heuristic (consistent for these
    moves). The open list is a bucket queue: an entry goes to bucket ``⌊(f - f_s) / WIDTH⌋``
    (``f_s`` the start's), a bucket is a stack, the lowest non-empty bucket is popped first. Order
    within a bucket is not by ``f``, so a cell may be expanded before its best ``g`` is known; it
    is then reopened when a better ``g`` arrives (A* with reopening), and the search stops only
    when the lowest bucket's lower edge ``f_s + b·WIDTH`` reaches the best ``g`` of the target:
    every entry left has ``f ≥`` that edge, so no path through it is shorter. The result is the
    optimum, as with a heap, at O(1) per queue operation (a binary heap of a few 10⁵ entries is
    about 3 times slower here). Memory: a float64 ``g``, an int32 parent and a uint8 state per
    cell, allocated untouched (``np.empty``, ``np.zeros``), so only the explored rows cost pages.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

SQRT2 = math.sqrt(2.0)
WIDTH = 1.0 / 64  # bucket width (cells of path length)
_K = SQRT2 - 1.0


@njit(cache=True, nogil=True)
def cell_path(free: np.ndarray, width: int, source: int, target: int) -> np.ndarray:
    """The flat indices of a shortest 8-connected cell path ``source … target`` in the padded,
    raveled grid ``free`` of ``width`` columns, or an empty array (module docstring)."""
    n = free.size
    w = width
    g = np.empty(n)
    parent = np.empty(n, np.int32)
    state = np.zeros(n, np.uint8)  # 0 unseen (g undefined), 1 queued, 2 expanded
    offsets = np.array([-w - 1, -w, -w + 1, -1, 1, w - 1, w, w + 1], np.int64)
    tr = target // w
    tc = target - tr * w
    sr = source // w
    f0 = _octile(abs(source - sr * w - tc), abs(sr - tr))
    buckets = 1 << 14
    head = np.full(buckets, -1, np.int64)
    cap = 1 << 16
    node = np.empty(cap, np.int64)
    cost = np.empty(cap)
    below = np.empty(cap, np.int64)  # the next entry down the same bucket's stack
    g[source] = 0.0
    state[source] = 1
    node[0], cost[0], below[0], head[0] = source, 0.0, -1, 0
    entries = 1
    b = 0
    best = np.inf
    while True:
        while b < buckets and head[b] < 0:
            b += 1
        if b == buckets or f0 + b * WIDTH >= best:
            break
        e = head[b]
        head[b] = below[e]
        u = node[e]
        gu = cost[e]
        if gu > g[u] or state[u] == 2:
            continue  # a stale entry
        state[u] = 2
        if u == target:
            best = gu
            continue
        north, south, west, east = free[u - w], free[u + w], free[u - 1], free[u + 1]
        for m in range(8):
            if m == 1:
                ok, step = north, 1.0
            elif m == 3:
                ok, step = west, 1.0
            elif m == 4:
                ok, step = east, 1.0
            elif m == 6:
                ok, step = south, 1.0
            else:
                ns = north if m < 4 else south
                we = west if m == 0 or m == 5 else east
                ok, step = ns and we and free[u + offsets[m]], SQRT2
            if not ok:
                continue
            v = u + offsets[m]
            gv = gu + step
            if state[v] != 0 and gv >= g[v]:
                continue
            g[v] = gv
            parent[v] = u
            state[v] = 1
            vr = v // w
            k = max(int((gv + _octile(abs(v - vr * w - tc), abs(vr - tr)) - f0) / WIDTH), b)
            if k >= buckets:
                grown = np.full(max(2 * buckets, k + 1), -1, np.int64)
                grown[:buckets] = head
                head, buckets = grown, grown.size
            if entries == cap:
                cap *= 2
                node, cost, below = _grow(node, cap), _grow(cost, cap), _grow(below, cap)
            node[entries], cost[entries], below[entries] = v, gv, head[k]
            head[k] = entries
            entries += 1
    if best == np.inf:
        return np.empty(0, np.int64)
    count, v = 1, target
    while v != source:
        v = parent[v]
        count += 1
    path = np.empty(count, np.int64)
    v = target
    for i in range(count - 1, -1, -1):
        path[i] = v
        v = parent[v]
    return path


@njit(cache=True, nogil=True, inline="always")
def _octile(dx, dy) -> float:
    return max(dx, dy) + _K * min(dx, dy)


@njit(cache=True, nogil=True)
def _grow(a: np.ndarray, size: int) -> np.ndarray:
    out = np.empty(size, a.dtype)
    out[: a.size] = a
    return out
