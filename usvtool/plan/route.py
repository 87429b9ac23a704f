"""Plan a global route on a grid and write it as a path GeoJSON (the ``usvtool plan`` API).

Algorithms: every optimizer of :data:`usvtool.plan.optimizers.OPTIMIZERS` (minimising the
:class:`~usvtool.plan.problem.PathProblem` cost), ``astar`` (8-connected) and ``anyangle`` (the
exact any-angle shortest route, :mod:`usvtool.plan.exact`). A ``+s`` suffix (``iwso+s``,
``astar+s``) adds route shortening (:mod:`usvtool.plan.shorten`) to the planner's result.

Figures of a route: ``length_m`` (IWSO eq. 28; for a georeferenced grid the geodesic length on
the WGS84 ellipsoid), ``turns`` and ``mot`` (:mod:`usvtool.metrics`), ``fitness`` (the path
problem's cost of the route, the same for every algorithm), ``planning_time_s`` (every run of
the search, and any shortening; reading the grid, validating the request and building the grid's
collision tables, about 20 ms on 500 x 500 cells and done once per grid, are not included),
``collision_free`` (the exact check of :mod:`usvtool.plan.raster` on the written coordinates)
and ``attempt`` (the optimizer run that gave the route, :func:`_optimize`).
"""

from __future__ import annotations

import json
import os
import time
from dataclasses import dataclass, field

import numpy as np

from usvtool import metrics
from usvtool.errors import UsvError
from usvtool.grid import MARGIN, OBSTACLE, Grid
from usvtool.plan import exact
from usvtool.plan.problem import ENCODINGS, PathProblem
from usvtool.plan.raster import EPS, SegmentChecker
from usvtool.plan.shorten import SUFFIX, shorten

EXACT = ("astar", "anyangle")


def algorithm_names() -> list[str]:
    """Every accepted ``algo`` name, without the ``+s`` variants."""
    from usvtool.plan.optimizers import OPTIMIZERS

    return [*OPTIMIZERS, *EXACT]


@dataclass
class Route:
    """A planned route: map coordinates ``points`` ``(m, 2)`` and its figures."""

    points: np.ndarray
    algorithm: str
    parameters: dict
    seed: int | None
    length_m: float
    turns: int
    mot: float
    fitness: float
    planning_time_s: float | None  # None: not recorded (--no-timing)
    collision_free: bool
    convergence: list[float] = field(default_factory=list)
    attempt: int | None = None  # the optimizer run that gave the route (None: exact planner)

    def figures(self) -> dict:
        """The route's figures (the GeoJSON properties and the CLI summary share them)."""
        return {
            "algorithm": self.algorithm,
            "parameters": self.parameters,
            "seed": self.seed,
            "length_m": self.length_m,
            "turns": self.turns,
            "mot": self.mot,
            "fitness": self.fitness,
            "planning_time_s": self.planning_time_s,
            "collision_free": self.collision_free,
            "convergence": self.convergence,
            "attempt": self.attempt,
        }


def plan_route(
    grid: Grid,
    start,
    goal,
    algo: str = "iwso",
    pop: int = 50,
    iters: int = 300,
    seed: int | None = 0,
    waypoints: int = 3,
    encoding: str = "waypoints",
    params: dict | None = None,
    turn_weight: float = 1.0,
    attempts: int = 1,
) -> Route:
    """Plan a route from ``start`` to ``goal`` (map metres) with algorithm ``algo``.

    An optimizer runs up to ``attempts`` times (:func:`_optimize`) until its best route is
    collision-free; the exact planners run once.

    Raises :class:`UsvError` for an unknown algorithm, a start or goal outside the grid or
    touching an obstacle or margin cell, or no navigable connection between them.
    """
    base, shortened = (algo[: -len(SUFFIX)], True) if algo.endswith(SUFFIX) else (algo, False)
    if base not in algorithm_names():
        known = ", ".join(algorithm_names())
        raise UsvError(f"unknown algorithm {algo!r} (known: {known}, each also with {SUFFIX})")
    if encoding not in ENCODINGS:
        raise UsvError(f"unknown encoding {encoding!r} (known: {', '.join(ENCODINGS)})")
    if encoding == "waypoints" and waypoints < 1:
        raise UsvError(f"waypoints must be >= 1, not {waypoints}")
    if attempts < 1:
        raise UsvError(f"attempts must be >= 1, not {attempts}")
    start_c, goal_c = check_ends(grid, start, goal)
    problem = PathProblem(
        grid, tuple(start), tuple(goal), encoding, waypoints, turn_weight=turn_weight
    )
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
    else:
        cells, convergence, parameters, attempt = _optimize(
            problem, base, pop, iters, seed, params or {}, attempts
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
    return Route(
        points=points,
        algorithm=algo,
        parameters=parameters,
        seed=seed if base not in EXACT else None,
        length_m=route_length(grid, points),
        turns=int(metrics.turns(points)),
        mot=float(metrics.mot(points)),
        fitness=float(problem.cost(cells[None], exact=True)[0]),
        planning_time_s=elapsed,
        collision_free=is_collision_free(grid, points, checker),
        convergence=convergence,
        attempt=attempt,
    )


def _optimize(
    problem: PathProblem, base: str, pop: int, iters: int, seed: int | None, params: dict,
    attempts: int,
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


def route_length(grid: Grid, points) -> float:
    """Length in metres: geodesic (WGS84) for a georeferenced grid, planar otherwise."""
    points = np.asarray(points, float)
    if grid.crs is None:
        return float(metrics.path_length(points))
    from usvtool.chart.georef import WGS84, geodesic_length, transformer

    lon, lat = transformer(grid.crs, WGS84).transform(points[:, 0], points[:, 1])
    return geodesic_length(lon, lat)


def is_collision_free(grid: Grid, points, checker: SegmentChecker | None = None) -> bool:
    """Whether the route (map metres) stays in the grid and touches no blocked cell."""
    col, row = grid.to_cell_coords(*np.asarray(points, float).T)
    cells = np.column_stack([col, row])
    checker = checker or SegmentChecker(grid.blocked)
    try:
        hit = checker.collides(cells[:-1], cells[1:])
    except ValueError:  # leaves the grid
        return False
    return not hit.any()


def _m(value: float) -> str:
    """Metres for messages: 0.1 m resolution, no exponent, no trailing zeros (332204.3, 21)."""
    return f"{value:.1f}".rstrip("0").rstrip(".")


def write_path_geojson(path: str | os.PathLike, route: Route, grid: Grid) -> None:
    """Write ``route`` as a GeoJSON FeatureCollection holding one LineString feature, atomically.

    With a CRS the coordinates are lon/lat (RFC 7946) and ``map_coordinates`` (with ``crs``)
    holds the grid's; without one they are the grid's local metres, and ``frame`` says so.
    """
    from usvtool.atomic import jsonable, write_text

    points = np.asarray(route.points, float)
    props = route.figures()
    if grid.crs is None:
        coords = points
        props["frame"] = "local metres (no CRS): x east, y north from the grid's lower-left corner"
    else:
        from usvtool.chart.georef import WGS84, transformer

        lon, lat = transformer(grid.crs, WGS84).transform(points[:, 0], points[:, 1])
        coords = np.column_stack([lon, lat])
        props["crs"] = grid.crs.to_string()
        props["map_coordinates"] = points.tolist()
    feature = {
        "type": "Feature",
        "geometry": {"type": "LineString", "coordinates": coords.tolist()},
        "properties": props,
    }
    text = json.dumps(
        {"type": "FeatureCollection", "features": [feature]}, indent=1, default=jsonable
    )
    write_text(path, text + "\n")


def read_path_geojson(path: str | os.PathLike) -> tuple[np.ndarray, dict]:
    """The map coordinates ``(m, 2)`` and the properties of a path GeoJSON."""
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
        feature = data["features"][0] if data.get("type") == "FeatureCollection" else data
        props = feature["properties"]
        coords = props.get("map_coordinates", feature["geometry"]["coordinates"])
        return np.asarray(coords, float), props
    except (OSError, ValueError, KeyError, IndexError, TypeError) as exc:
        raise UsvError(f"{path}: not a path GeoJSON ({exc})") from None


def check_ends(grid: Grid, start, goal) -> tuple[tuple[float, float], tuple[float, float]]:
    """Cell coordinates of ``start`` and ``goal`` (map metres), or :class:`UsvError`.

    Each must lie in the grid and touch no blocked cell, and a navigable route must join them.
    """
    start_c = _check_end(grid, "start", start)
    goal_c = _check_end(grid, "goal", goal)
    _check_connected(grid, start_c, goal_c)
    return start_c, goal_c


def _check_end(grid: Grid, name: str, point) -> tuple[float, float]:
    """Cell coordinates of a start or goal that lies in the grid and touches no blocked cell."""
    x, y = (float(v) for v in point)
    left, bottom, right, top = grid.bounds
    if not (left <= x <= right and bottom <= y <= top):
        raise UsvError(
            f"{name} ({_m(x)}, {_m(y)}) is outside the grid (x {_m(left)}..{_m(right)}, "
            f"y {_m(bottom)}..{_m(top)})"
        )
    col, row = (float(v) for v in grid.to_cell_coords(x, y))
    rows = slice(max(int(np.ceil(row - 1 - EPS)), 0), int(np.floor(row + EPS)) + 1)
    cols = slice(max(int(np.ceil(col - 1 - EPS)), 0), int(np.floor(col + EPS)) + 1)
    touched = grid.cells[rows, cols]
    if (touched == OBSTACLE).any():
        raise UsvError(f"{name} ({_m(x)}, {_m(y)}) is on an obstacle")
    if (touched == MARGIN).any():
        raise UsvError(f"{name} ({_m(x)}, {_m(y)}) is in the safety margin around an obstacle")
    return col, row


def _check_connected(grid: Grid, start, goal) -> None:
    """Refuse a request whose start and goal lie in different navigable regions."""
    if grid.region_at(*start) != grid.region_at(*goal):
        raise UsvError("no navigable connection between start and goal")
