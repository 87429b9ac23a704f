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
    the optimizers are scored against. The search (compiled, :mod:`usvtool.plan.gridsearch`) is
    A* over these vertices, building the visibility graph lazily: expanding a vertex tests the
    edges to every vertex it would improve, first by three sample points (a blocked one proves a
    collision), then exactly. Only edges that are taut at both ends are considered (the line
    through a corner must not cut into its blocked cell: a shortest route wraps around the
    corners it touches), which halves the candidates at each end without losing the optimum.

    Heuristic: ``h(v) = max(|v - goal|, (D(v) - SLACK) / RATIO)``, with ``D`` the distance to the
    goal's cell corners in the graph of grid points (moves along a cell edge with a free cell
    beside it, cost 1, or across a free cell's diagonal, √2). It never overestimates: a free
    segment ``P → Q`` between grid points crosses, in each column, the cell its digital line
    (Bresenham's) steps through, so that line is a path of the point graph, of octile length
    ``≤ |PQ| / cos(π/8)``; ``RATIO`` = 1.0824 is that factor, ``SLACK`` = 2 cells covers the
    goal's offset from its cell's corners and the vertices' ``DELTA`` (tested against a
    brute-force visibility graph). ``D`` comes from one A* over the point graph from the goal's
    cell to the start's, stopped when it arrives at distance ``U``: exact where it settled a
    point, ``≥ U - oct(v, start)`` elsewhere. Unlike the Euclidean distance it sees round
    peninsulas (on US4MD81M's winding route it halves the expanded vertices). The search may
    also drop every vertex with ``|v - start| + h(v) ≥ B`` and every edge with ``g + |uv| + h ≥
    B`` for a bound ``B``: ``(U + 2·SLACK) / TIGHT`` first, then ``U + 2·SLACK`` (the point
    graph's distance is above the any-angle one except through pinches, two blocked cells
    touching at a corner; by 0-8 % with the direction, so the tighter bound usually holds the
    optimum and prunes more), then ``RATIO·(U + 2·SLACK)``, then none; a bound below the
    optimum only returns no route, so the
    result is the optimum whichever bound gives it.
"""

from __future__ import annotations

import math

import numpy as np

from usvtool.collision import SegmentChecker

DELTA = 1e-5
RATIO = 1.0824  # ≥ 1/cos(π/8): the octile length over the Euclidean, at most
SLACK = 2.0  # cells: the goal's cell corners, and the vertices' DELTA offsets
TIGHT = 1.02  # the first bound tried is the point distance over this (most routes are shorter)


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
    from usvtool.plan import gridsearch

    blocked = np.asarray(blocked, bool)
    corners, signs = convex_corners(blocked)
    ends = np.array([start, goal], float)
    at = np.vstack([ends, corners])  # tautness is judged at the corners themselves
    pos = np.vstack([ends, corners - DELTA * signs])
    kind = np.concatenate([[0, 0], signs[:, 0] * signs[:, 1]])
    free = np.pad(~blocked, 1).ravel()
    h, ends_apart = _heuristic(free, blocked.shape, corners, pos, ends)
    lower = np.hypot(*(pos - ends[0]).T) + h  # no route through v is shorter
    first = ends_apart + 2 * SLACK
    for bound in (first / TIGHT, first, RATIO * first, np.inf):
        keep = np.flatnonzero(lower < bound)  # the ends first: their lower bound is |goal - start|
        if keep.size < 2 or keep[1] != 1:
            path = keep[:0]
        else:
            path = keep[gridsearch.visibility_path(
                pos[keep], at[keep], kind[keep], h[keep], free, checker._prefix,
                checker.width + 2, bound,
            )]  # fmt: skip
        if path.size or not np.isfinite(ends_apart):
            break
    return pos[path] if path.size else None


def _heuristic(free: np.ndarray, shape, corners: np.ndarray, pos: np.ndarray, ends):
    """``(h, D)``: admissible estimates ``h`` of the any-angle distance from each vertex to the
    goal (module docstring) on the padded grid ``free`` (``shape`` unpadded): ``max(|v - goal|,
    (D(v) - SLACK) / RATIO)`` with ``D`` the grid-point
    graph distance from the goal's cell, bounded below where the search did not settle it
    (:func:`usvtool.plan.gridsearch.point_bounds`); and ``D`` between the ends' cells."""
    from usvtool.plan import gridsearch

    w = shape[1] + 2

    def cell_corners(point) -> np.ndarray:
        r, c = _cell_of(point, shape)
        return np.array([(r + dy + 1) * w + c + dx + 1 for dy in (0, 1) for dx in (0, 1)])

    start, goal = ends
    corners4 = cell_corners(start)
    xy = np.column_stack([corners4 % w - 1, corners4 // w - 1])
    target = corners4[np.argmin(np.hypot(*(xy - start).T))]  # the start cell's nearest corner
    queries = np.concatenate([(corners[:, 1] + 1) * w + corners[:, 0] + 1, [target]])
    bound = gridsearch.point_bounds(free, w, cell_corners(goal), target, queries)
    h = np.hypot(*(pos - goal).T)
    h[2:] = np.maximum(h[2:], (bound[:-1] - SLACK) / RATIO)
    h[1] = 0.0
    return h, float(bound[-1])


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
