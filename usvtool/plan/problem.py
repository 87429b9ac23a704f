"""The path problem: a route encoded as a vector, and its cost for a whole population at once.

Encodings (``x`` is one individual, bounds are :attr:`PathProblem.lower` / ``upper``)

``waypoints`` (default)
    ``x = (dx_1, dy_1, …, dx_K, dy_K)``: ``K`` free waypoints, each given in map metres as its
    offset from its base point ``b_k = start + k / (K + 1) (goal - start)`` on the straight
    start-goal line and bounded so that it stays inside the bounding box of the navigable region
    holding the start and goal (:attr:`usvtool.grid.Grid.regions`; the grid's extent when the
    water reaches every edge): a waypoint outside that box lies in a cell that no collision-free
    route reaches, so no such route is lost, and on a chart whose water is a thin strip of a wide
    grid the box is several times smaller. The route is start → waypoints → goal joined by
    straight segments. Centring the variables on the straight route matters: WSO/IWSO
    (eqs. 4, 9), SSA/ISSA (eq. 1) and others scale positions towards the
    origin, which with absolute coordinates is the map's corner (their routes then crowd it,
    docs/planning.md has the figures); with offsets it is the straight route, a fair prior for
    every algorithm.
``columns`` (the ISSA paper's encoding, section 4)
    One variable per grid column (dimension = number of columns): the route visits one cell in
    each column, west to east: start → the centres of the chosen cells → goal. ``x_j`` in
    ``[-H, H]`` is the chosen cell's offset in cells (north positive) from the straight
    start-goal line at the column's centre, floored to a whole cell and clipped to the grid.
    Measuring from that line rather than from the grid's edge keeps the encoding the same
    whichever corner the route starts from, and makes ``x = 0`` the straight route rather than
    the route along an edge of the grid (SSA and ISSA pull producers towards ``x = 0``).

What the optimizers see (:meth:`PathProblem.search`)
    A dimensionless view of the problem: the ``waypoints`` variables in units of the straight
    start-goal distance ``D`` and the cost in units of ``D`` (the ``columns`` variables are
    already in cells; their cost is counted in cells). Several published update rules have a
    term of fixed size (SSA's producer step ``x + Q L`` with ``Q ~ N(0, 1)``, its fly-off
    ``Q exp((x_worst - x) / i^2)``, its scouts' ``K |x - x_worst| / (f - f_w)``, BOA's fragrance
    ``c I^a``), tuned on benchmark functions whose variables and costs are of order 1-100; in
    metres their effect would depend on the chart's size and units (on Boston, offsets of
    10 000 m make the fly-off overflow to the box's corners). In units of ``D`` the same
    geometry gives the same search whatever its scale. The optimizers' best costs are reported
    back in metres.

Cost (in metres; ``ℓ`` cell size, ``W × H`` grid)

``cost = L + ℓ · w · T + S · n_col + 10 · ℓ · L_in``, where ``L`` is the route length (IWSO eq.
28), ``T`` the ISSA turning energy (:func:`usvtool.measures.turn_cost`, in cell sides, weight
``w``), ``S = ℓ (W + H)`` (longer than any sensible route, so any collision-free route beats a
colliding one of similar length), and, against the blocked squares grown by ``PAD`` = 1e-3 cell
(:meth:`usvtool.collision.SegmentChecker.guide`), ``n_col`` the number of segments touching
them and ``L_in`` (cells) the length inside them, which guides the search out of land: exact
near the boundary, estimated from samples for segments that run deep into land.

The tolerance ``PAD`` matters. Against the exact squares, ``L_in`` falls to 0 at the obstacle's
boundary while ``n_col`` is still 1, so a search converging onto the boundary from the colliding
side (SSA and ISSA do, pulled towards the straight route) ends 1e-9 cell inside it: colliding.
With the grown squares it ends up to 1e-3 cell outside: free. In the search the penalty is zero
exactly for routes that keep 1e-3 cell clear of every blocked cell. The figure reported for a
route (``cost(routes, exact=True)``, the route's ``fitness``) drops the tolerance: its penalty is
zero exactly when the route is collision-free, so the exact planners' routes, 1e-5 cell from
the corners they wrap, and the searches' routes, which end on the grown boundary, show none.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from usvtool import measures
from usvtool.collision import SegmentChecker
from usvtool.grid import Grid

ENCODINGS = ("waypoints", "columns")
INSIDE_WEIGHT = 10.0  # cost per metre of route inside blocked cells
PAD = 1e-3  # cells by which the cost grows the blocked squares (module docstring)


@dataclass
class PathProblem:
    """A route from ``start`` to ``goal`` (map metres) on ``grid``; call it on a population.

    >>> from affine import Affine
    >>> g = Grid(np.zeros((10, 10), np.uint8), Affine(1, 0, 0, 0, -1, 10))
    >>> p = PathProblem(g, (0.5, 0.5), (9.5, 0.5), waypoints=1)
    >>> X = p.encode([[[5.0, 0.5]], [[5.0, 4.5]]])  # waypoints in map metres -> offsets
    >>> X.tolist()
    [[0.0, 0.0], [0.0, 4.0]]
    >>> p(X).round(3).tolist()  # straight; 12.042 m + an 83.3° turn
    [9.0, 12.412]
    """

    grid: Grid
    start: tuple[float, float]
    goal: tuple[float, float]
    encoding: str = "waypoints"
    waypoints: int = 3
    turn_weight: float = 1.0
    checker: SegmentChecker = field(init=False, repr=False)  # its pad is the cost's PAD

    def __post_init__(self):
        if self.encoding not in ENCODINGS:
            raise ValueError(f"encoding must be one of {ENCODINGS}, not {self.encoding!r}")
        if self.encoding == "waypoints" and self.waypoints < 1:
            raise ValueError("waypoints must be >= 1")
        self.checker = SegmentChecker(self.grid.blocked, pad=PAD)
        from usvtool.plan import cost_kernels

        cost_kernels.warm(self.encoding)  # compiled or loaded now, not in a timed call

        self._ends = np.array(
            [self.grid.to_cell_coords(*self.start), self.grid.to_cell_coords(*self.goal)], float
        )
        g = self.grid
        left, _, _, top = g.bounds
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
            t = np.arange(1, self.waypoints + 1) / (self.waypoints + 1)
            start, goal = np.asarray(self.start, float), np.asarray(self.goal, float)
            self._base = start + t[:, None] * (goal - start)  # (K, 2) map metres
            water = g.regions == g.region_at(*self._ends[0])
            rows, cols = np.flatnonzero(water.any(axis=1)), np.flatnonzero(water.any(axis=0))
            x0, y0 = g.to_map(cols[0], rows[-1] + 1)  # the box's south-west corner
            x1, y1 = g.to_map(cols[-1] + 1, rows[0])
            self.lower = (np.array([x0, y0]) - self._base).ravel()
            self.upper = (np.array([x1, y1]) - self._base).ravel()

    @property
    def dim(self) -> int:
        return self.lower.size

    def decode(self, X) -> np.ndarray:
        """Routes of the population ``X`` ``(n, dim)`` as cell coordinates ``(n, m, 2)``: one
        compiled call (:mod:`usvtool.plan.cost_kernels`; :meth:`_decode_python` the same in
        NumPy)."""
        X = np.atleast_2d(np.ascontiguousarray(X, dtype=float))
        if X.ndim != 2 or X.shape[1] != self.dim:
            raise ValueError(f"a population of shape (n, {self.dim}), not {X.shape}")
        from usvtool.plan import cost_kernels  # numba: imported with the checker's kernels

        if self.encoding == "columns":
            return cost_kernels.decode_columns(X, self._line, self.grid.height, self._ends)
        return cost_kernels.decode_waypoints(X, self._base, self._origin, self._scale, self._ends)

    def _decode_python(self, X) -> np.ndarray:
        """:meth:`decode` in NumPy (the reference of tests/plan/test_cost_kernels.py)."""
        X = np.atleast_2d(np.asarray(X, float))
        n, k = X.shape
        g = self.grid
        if self.encoding == "columns":
            mid = np.empty((n, k, 2))
            mid[..., 0] = np.arange(k) + 0.5
            mid[..., 1] = np.clip(np.floor(self._line - X), 0, g.height - 1) + 0.5
        else:
            mid = (X.reshape(n, k // 2, 2) + self._base - self._origin) / self._scale
        routes = np.empty((n, mid.shape[1] + 2, 2))
        routes[:, 0] = self._ends[0]
        routes[:, 1:-1] = mid
        routes[:, -1] = self._ends[1]
        return routes

    def encode(self, waypoints) -> np.ndarray:
        """Individuals ``(n, dim)`` for waypoints given in map metres ``(n, K, 2)``
        (``waypoints`` encoding)."""
        if self.encoding != "waypoints":
            raise ValueError("encode() is for the waypoints encoding")
        W = np.asarray(waypoints, float).reshape(-1, self.waypoints, 2)
        return (W - self._base).reshape(W.shape[0], -1)

    def __call__(self, X) -> np.ndarray:
        """Cost of each individual of ``X`` ``(n, dim)``: one vectorised evaluation."""
        return self.cost(self.decode(X))

    def cost(self, routes, exact: bool = False) -> np.ndarray:
        """Cost (module docstring) of routes in cell coordinates ``(n, m, 2)`` inside the grid;
        with ``exact``, against the blocked squares themselves rather than the grown ones (the
        figure reported for a route: the search's tolerance is not a property of the route).

        Two compiled calls around NumPy's ``arctan2`` (:mod:`usvtool.plan.cost_kernels`), the
        same floats as :meth:`_cost_python`."""
        return self._kernel_cost(routes, True, 0.0 if exact else self.checker.pad)

    def _kernel_cost(self, routes, check: bool, pad: float) -> np.ndarray:
        """:meth:`cost` against the squares grown by ``pad``; without ``check`` (routes known
        to be collision-free) only its length and turning terms (:meth:`free_cost`)."""
        routes = np.ascontiguousarray(routes, dtype=float)
        if routes.ndim != 3 or routes.shape[2] != 2:
            raise ValueError(f"routes of shape (n, m, 2), not {routes.shape}")
        from usvtool.plan import cost_kernels

        length, inside, hits, turn = cost_kernels.route_terms(
            routes, check, *self.checker.kernel_args(pad)
        )
        angle = np.arctan2(turn.imag, turn.real)  # NumPy's, whose bits the cost keeps
        return cost_kernels.combine(
            length, inside, hits, angle, float(self.grid.cell_size), float(self.turn_weight),
            INSIDE_WEIGHT, float(self.penalty),
        )  # fmt: skip

    def _cost_python(self, routes, exact: bool = False) -> np.ndarray:
        """:meth:`cost` in NumPy (the reference of tests/plan/test_cost_kernels.py)."""
        routes = np.asarray(routes, float)
        n, m = routes.shape[:2]
        ell = self.grid.cell_size
        seg = measures.segments(routes)  # once, for the lengths, the turns and the checks
        seg_length = np.abs(seg)
        hit, inside = self.checker.guide(
            routes[:, :-1].reshape(-1, 2), routes[:, 1:].reshape(-1, 2), seg_length.ravel(), exact
        )
        n_col = hit.reshape(n, m - 1).sum(axis=1)
        inside = inside.reshape(n, m - 1).sum(axis=1)
        return ell * (self.free_cost(seg) + INSIDE_WEIGHT * inside) + self.penalty * n_col

    def free_cost(self, seg: np.ndarray) -> np.ndarray:
        """The length and turning terms (cells) of routes given by their segments
        (:func:`measures.segments`): the whole cost, over the cell size, of a route that touches
        no blocked cell."""
        return np.abs(seg).sum(axis=1) + self.turn_weight * measures.turn_cost(seg)

    @property
    def unit(self) -> float:
        """Metres per unit of :meth:`search`'s cost: ``D`` (at least one cell) for ``waypoints``,
        the cell size for ``columns``."""
        if self.encoding == "columns":
            return self.grid.cell_size
        return max(float(np.hypot(*np.subtract(self.goal, self.start))), self.grid.cell_size)

    def search(self) -> Search:
        """The dimensionless view the optimizers minimise (module docstring).

        >>> from affine import Affine
        >>> g = Grid(np.zeros((10, 10), np.uint8), Affine(1, 0, 0, 0, -1, 10))
        >>> s = PathProblem(g, (0.5, 0.5), (9.5, 0.5), waypoints=1).search()  # D = 9 m
        >>> s.lower.tolist(), s.upper.tolist()  # the box: x 0 … 10, y 0 … 10 around (5, 0.5)
        ([-0.5555555555555556, -0.05555555555555555], [0.5555555555555556, 1.0555555555555556])
        >>> s(np.array([[0.0, 0.0]])).tolist()  # the straight route: 9 m = 1 D
        [1.0]
        """
        scale = 1.0 if self.encoding == "columns" else self.unit
        return Search(self, scale, self.unit, self.lower / scale, self.upper / scale)

    def to_map(self, route) -> np.ndarray:
        """Cell coordinates ``(m, 2)`` to map metres ``(m, 2)``."""
        route = np.asarray(route, float)
        return np.column_stack(self.grid.to_map(route[:, 0], route[:, 1]))


@dataclass(frozen=True)
class Search:
    """:class:`PathProblem` as the optimizers see it: variables ``z = x / scale`` within
    ``lower … upper``, cost in units of ``unit`` metres; call it on a population ``(n, dim)``."""

    problem: PathProblem
    scale: float  # the problem's variable units per unit of z
    unit: float  # metres per unit of cost (:attr:`PathProblem.unit`)
    lower: np.ndarray
    upper: np.ndarray

    def __call__(self, Z) -> np.ndarray:
        return self.problem(self.to_problem(Z)) / self.unit

    def to_problem(self, Z) -> np.ndarray:
        """The problem's variables ``x`` of the search's ``z``."""
        return np.asarray(Z, float) * self.scale
