"""Exact reference planners: 8-connected A* and the any-angle shortest route.

Both work in cell coordinates (see :mod:`usvtool.collision`) and return routes that touch no
blocked cell under the collision definition of :mod:`usvtool.collision`.

8-connected A* (:func:`astar`)
    Over cell centres, moves to the 8 neighbours (cost 1 or √2), with the octile heuristic. A
    diagonal move passes through the shared corner of four cells, so it is allowed only when the
    two side cells are free too (no corner cutting). The route is start → the centres of the cell
    path → goal, with collinear centres dropped: the shortest route of that kind. The search is
    compiled (:mod:`usvtool.plan.gridsearch`).

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
    """A shortest 8-connected path of cells ``(row, col)`` from ``source`` to ``target``, or None
    (compiled A*: :func:`usvtool.plan.gridsearch.cell_path`)."""
    from usvtool.plan import gridsearch

    padded = np.pad(free, 1)
    w = padded.shape[1]
    path = gridsearch.cell_path(
        padded.ravel(), w, (source[0] + 1) * w + source[1] + 1, (target[0] + 1) * w + target[1] + 1
    )
    if path.size == 0:
        return None
    return np.column_stack(np.divmod(path, w)) - 1


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
