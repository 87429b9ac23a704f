"""Plan a global route on a grid (the ``usvtool plan`` API): :func:`plan_route`.

Algorithms: every optimizer of :data:`usvtool.plan.optimizers.OPTIMIZERS` (minimising the
:class:`~usvtool.plan.problem.PathProblem` cost), ``astar`` (8-connected) and ``anyangle`` (the
exact any-angle shortest route, :mod:`usvtool.plan.exact`). A ``+s`` suffix (``iwso+s``,
``astar+s``) adds route shortening (:mod:`usvtool.plan.shorten`) to the planner's result; a
``+g`` suffix (``iwso+g``, optimizers only) runs the optimizer on the route-guided problem of
:mod:`usvtool.plan.guided` (waypoints about the stations of the exact any-angle route, K from
the route with ``waypoints="auto"``, the default there).

What to plan is a :class:`PlanOptions`; the answer a :class:`PlanResult`, holding the
:class:`usvtool.route.Route` (write it with :func:`usvtool.route.write_path_geojson`) and the
summary the command prints.

Figures of a route: ``length_m`` (IWSO eq. 28; for a georeferenced grid the geodesic length on
the WGS84 ellipsoid), ``turns`` and ``mot`` (:mod:`usvtool.metrics`), ``fitness`` (the path
problem's cost of the route, the same for every algorithm), ``planning_time_s`` (every run of
the search, and any shortening; reading the grid, validating the request and building the grid's
collision tables, about 20 ms on 500 x 500 cells and done once per grid, are not included),
``collision_free`` (the exact check of :mod:`usvtool.collision` on the written coordinates)
and ``attempt`` (the optimizer run that gave the route, :func:`_optimize`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from usvtool import metrics
from usvtool.collision import check_point, is_collision_free
from usvtool.errors import UsvError
from usvtool.grid import Grid
from usvtool.plan import exact, guided
from usvtool.plan.problem import ENCODINGS, PathProblem
from usvtool.plan.shorten import SUFFIX, shorten
from usvtool.route import Route, route_length

EXACT = ("astar", "anyangle")
VARIANTS = (SUFFIX, guided.SUFFIX)  # +s (shortening), +g (route-guided)
DEFAULT_WAYPOINTS = 3  # free waypoints of the faithful encoding when none are given


def algorithm_names() -> list[str]:
    """Every accepted ``algo`` name, without the ``+s`` and ``+g`` variants."""
    from usvtool.plan.optimizers import OPTIMIZERS

    return [*OPTIMIZERS, *EXACT]


def split_algorithm(algo: str) -> tuple[str, str]:
    """``(base, variant)`` of an ``algo`` name: ``("iwso", "+g")``, ``("astar", "")``.

    >>> split_algorithm("iwso+g"), split_algorithm("anyangle+s"), split_algorithm("gwo")
    (('iwso', '+g'), ('anyangle', '+s'), ('gwo', ''))
    """
    for suffix in VARIANTS:
        if algo.endswith(suffix):
            return algo[: -len(suffix)], suffix
    return algo, ""


@dataclass
class PlanOptions:
    """Everything :func:`plan_route` can be told (the ``usvtool plan`` options)."""

    algo: str = "iwso"  # an algorithm_names() entry, optionally with the suffix +s or +g
    pop: int = 50  # agents (optimizers)
    iters: int = 300  # iterations (optimizers)
    seed: int | None = 0
    waypoints: int | str | None = None  # free waypoints: None = 3 (+g: "auto", from the route)
    encoding: str = "waypoints"  # or "columns" (ISSA)
    params: dict = field(default_factory=dict)  # optimizer parameters
    turn_weight: float = 1.0  # weight of the ISSA turning energy in the cost
    attempts: int = 1  # optimizer runs at most, until the best route is collision-free
    timing: bool = True  # False: planning_time_s is None (byte-identical outputs per seed)


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

    An optimizer runs up to ``options.attempts`` times (:func:`_optimize`) until its best route
    is collision-free; the exact planners run once.

    Raises :class:`UsvError` for an unknown algorithm, a start or goal outside the grid or
    touching an obstacle or margin cell, a start and goal within one cell of each other, or no
    navigable connection between them.
    """
    opts = options or PlanOptions()
    algo, encoding, waypoints, attempts = opts.algo, opts.encoding, opts.waypoints, opts.attempts
    seed, turn_weight = opts.seed, opts.turn_weight
    base, variant = split_algorithm(algo)
    shortened, guide = variant == SUFFIX, variant == guided.SUFFIX
    if base not in algorithm_names():
        known = ", ".join(algorithm_names())
        raise UsvError(f"unknown algorithm {algo!r} (known: {known}, each also with "
                       f"{' or '.join(VARIANTS)})")  # fmt: skip
    if guide and base in EXACT:
        raise UsvError(f"{algo!r}: {guided.SUFFIX} is a variant of the optimizers, not of {base}")
    if encoding not in ENCODINGS:
        raise UsvError(f"unknown encoding {encoding!r} (known: {', '.join(ENCODINGS)})")
    if guide and encoding != "waypoints":
        raise UsvError(f"{algo!r}: {guided.SUFFIX} has its own encoding, not {encoding!r}")
    if waypoints is None:
        waypoints = guided.AUTO if guide else DEFAULT_WAYPOINTS
    if waypoints == guided.AUTO and not guide:
        raise UsvError(f"waypoints {guided.AUTO!r} is for the {guided.SUFFIX} variants")
    if waypoints != guided.AUTO and (not isinstance(waypoints, int) or waypoints < 1):
        raise UsvError(f"waypoints must be an integer >= 1 or {guided.AUTO!r}, not {waypoints!r}")
    if attempts < 1:
        raise UsvError(f"attempts must be >= 1, not {attempts}")
    start_c, goal_c = check_ends(grid, start, goal)
    problem = PathProblem(
        grid, tuple(start), tuple(goal), encoding,
        1 if guide else waypoints, turn_weight=turn_weight,
    )  # fmt: skip
    checker = problem.checker
    convergence: list[float] = []
    attempt = None
    t0 = time.perf_counter()
    if base == "astar":
        cells = exact.astar(grid.blocked, start_c, goal_c)
        parameters: dict = {}
    elif base == "anyangle":
        cells = exact.any_angle(checker, grid.blocked, start_c, goal_c)
        parameters = {"delta_cells": exact.DELTA}
    elif guide:
        route = exact.any_angle(checker, grid.blocked, start_c, goal_c)
        station = guided.stations(checker, route, waypoints)
        clear = guided.clear_of_corners(checker, station)
        searched = (guided.GuidedProblem(problem, station) if clear is None
                    else guided.GuidedProblem(problem, clear, margin=True))  # fmt: skip
        if searched.waypoints:
            cells, convergence, parameters, attempt = _optimize(
                searched, base, opts.pop, opts.iters, seed, opts.params or {}, attempts
            )
        else:  # a straight station route: nothing to search
            cells, parameters = searched.station, {}
        cells, kept = guided.settle(route, searched.station, cells)
        if not is_collision_free(grid, problem.to_map(cells), checker):
            cells, kept = searched.station, True  # free in cells, not once in map metres
        parameters = {**parameters, "encoding": "guided", "turn_weight": turn_weight,
                      "waypoints": searched.waypoints, "guide_vertices": len(route),
                      "station_route": kept}  # fmt: skip
    else:
        cells, convergence, parameters, attempt = _optimize(
            problem, base, opts.pop, opts.iters, seed, opts.params or {}, attempts
        )
        parameters = {**parameters, "encoding": encoding, "turn_weight": turn_weight}
        if encoding == "waypoints":
            parameters["waypoints"] = waypoints
    if cells is None:  # connectivity was checked: an exact planner must find a route
        raise UsvError(f"{base}: no route found between start and goal")
    if shortened:
        cells = shorten(checker, cells)
        parameters = {**parameters, "shorten": True}
    elapsed = time.perf_counter() - t0
    points = problem.to_map(cells)
    route = Route(
        points=points,
        algorithm=algo,
        parameters=parameters,
        seed=seed if base not in EXACT else None,
        length_m=route_length(grid, points),
        turns=int(metrics.turns(points)),
        mot=float(metrics.mot(points)),
        fitness=float(problem.cost(cells[None], exact=True)[0]),
        planning_time_s=elapsed if opts.timing else None,
        collision_free=is_collision_free(grid, points, checker),
        convergence=convergence,
        attempt=attempt,
    )
    start = tuple(float(v) for v in start)
    goal = tuple(float(v) for v in goal)
    return PlanResult(route, start, goal, opts)


def _optimize(
    problem: PathProblem | guided.GuidedProblem, base: str, pop: int, iters: int,
    seed: int | None, params: dict, attempts: int,
) -> tuple[np.ndarray, list[float], dict, int]:
    """Minimise ``problem`` with optimizer ``base``: up to ``attempts`` independent runs, stopping
    at the first whose best route is collision-free (else keeping the lowest-cost route).

    Why restarts: a population-based search converges on one basin per run, and on a hard
    chart a faithful optimizer's run can end in a colliding basin (docs/planning.md has the
    rates). Independent runs are the standard remedy (MoveIt's planning attempts; multi-start
    in the metaheuristics literature); they leave every run the published algorithm. Run 1
    uses ``seed`` itself, so ``attempts=1`` and the first attempt give the same route as
    before; run ``k`` > 1 uses child ``k - 2`` of ``SeedSequence(seed).spawn``, so the result
    depends on the seed alone.

    Returns the route's cells, its run's convergence (metres), the optimizer's parameters with
    ``attempts``, and the 1-based number of the run that gave the route.
    """
    from usvtool.plan.optimizers import make_optimizer

    search = problem.search()
    children = np.random.SeedSequence(seed).spawn(attempts - 1)
    seeds = [seed, *(np.random.default_rng(child) for child in children)]
    best = None
    for attempt, run_seed in enumerate(seeds, start=1):
        try:
            optimizer = make_optimizer(base, pop, iters, run_seed, **params)
        except ValueError as exc:
            raise UsvError(str(exc)) from None
        result = optimizer.minimize(search, search.lower, search.upper)
        cells = problem.decode(search.to_problem(result.x))[0]
        fitness = float(problem.cost(cells[None], exact=True)[0])
        run = (fitness, cells, (result.history * search.unit).tolist(), result.params, attempt)
        if not problem.checker.collides(cells[:-1], cells[1:]).any():
            best = run  # free: kept even if a colliding run cost less (a free detour > S)
            break
        if best is None or fitness < best[0]:
            best = run
    _, cells, convergence, parameters, attempt = best
    return cells, convergence, {**parameters, "attempts": attempts}, attempt


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
