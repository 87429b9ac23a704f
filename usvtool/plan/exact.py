"""Exact reference planners: 8-connected A* and the any-angle shortest route.

Both work in cell coordinates (see :mod:`usvtool.collision`) and return routes that touch no
blocked cell under the collision definition of :mod:`usvtool.collision`.

8-connected A* (:func:`astar`)
    Over cell centres, moves to the 8 neighbours (cost 1 or √2), with the octile heuristic. A
    diagonal move passes through the shared corner of four cells, so it is allowed only when the
    two side cells are free too (no corner cutting). The route is start → the centres of the cell
    path → goal, with collinear centres dropped: the shortest route of that kind.

Any-angle shortest route (:func:`any_angle`)
    The shortest polyline touching no blocked cell bends only at convex corners of the blocked
    region: grid points where exactly one of the four incident cells is blocked (cells outside
    the grid count as blocked here, so no vertex lies on the grid's edge). A route may not touch
    the corner itself, so each vertex is moved ``DELTA`` = 1e-5 cell diagonally away from its
    blocked cell; the result is within ``2·DELTA`` per bend of the infimum, which is the optimum
    the optimizers are scored against. The search is A* over these vertices with the Euclidean
    heuristic, building the visibility graph lazily: when a vertex is expanded, one vectorised
    exact line-of-sight call tests the edges to every vertex it would improve. Only edges that
    are taut at both ends are considered (the line through a corner must not cut into its
    blocked cell: a shortest route wraps around the corners it touches), which halves the
    candidates at each end without losing the optimum.
"""

from __future__ import annotations

import heapq
import math

import numpy as np

from usvtool.collision import SegmentChecker

DELTA = 1e-5
_SQRT2 = math.sqrt(2.0)
_MOVES = [(dr, dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1) if dr or dc]


def astar(blocked: np.ndarray, start, goal) -> np.ndarray | None:
    """The 8-connected A* route from ``start`` to ``goal`` (cell coordinates), or None.

    ``start`` and ``goal`` must lie in free cells.

    >>> b = np.zeros((3, 4), bool); b[0:2, 1] = True
    >>> astar(b, (0.5, 0.5), (2.5, 0.5)).tolist()
    [[0.5, 0.5], [0.5, 2.5], [2.5, 2.5], [2.5, 0.5]]
    """
    blocked = np.asarray(blocked, bool)
    cells = _cell_path(~blocked, _cell_of(start, blocked.shape), _cell_of(goal, blocked.shape))
    if cells is None:
        return None
    centres = cells[:, ::-1] + 0.5  # (col, row)
    return _drop_collinear(np.vstack([start, centres, goal]))


def _cell_path(free: np.ndarray, source, target) -> np.ndarray | None:
    """A shortest 8-connected path of cells ``(row, col)`` from ``source`` to ``target``, or None.

    A* as Dijkstra on reduced costs (compiled: :func:`scipy.sparse.csgraph.dijkstra`): with the
    octile distance ``h`` to the target, a consistent heuristic, the move ``u → v`` of cost ``w``
    costs ``w - h(u) + h(v) ≥ 0``, and ``limit = U - h(source)`` settles exactly the cells with
    ``g + h ≤ U``. Every cell of a path of length ``≤ U`` lies in the octile ellipse
    ``oct(source, v) + oct(v, target) ≤ U``, so the graph is built on the free cells of that
    ellipse only. ``U`` starts 0.1 % (at least 4 cells) above the octile distance, its slack
    growing 4-fold until the target is reached (an ellipse holding every cell proves there is
    no path).
    """
    source, target = np.asarray(source), np.asarray(target)
    direct = _octile(*np.abs(source - target))
    slack = max(0.001 * direct, 4.0)
    whole = 2.0 * _octile(*free.shape)  # no octile sum exceeds it
    while True:
        bound = direct + slack
        found = _bounded_search(free, source, target, bound)
        if found is not None or bound > whole:
            return found
        slack *= 4.0


def _bounded_search(free: np.ndarray, source, target, bound: float) -> np.ndarray | None:
    """:func:`_cell_path` restricted to paths of length ``≤ bound``."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import dijkstra

    h, w = free.shape
    lo, hi = _ellipse_rows(source, target, bound, h, w)
    rows = np.arange(h)
    inside = hi >= lo
    r0, r1 = rows[inside][[0, -1]]
    c0, c1 = max(int(lo[inside].min()), 0), min(int(hi[inside].max()), w - 1)
    box = np.zeros((r1 - r0 + 3, c1 - c0 + 3), bool)  # the ellipse's box and a frame
    box[1:-1, 1:-1] = free[r0 : r1 + 1, c0 : c1 + 1]
    stride = box.shape[1]
    cols = np.arange(c0 - 1, c1 + 2)
    span = slice(r0, r1 + 1)
    box[1:-1, 1:-1] &= (cols[1:-1] >= lo[span, None]) & (cols[1:-1] <= hi[span, None])
    flat = np.zeros(box.size, bool)  # free cells of the box (for the side cells)
    flat.reshape(box.shape)[1:-1, 1:-1] = free[r0 : r1 + 1, c0 : c1 + 1]
    cells = np.flatnonzero(box)
    origin = np.array([r0 - 1, c0 - 1])
    n = cells.size
    ids = np.full(box.size, -1, np.int32)
    ids[cells] = np.arange(n, dtype=np.int32)
    s = ids[(source[0] - origin[0]) * stride + source[1] - origin[1]]
    t = ids[(target[0] - origin[0]) * stride + target[1] - origin[1]]
    if s < 0 or t < 0:
        return None
    # moves: 8 slots a node; a move that is not allowed is a loop to the node itself, which
    # Dijkstra ignores (a node is settled when it scans its moves)
    r, c = np.divmod(cells, stride)
    dr_t, dc_t = r + (origin[0] - target[0]), c + (origin[1] - target[1])
    potential = _octile(np.abs(dr_t), np.abs(dc_t))
    targets = np.empty((n, 8), np.int32)
    weights = np.empty((n, 8))
    itself = np.arange(n, dtype=np.int32)
    for k, (dr, dc) in enumerate(_MOVES):
        nb = ids[cells + (dr * stride + dc)]
        ok = nb >= 0
        if dr and dc:
            ok &= flat[cells + dr * stride] & flat[cells + dc]
        targets[:, k] = np.where(ok, nb, itself)
        step = _SQRT2 if dr and dc else 1.0
        reduced = step + _octile(np.abs(dr_t + dr), np.abs(dc_t + dc)) - potential
        weights[:, k] = np.where(ok, np.maximum(reduced, 0.0), 0.0)
    graph = csr_matrix(
        (weights.ravel(), targets.ravel(), np.arange(0, 8 * n + 1, 8, dtype=np.int32)), (n, n)
    )
    dist, pred = dijkstra(
        graph, indices=s, return_predecessors=True, limit=bound - potential[s] + 1e-9
    )
    if not np.isfinite(dist[t]):
        return None
    path = [t]
    while path[-1] != s:
        path.append(int(pred[path[-1]]))
    return np.column_stack([r, c])[path[::-1]] + origin


def _ellipse_rows(source, target, bound: float, h: int, w: int):
    """Per row, the first and last column of the cells whose centres' octile distances to
    ``source`` and ``target`` (``(row, col)``) add up to at most ``bound`` (hi < lo: none).

    Along a row that sum is convex in the column, smallest between the two ends' columns:
    ternary search for the minimum, then bisection for the two crossings, over all rows at once.
    """
    rows = np.arange(h, dtype=float)[:, None]

    def total(col):
        return _octile(np.abs(rows - source[0]), np.abs(col - source[1])) + _octile(
            np.abs(rows - target[0]), np.abs(col - target[1])
        )

    a = np.full((h, 1), float(min(source[1], target[1])))
    b = np.full((h, 1), float(max(source[1], target[1])))
    for _ in range(int(np.log(max(b[0, 0] - a[0, 0], 1.0)) / np.log(1.5)) + 2):
        m1, m2 = a + (b - a) / 3, b - (b - a) / 3
        left = total(m1) <= total(m2)
        a, b = np.where(left, a, m1), np.where(left, m2, b)
    m = np.clip((a + b) / 2, 0, w - 1)
    best = np.where(total(np.floor(m)) <= total(np.ceil(m)), np.floor(m), np.ceil(m))
    ends = []
    for edge in (0.0, w - 1.0):
        inner, outer = best.copy(), np.full((h, 1), edge)
        for _ in range(int(np.log2(w)) + 2):
            mid = np.round((inner + outer) / 2)
            ok = total(mid) <= bound + 1e-9
            inner, outer = np.where(ok, mid, inner), np.where(ok, outer, mid)
        ends.append(np.where(total(outer) <= bound + 1e-9, outer, inner))
    lo, hi = ends
    empty = total(best) > bound + 1e-9
    return np.where(empty, 1, lo).ravel().astype(int), np.where(empty, 0, hi).ravel().astype(int)


def _octile(dx, dy):
    """The 8-connected distance with moves of 1 and √2 (the A* heuristic)."""
    return np.maximum(dx, dy) + (_SQRT2 - 1.0) * np.minimum(dx, dy)


def convex_corners(blocked: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Grid points with exactly one blocked incident cell, and that cell's direction.

    Returns ``(points, signs)``: corner coordinates ``(x, y)`` and the signs ``(±1, ±1)`` of the
    blocked cell's quadrant as seen from the corner. Cells outside the grid count as blocked.

    >>> b = np.zeros((3, 3), bool); b[1, 1] = True
    >>> p, s = convex_corners(b)
    >>> p.tolist(), s.tolist()
    ([[1, 1], [2, 1], [1, 2], [2, 2]], [[1, 1], [-1, 1], [1, -1], [-1, -1]])
    """
    b = np.pad(np.asarray(blocked, bool), 1, constant_values=True).astype(np.int8)
    up_left, up_right, down_left, down_right = b[:-1, :-1], b[:-1, 1:], b[1:, :-1], b[1:, 1:]
    convex = up_left + up_right + down_left + down_right == 1
    rows, cols = np.nonzero(convex)
    sx = (up_right + down_right - up_left - down_left)[rows, cols]
    sy = (down_left + down_right - up_left - up_right)[rows, cols]
    return np.column_stack([cols, rows]), np.column_stack([sx, sy])


def any_angle(checker: SegmentChecker, blocked: np.ndarray, start, goal) -> np.ndarray | None:
    """The any-angle shortest route from ``start`` to ``goal`` (cell coordinates), or None.

    ``checker`` is the :class:`SegmentChecker` of ``blocked``; ``start`` and ``goal`` must touch
    no blocked cell.

    >>> b = np.zeros((3, 5), bool); b[0:2, 2] = True
    >>> r = any_angle(SegmentChecker(b), b, (0.5, 0.5), (4.5, 0.5))
    >>> r.round(4).tolist(), round(float(np.hypot(*np.diff(r, axis=0).T).sum()), 4)  # 3√2 + 1
    ([[0.5, 0.5], [2.0, 2.0], [3.0, 2.0], [4.5, 0.5]], 5.2427)
    """
    blocked = np.asarray(blocked, bool)
    corners, signs = convex_corners(blocked)
    ends = np.array([start, goal], float)
    at = np.vstack([ends, corners])  # tautness is judged at the corners themselves
    pos = np.vstack([ends, corners - DELTA * signs])
    kind = np.concatenate([[0, 0], signs[:, 0] * signs[:, 1]])
    n = len(pos)
    g = np.full(n, np.inf)
    g[0] = 0.0
    parent = np.full(n, -1)
    closed = np.zeros(n, bool)
    h = np.hypot(*(pos - pos[1]).T)
    heap = [(h[0], 0)]
    while heap:
        _, u = heapq.heappop(heap)
        if closed[u]:
            continue
        closed[u] = True
        if u == 1:
            break
        d = at - at[u]
        cross = d[:, 0] * d[:, 1]
        g_new = g[u] + np.hypot(*(pos - pos[u]).T)
        cand = (g_new < g) & (g_new + h < g[1]) & (kind * cross <= 0) & (kind[u] * cross <= 0)
        cand[closed] = False
        idx = np.flatnonzero(cand)
        if idx.size == 0:
            continue
        idx = idx[~_sampled_hit(blocked, pos[u], pos[idx])]  # cheap certain misses first
        if idx.size == 0:
            continue
        idx = idx[~checker.collides(np.broadcast_to(pos[u], (idx.size, 2)), pos[idx])]
        g[idx] = g_new[idx]
        parent[idx] = u
        for v in idx.tolist():
            heapq.heappush(heap, (g[v] + h[v], v))
    if not closed[1]:
        return None
    path = [1]
    while path[-1] != 0:
        path.append(int(parent[path[-1]]))
    return pos[path[::-1]]


def _sampled_hit(blocked: np.ndarray, a, b) -> np.ndarray:
    """Whether the segments ``a → b[i]`` have one of the points at 1/4, 1/2 or 3/4 of their
    length in a blocked cell: then they touch its closed square and collide (a certificate;
    False decides nothing)."""
    h, w = blocked.shape
    hit = np.zeros(len(b), bool)
    for t in (0.5, 0.25, 0.75):
        p = a + t * (b - a)
        col = np.minimum(p[:, 0].astype(np.intp), w - 1)
        row = np.minimum(p[:, 1].astype(np.intp), h - 1)
        hit |= blocked[row, col]
    return hit


def _cell_of(point, shape) -> tuple[int, int]:
    """``(row, col)`` of the cell holding ``point`` (the far edges count in the last cells)."""
    col = min(int(math.floor(point[0])), shape[1] - 1)
    row = min(int(math.floor(point[1])), shape[0] - 1)
    return row, col


def _drop_collinear(route: np.ndarray) -> np.ndarray:
    """The route without repeated points and without vertices that do not turn."""
    keep = np.ones(len(route), bool)
    keep[1:] = np.any(np.diff(route, axis=0) != 0, axis=1)
    route = route[keep]
    if len(route) < 3:
        return route
    d = np.diff(route, axis=0)
    cross = d[:-1, 0] * d[1:, 1] - d[:-1, 1] * d[1:, 0]
    dot = (d[:-1] * d[1:]).sum(axis=1)
    turning = (cross != 0) | (dot < 0)
    return route[np.concatenate([[True], turning, [True]])]
