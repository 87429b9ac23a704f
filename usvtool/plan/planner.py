"""Plan a global route on a grid (the ``usvtool plan`` API): :func:`plan_route`.

Algorithms: the planners of :mod:`usvtool.plan.planners`, by name: every optimizer of
:data:`usvtool.plan.optimizers.OPTIMIZERS` (minimising the
:class:`~usvtool.plan.problem.PathProblem` cost) and every exact planner of
:data:`usvtool.plan.planners.EXACT`: ``anyangle`` (the exact any-angle shortest route,
:mod:`usvtool.plan.exact`), ``astar`` (8-connected) and those of plugins. A ``+s`` suffix
(``iwso+s``, ``astar+s``) adds route shortening (:mod:`usvtool.plan.shorten`) to the planner's
result; a ``+g`` suffix (``iwso+g``, optimizers only) runs the optimizer on the route-guided
problem of :mod:`usvtool.plan.guided` (waypoints about the stations of the exact any-angle
route, K from the route with ``waypoints="auto"``, the default there). A plugin's exact planner
takes no suffix unless it declares one (:attr:`usvtool.plan.planners.Planner.variants`).

What to plan is a :class:`PlanOptions`, which checks itself (:meth:`PlanOptions.checked`); the
answer a :class:`PlanResult`, holding the :class:`usvtool.route.Route` (write it with
:func:`usvtool.route.write_path_geojson`) and the summary the command prints.

Figures of a route: ``length_m`` (IWSO eq. 28; for a georeferenced grid the geodesic length on
the WGS84 ellipsoid), ``turns`` and ``mot`` (:mod:`usvtool.measures`), ``fitness`` (the path
problem's cost of the route, the same for every algorithm), ``planning_time_s`` (every run of
the search, and any shortening; reading the grid, validating the request and building the grid's
collision tables, about 20 ms on 500 x 500 cells and done once per grid, are not included),
``collision_free`` (the exact check of :mod:`usvtool.collision` on the written coordinates)
and ``attempt`` (the optimizer run that gave the route, :func:`usvtool.plan.planners.optimize`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from usvtool import measures
from usvtool.collision import check_point, is_collision_free
from usvtool.errors import UsvError
from usvtool.grid import Grid
from usvtool.plan import guided
from usvtool.plan.planners import Planner, Request, resolve
from usvtool.plan.problem import ENCODINGS, PathProblem
from usvtool.route import Route, route_length


@dataclass
class PlanOptions:
    """Everything :func:`plan_route` can be told (the ``usvtool plan`` options)."""

    algo: str = "iwso"  # a planners.names() entry, optionally with the suffix +s or +g
    pop: int = 50  # agents (optimizers)
    iters: int = 300  # iterations (optimizers)
    seed: int | None = 0
    waypoints: int | str | None = None  # free waypoints: None = 3 (+g: "auto", from the route)
    encoding: str = "waypoints"  # or "columns" (ISSA)
    params: dict = field(default_factory=dict)  # optimizer parameters
    turn_weight: float = 1.0  # weight of the ISSA turning energy in the cost
    attempts: int = 1  # optimizer runs at most, until the best route is collision-free
    timing: bool = True  # False: planning_time_s is None (byte-identical outputs per seed)

    def checked(self) -> tuple[Planner, int | str]:
        """The planner ``algo`` names and the free waypoints, every option checked: the
        algorithm (:func:`usvtool.plan.planners.resolve`), the encoding, the waypoints, the
        attempts and the optimizer's parameters (name, type and range); :class:`UsvError`."""
        planner = resolve(self.algo)
        self.check_encoding(planner)
        waypoints = self.free_waypoints(planner)
        self.check_attempts()
        planner.check_params(self.params or {})
        return planner, waypoints

    def check_encoding(self, planner: Planner) -> None:
        """An encoding of :data:`ENCODINGS`; a ``+g`` variant has its own."""
        if self.encoding not in ENCODINGS:
            raise UsvError(f"unknown encoding {self.encoding!r} (known: {', '.join(ENCODINGS)})")
        if planner.guided and self.encoding != "waypoints":
            raise UsvError(f"{self.algo!r}: {guided.SUFFIX} has its own encoding, "
                           f"not {self.encoding!r}")  # fmt: skip

    def free_waypoints(self, planner: Planner) -> int | str:
        """``waypoints``, or the planner's default: an integer >= 1, or ``auto`` for ``+g``."""
        waypoints = planner.default_waypoints if self.waypoints is None else self.waypoints
        if waypoints == guided.AUTO and not planner.guided:
            raise UsvError(f"waypoints {guided.AUTO!r} is for the {guided.SUFFIX} variants")
        if waypoints != guided.AUTO and (not isinstance(waypoints, int) or waypoints < 1):
            raise UsvError(f"waypoints must be an integer >= 1 or {guided.AUTO!r}, "
                           f"not {waypoints!r}")  # fmt: skip
        return waypoints

    def check_attempts(self) -> None:
        if self.attempts < 1:
            raise UsvError(f"attempts must be >= 1, not {self.attempts}")


@dataclass
class PlanResult:
    """A planned route and the request that gave it."""

    route: Route
    start: tuple[float, float]  # map metres, as asked
    goal: tuple[float, float]
    options: PlanOptions

    def summary(self) -> dict:
        """The plan summary: ``start``, ``goal``, ``points`` and the route's figures (the CLI
        adds ``output`` and ``grid`` in front)."""
        return {
            "start": list(self.start),
            "goal": list(self.goal),
            "points": len(self.route.points),
            **self.route.figures(),
        }


def plan_route(grid: Grid, start, goal, options: PlanOptions | None = None) -> PlanResult:
    """Plan a route from ``start`` to ``goal`` (map metres) as ``options`` say.

    An optimizer runs up to ``options.attempts`` times (:func:`usvtool.plan.planners.optimize`)
    until its best route is collision-free; the exact planners run once.

    Raises :class:`UsvError` for bad options (:meth:`PlanOptions.checked`), a start or goal
    outside the grid or touching an obstacle or margin cell, a start and goal within one cell
    of each other, or no navigable connection between them.
    """
    opts = options or PlanOptions()
    planner, waypoints = opts.checked()
    start_c, goal_c = check_ends(grid, start, goal)
    problem = PathProblem(grid, tuple(start), tuple(goal), opts.encoding,
                          planner.problem_waypoints(waypoints),
                          turn_weight=opts.turn_weight)  # fmt: skip
    t0 = time.perf_counter()
    planned = planner.plan(Request(problem, start_c, goal_c, opts, waypoints))
    elapsed = time.perf_counter() - t0
    cells = planned.cells
    points = problem.to_map(cells)
    route = Route(
        points=points,
        algorithm=opts.algo,
        parameters=planned.parameters,
        seed=opts.seed if planner.seeded else None,
        length_m=route_length(grid, points),
        turns=int(measures.turns(points)),
        mot=float(measures.mot(points)),
        fitness=float(problem.cost(cells[None], exact=True)[0]),
        planning_time_s=elapsed if opts.timing else None,
        collision_free=is_collision_free(grid, points, problem.checker),
        convergence=planned.convergence,
        attempt=planned.attempt,
    )
    start = tuple(float(v) for v in start)
    goal = tuple(float(v) for v in goal)
    return PlanResult(route, start, goal, opts)


def check_ends(grid: Grid, start, goal) -> tuple[tuple[float, float], tuple[float, float]]:
    """Cell coordinates of ``start`` and ``goal`` (map metres), or :class:`UsvError`.

    Each must lie in the grid and touch no blocked cell, they must be at least one cell apart,
    and a navigable route must join them.
    """
    start_c = check_point(grid, start, "start")
    goal_c = check_point(grid, goal, "goal")
    _check_apart(grid, start_c, goal_c)
    _check_connected(grid, start_c, goal_c)
    return start_c, goal_c


def _check_apart(grid: Grid, start, goal) -> None:
    """Refuse a start and goal within one cell of each other: in the same cell, or less than one
    cell side apart. There is no route to plan, and the figures of one would be meaningless (a
    length of 0 with turns, a mot up to pi)."""
    (c0, r0), (c1, r1) = start, goal
    gap = math.hypot(c1 - c0, r1 - r0)
    same_cell = (math.floor(c0), math.floor(r0)) == (math.floor(c1), math.floor(r1))
    if same_cell or gap < 1.0:
        size = grid.cell_size
        raise UsvError(
            f"start and goal are within one cell of each other ({gap * size:.2f} m apart, "
            f"cells of {size:g} m): give a goal at least one cell from the start"
        )


def _check_connected(grid: Grid, start, goal) -> None:
    """Refuse a request whose start and goal lie in different navigable regions."""
    if grid.region_at(*start) != grid.region_at(*goal):
        raise UsvError("no navigable connection between start and goal")
