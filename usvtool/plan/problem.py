"""The path problem: a route encoded as a vector, and its cost for a whole population at once.

Encodings (``x`` is one individual, bounds are :attr:`PathProblem.lower` / ``upper``)

``waypoints`` (default)
    ``x = (x_1, y_1, …, x_K, y_K)``: ``K`` free waypoints in map metres, each bounded by the
    grid's extent; the route is start → waypoints → goal joined by straight segments.
``columns`` (the ISSA paper's encoding, section 4)
    One variable per grid column (dimension = number of columns): the route visits one cell in
    each column, west to east: start → the centres of the chosen cells → goal. ``x_j`` in
    ``[-H, H]`` is the chosen cell's offset in cells (north positive) from the straight
    start-goal line at the column's centre, floored to a whole cell and clipped to the grid.
    Measuring from that line rather than from the grid's edge keeps the encoding the same
    whichever corner the route starts from, and makes ``x = 0`` the straight route rather than
    the route along an edge of the grid (SSA and ISSA pull producers towards ``x = 0``).

Cost (in metres; ``ℓ`` cell size, ``W × H`` grid)

``cost = L + ℓ · w · T + S · n_col + 10 · L_in``, where ``L`` is the route length (IWSO eq. 28),
``T`` the ISSA turning energy (:func:`usvtool.metrics.turn_cost`, in cell sides, weight ``w``),
``n_col`` the number of segments touching a blocked cell (exact, :mod:`usvtool.plan.raster`),
``S = ℓ (W + H)`` (longer than any sensible route, so any collision-free route beats a colliding
one of similar length) and ``L_in`` the estimated length inside blocked cells, which guides the
search out of land. The penalty is zero exactly when the route is collision-free.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from usvtool import metrics
from usvtool.grid import Grid
from usvtool.plan.raster import SegmentChecker

ENCODINGS = ("waypoints", "columns")
INSIDE_WEIGHT = 10.0  # cost per metre of route inside blocked cells

_cache: tuple[Grid, SegmentChecker] | None = None


def checker_for(grid: Grid) -> SegmentChecker:
    """The :class:`SegmentChecker` of ``grid`` (kept for the last grid used; do not mutate it)."""
    global _cache
    if _cache is None or _cache[0] is not grid:
        _cache = (grid, SegmentChecker(grid.blocked))
    return _cache[1]


@dataclass
class PathProblem:
    """A route from ``start`` to ``goal`` (map metres) on ``grid``; call it on a population.

    >>> from affine import Affine
    >>> g = Grid(np.zeros((10, 10), np.uint8), Affine(1, 0, 0, 0, -1, 10))
    >>> p = PathProblem(g, (0.5, 0.5), (9.5, 0.5), waypoints=1)
    >>> p([[5.0, 0.5], [5.0, 4.5]]).round(3).tolist()  # straight; 12.042 m + an 83.3° turn
    [9.0, 12.412]
    """

    grid: Grid
    start: tuple[float, float]
    goal: tuple[float, float]
    encoding: str = "waypoints"
    waypoints: int = 3
    turn_weight: float = 1.0
    checker: SegmentChecker = field(init=False, repr=False)

    def __post_init__(self):
        if self.encoding not in ENCODINGS:
            raise ValueError(f"encoding must be one of {ENCODINGS}, not {self.encoding!r}")
        if self.encoding == "waypoints" and self.waypoints < 1:
            raise ValueError("waypoints must be >= 1")
        self.checker = checker_for(self.grid)
        self._ends = np.array(
            [self.grid.to_cell_coords(*self.start), self.grid.to_cell_coords(*self.goal)], float
        )
        g = self.grid
        left, bottom, right, top = g.bounds
        self._origin = np.array([left, top])
        self._scale = np.array([g.cell_size, -g.cell_size])
        self.penalty = g.cell_size * (g.width + g.height)
        if self.encoding == "columns":
            (c0, r0), (c1, r1) = self._ends
            centres = np.arange(g.width) + 0.5
            self._line = r0 + (r1 - r0) * ((centres - c0) / (c1 - c0) if c1 != c0 else 0.0)
            self.lower = np.full(g.width, -float(g.height))
            self.upper = np.full(g.width, float(g.height))
        else:
            self.lower = np.tile([left, bottom], self.waypoints)
            self.upper = np.tile([right, top], self.waypoints)

    @property
    def dim(self) -> int:
        return self.lower.size

    def decode(self, X) -> np.ndarray:
        """Routes of the population ``X`` ``(n, dim)`` as cell coordinates ``(n, m, 2)``."""
        X = np.atleast_2d(np.asarray(X, float))
        n, k = X.shape
        g = self.grid
        if self.encoding == "columns":
            mid = np.empty((n, k, 2))
            mid[..., 0] = np.arange(k) + 0.5
            mid[..., 1] = np.clip(np.floor(self._line - X), 0, g.height - 1) + 0.5
        else:
            mid = (X.reshape(n, k // 2, 2) - self._origin) / self._scale
        routes = np.empty((n, mid.shape[1] + 2, 2))
        routes[:, 0] = self._ends[0]
        routes[:, 1:-1] = mid
        routes[:, -1] = self._ends[1]
        return routes

    def __call__(self, X) -> np.ndarray:
        """Cost of each individual of ``X`` ``(n, dim)``: one vectorised evaluation."""
        return self.cost(self.decode(X))

    def cost(self, routes) -> np.ndarray:
        """Cost (module docstring) of routes in cell coordinates ``(n, m, 2)`` inside the grid."""
        routes = np.asarray(routes, float)
        n, m = routes.shape[:2]
        ell = self.grid.cell_size
        hit, inside = self.checker.check_unchecked(
            routes[:, :-1].reshape(-1, 2), routes[:, 1:].reshape(-1, 2)
        )
        n_col = hit.reshape(n, m - 1).sum(axis=1)
        inside = inside.reshape(n, m - 1).sum(axis=1)
        length = metrics.path_length(routes)
        turning = self.turn_weight * metrics.turn_cost(routes)
        return ell * (length + turning + INSIDE_WEIGHT * inside) + self.penalty * n_col

    def to_map(self, route) -> np.ndarray:
        """Cell coordinates ``(m, 2)`` to map metres ``(m, 2)``."""
        route = np.asarray(route, float)
        return np.column_stack(self.grid.to_map(route[:, 0], route[:, 1]))
