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
    cell, the first two allocated untouched (``np.empty``), so only the explored rows cost pages.
Any-angle route (:func:`point_bounds`, :func:`visibility_path`)
    The heuristic's grid-point search and the lazy visibility-graph A* (its exact line of sight
    is :func:`usvtool.collision_kernels.touches`), for :func:`usvtool.plan.exact.any_angle`
    (whose docstring gives the method).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from usvtool.collision_kernels import touches

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
    state = np.empty(n, np.uint8)  # 0 unseen (g undefined), 1 queued, 2 expanded
    for i in range(n):  # zeroed by a loop (a memset to LLVM): np.zeros is more to compile
        state[i] = 0
    offsets = np.empty(8, np.int64)
    offsets[0], offsets[1], offsets[2], offsets[3] = -w - 1, -w, -w + 1, -1
    offsets[4], offsets[5], offsets[6], offsets[7] = 1, w - 1, w, w + 1
    tr = target // w
    tc = target - tr * w
    sr = source // w
    f0 = _octile(abs(source - sr * w - tc), abs(sr - tr))
    head, node, cost, below = _queue()
    g[source] = 0.0
    state[source] = 1
    head, node, cost, below, entries = _push(head, node, cost, below, 0, 0, source, 0.0)
    b = 0
    best = np.inf
    while True:
        b, u, gu = _pop(head, node, cost, below, g, state, b, f0, best)
        if u < 0:
            break
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
            head, node, cost, below, entries = _push(head, node, cost, below, entries, k, v, gv)
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
def _sampled_hit(free: np.ndarray, stride: int, x0: float, y0: float, x1: float, y1: float) -> bool:
    """Whether the point at 1/2, 1/4 or 3/4 of the segment lies in a blocked cell: then the
    segment touches that cell's closed square (a certificate; False decides nothing). Points on
    the grid's far edges count in the last cells."""
    last_col, last_row = stride - 3, free.size // stride - 3
    for t in (0.5, 0.25, 0.75):
        col = min(int(x0 + t * (x1 - x0)), last_col)
        row = min(int(y0 + t * (y1 - y0)), last_row)
        if not free[(row + 1) * stride + col + 1]:
            return True
    return False


@njit(cache=True, nogil=True, inline="always")
def _octile(dx, dy) -> float:
    return max(dx, dy) + _K * min(dx, dy)


@njit(cache=True, nogil=True)
def _queue():
    """An empty bucket queue: ``head[b]`` the top entry of bucket ``b`` (-1: empty), and per
    entry its ``node``, ``cost`` (g) and the entry ``below`` it in its bucket's stack."""
    head = np.empty(1 << 14, np.int64)
    for b in range(head.size):  # not _heads(…, 1 << 14): compiled again for the literal size
        head[b] = -1
    return head, np.empty(1 << 16, np.int64), np.empty(1 << 16), np.empty(1 << 16, np.int64)


@njit(cache=True, nogil=True)
def _heads(head: np.ndarray, size: int) -> np.ndarray:
    """``head`` extended to ``size`` buckets, the new ones empty (-1). Loops, not ``np.full``
    and a slice assignment: those compile their dtype-generic and shape-checking (error
    message formatting) code, seconds of a cold cache's compile."""
    out = np.empty(size, np.int64)
    for i in range(head.size):
        out[i] = head[i]
    for i in range(head.size, size):
        out[i] = -1
    return out


@njit(cache=True, nogil=True, inline="always")
def _pop(head, node, cost, below, g, state, b: int, f0: float, limit: float):
    """The next node to expand: the top entry of the lowest non-empty bucket (from ``b`` on)
    whose lower edge ``f0 + b·WIDTH`` is below ``limit``, stale entries (a better ``g`` since, or
    expanded already) dropped, marked expanded: ``(b, u, g_u)``, ``u = -1`` when none is left."""
    while True:
        while b < head.size and head[b] < 0:
            b += 1
        if b == head.size or f0 + b * WIDTH >= limit:
            return b, -1, 0.0
        e = head[b]
        head[b] = below[e]
        u = node[e]
        if cost[e] > g[u] or state[u] == 2:
            continue
        state[u] = 2
        return b, u, cost[e]


@njit(cache=True, nogil=True, inline="always")
def _push(head, node, cost, below, entries: int, k: int, v: int, gv: float):
    """Push ``(v, gv)`` onto bucket ``k`` (growing the arrays as needed): the queue's arrays and
    its new entry count."""
    if k >= head.size:
        head = _heads(head, max(2 * head.size, k + 1))
    if entries == node.size:
        size = 2 * entries
        node, cost, below = _grow_int(node, size), _grow(cost, size), _grow_int(below, size)
    node[entries], cost[entries], below[entries] = v, gv, head[k]
    head[k] = entries
    return head, node, cost, below, entries + 1


@njit(cache=True, nogil=True)
def _grow(a: np.ndarray, size: int) -> np.ndarray:
    """The float64 array ``a`` copied into a new one of ``size`` (one type per helper and a
    loop, not ``out[: a.size] = a``: see :func:`_heads`)."""
    out = np.empty(size)
    for i in range(a.size):
        out[i] = a[i]
    return out


@njit(cache=True, nogil=True)
def _grow_int(a: np.ndarray, size: int) -> np.ndarray:
    """:func:`_grow` of an int64 array."""
    out = np.empty(size, np.int64)
    for i in range(a.size):
        out[i] = a[i]
    return out


@njit(cache=True, nogil=True)
def point_bounds(
    free: np.ndarray, width: int, sources: np.ndarray, target: int, queries: np.ndarray
) -> np.ndarray:
    """Lower bounds on the grid-point graph distance ``D`` from ``sources`` to ``queries``.

    Points ``(x, y)`` of the grid are the flat indices ``(y + 1)·width + x + 1`` of the padded,
    raveled cell grid ``free`` (``width`` its columns): point ``P`` is the north-west corner of
    padded cell ``P``. Moves: along a cell edge (1) when a cell beside it is free, across a free
    cell's diagonal (√2). A* from ``sources`` (distance 0) to ``target`` with the octile
    heuristic, queue as :func:`cell_path`, stopped when the lowest bucket's edge ``E`` reaches
    the target's distance. Then a point with ``D + oct(·, target) < E`` has its exact ``D`` (it
    was settled), and every other has ``D ≥ E - oct(·, target)`` (else its ``f`` would be below
    ``E``): the bound returned is the first where it applies, else the second (``inf`` for every
    point when the target is unreachable).
    """
    n = free.size
    w = width
    g = np.empty(n)
    state = np.empty(n, np.uint8)
    for i in range(n):  # as in cell_path
        state[i] = 0
    offsets = np.empty(8, np.int64)
    offsets[0], offsets[1], offsets[2], offsets[3] = 1, -1, -w, w
    offsets[4], offsets[5], offsets[6], offsets[7] = -w + 1, -w - 1, w + 1, w - 1
    tx, ty = target % w, target // w
    head, node, cost, below = _queue()
    f0 = np.inf
    for p in sources:
        f0 = min(f0, _octile(abs(p % w - tx), abs(p // w - ty)))
    entries = 0
    for p in sources:
        g[p] = 0.0
        state[p] = 1
        k = int((_octile(abs(p % w - tx), abs(p // w - ty)) - f0) / WIDTH)
        head, node, cost, below, entries = _push(head, node, cost, below, entries, k, p, 0.0)
    stop = np.inf
    b = 0
    while True:
        b, u, gu = _pop(head, node, cost, below, g, state, b, f0, stop)
        if u < 0:
            break
        if u == target:
            stop = gu
            continue
        nw, ne, sw, se = free[u - w - 1], free[u - w], free[u - 1], free[u]
        for m in range(8):
            if m == 0:
                ok, step = ne or se, 1.0
            elif m == 1:
                ok, step = nw or sw, 1.0
            elif m == 2:
                ok, step = nw or ne, 1.0
            elif m == 3:
                ok, step = sw or se, 1.0
            elif m == 4:
                ok, step = ne, SQRT2
            elif m == 5:
                ok, step = nw, SQRT2
            elif m == 6:
                ok, step = se, SQRT2
            else:
                ok, step = sw, SQRT2
            if not ok:
                continue
            v = u + offsets[m]
            gv = gu + step
            if state[v] != 0 and gv >= g[v]:
                continue
            g[v] = gv
            state[v] = 1
            k = max(int((gv + _octile(abs(v % w - tx), abs(v // w - ty)) - f0) / WIDTH), b)
            head, node, cost, below, entries = _push(head, node, cost, below, entries, k, v, gv)
    edge = min(stop, f0 + b * WIDTH) if stop < np.inf else np.inf  # unreached: D = inf
    out = np.empty(queries.size)
    for i in range(queries.size):
        q = queries[i]
        rest = _octile(abs(q % w - tx), abs(q // w - ty))
        if state[q] != 0 and g[q] + rest < edge:
            out[i] = g[q]
        else:
            out[i] = edge - rest
    return out


@njit(cache=True, nogil=True)
def visibility_path(
    pos: np.ndarray, at: np.ndarray, kind: np.ndarray, h: np.ndarray, free: np.ndarray,
    prefix: np.ndarray, stride: int, bound: float,
) -> np.ndarray:
    """A* from vertex 0 to vertex 1 over the visibility graph of ``pos`` (any-angle route, see
    :func:`usvtool.plan.exact.any_angle`), built lazily: expanding ``u`` tries the edge to every
    vertex ``v`` it would improve, taut at both ends (``kind·(Δx·Δy) ≤ 0`` at the corners ``at``)
    and not pruned by ``g + |uv| + h(v) ≥`` the goal's ``g`` or ``bound``, then tests its line
    of sight: first whether the points at 1/2, 1/4 or 3/4 of it lie in a blocked cell (of the
    padded grid ``free``, :func:`cell_path`'s layout; a certain collision, decided in O(1)),
    then exactly (:func:`~usvtool.collision_kernels.touches`). ``h`` must be admissible; a
    vertex is reopened when its ``g`` improves, so it need not be consistent. Returns the vertex
    indices 0 … 1 of the shortest route if it is shorter than ``bound``, else an empty array."""
    n = pos.shape[0]
    px, py, cx, cy, g = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    parent = np.empty(n, np.int64)
    for v in range(n):  # a loop, not column copies and np.full: less to compile (_heads)
        px[v], py[v], cx[v], cy[v] = pos[v, 0], pos[v, 1], at[v, 0], at[v, 1]
        g[v], parent[v] = np.inf, -1
    g[0] = 0.0
    cap = 1 << 10
    hf = np.empty(cap)
    hv = np.empty(cap, np.int64)
    hf[0], hv[0] = h[0], 0
    size = 1
    while size > 0:
        fu, u = hf[0], hv[0]
        size -= 1
        if size > 0:
            lf, lv = hf[size], hv[size]
            i = 0
            while True:
                c = 2 * i + 1
                if c >= size:
                    break
                if c + 1 < size and hf[c + 1] < hf[c]:
                    c += 1
                if hf[c] < lf:
                    hf[i], hv[i] = hf[c], hv[c]
                    i = c
                else:
                    break
            hf[i], hv[i] = lf, lv
        if fu > g[u] + h[u]:
            continue  # stale
        if u == 1:
            break
        ux, uy, ax, ay, ku = px[u], py[u], cx[u], cy[u], kind[u]
        gu = g[u]
        room = min(g[1], bound) - gu  # an edge u → v needs |uv| + h(v) < room
        for v in range(n):
            reach = room - h[v]
            if reach <= 0.0:
                continue
            dx, dy = px[v] - ux, py[v] - uy
            d2 = dx * dx + dy * dy
            if d2 >= reach * reach:
                continue
            cross = (cx[v] - ax) * (cy[v] - ay)
            if kind[v] * cross > 0 or ku * cross > 0:
                continue
            gv = gu + math.sqrt(d2)
            if gv >= g[v]:
                continue
            vx, vy = px[v], py[v]
            if _sampled_hit(free, stride, ux, uy, vx, vy):
                continue
            if touches(prefix, stride, ux, uy, vx, vy):
                continue
            g[v] = gv
            parent[v] = u
            if v == 1:
                room = min(gv, bound) - gu
            if size == cap:
                cap *= 2
                hf, hv = _grow(hf, cap), _grow_int(hv, cap)
            fv = gv + h[v]
            i = size
            size += 1
            while i > 0:
                q = (i - 1) >> 1
                if fv < hf[q]:
                    hf[i], hv[i] = hf[q], hv[q]
                    i = q
                else:
                    break
            hf[i], hv[i] = fv, v
    if g[1] == np.inf:
        return np.empty(0, np.int64)
    count, v = 1, 1
    while v != 0:
        v = parent[v]
        count += 1
    path = np.empty(count, np.int64)
    v = 1
    for i in range(count - 1, -1, -1):
        path[i] = v
        v = parent[v]
    return path
