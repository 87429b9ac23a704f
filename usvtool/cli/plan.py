"""``usvtool plan``: a global route on a navigation grid, written as a path GeoJSON."""

from __future__ import annotations

import logging

import click

from usvtool.cli.options import (
    NON_NEGATIVE,
    emit,
    max_memory_option,
    output_option,
    param_option,
    seed_option,
    summary_option,
    write_summary,
)
from usvtool.plan import planners
from usvtool.plan.guided import AUTO
from usvtool.plan.problem import ENCODINGS

log = logging.getLogger(__name__)


class RouteCollides(click.ClickException):
    """The best route collides: it is written all the same, and the command exits with 3."""

    exit_code = 3


def _algo(ctx, param, value: str) -> str:
    """A name of the planner registry (a usage error); a variant its base has not got is the
    planner's to refuse (exit 1)."""
    names = planners.names()
    if planners.split_algorithm(value)[0] not in names:
        raise click.BadParameter(
            f"{value!r} is not one of {', '.join(names)} (each also with the suffix "
            f"{' or '.join(planners.VARIANTS)})"
        )
    return value


def _waypoints(ctx, param, value: str | None) -> int | str | None:
    """An integer >= 1, ``auto`` (+g: K from the exact route), or None (the default)."""
    if value is None or value == AUTO:
        return value
    try:
        k = int(value)
    except ValueError:
        k = 0
    if k < 1:
        raise click.BadParameter(f"{value!r} is neither an integer >= 1 nor {AUTO!r}")
    return k


@click.command()
@click.argument("grid_path", metavar="GRID.tif", type=click.Path(dir_okay=False))
@click.option("--start", nargs=2, type=float, metavar="X Y", help="Start in map metres.")
@click.option("--goal", nargs=2, type=float, metavar="X Y", help="Goal in map metres.")
@click.option(
    "--start-lonlat", nargs=2, type=float, metavar="LON LAT", help="Start (georeferenced grid)."
)
@click.option(
    "--goal-lonlat", nargs=2, type=float, metavar="LON LAT", help="Goal (georeferenced grid)."
)
@click.option(
    "--algo",
    default="iwso",
    show_default=True,
    callback=_algo,
    help=f"One of {', '.join(planners.names())}; add +s for route shortening, +g (optimizers) "
    "for the route-guided variant.",
)
@click.option("--pop", type=click.IntRange(min=2), default=50, show_default=True, help="Agents.")
@click.option(
    "--iters", type=click.IntRange(min=1), default=300, show_default=True, help="Iterations."
)
@seed_option
@click.option(
    "--waypoints",
    callback=_waypoints,
    metavar="K|auto",
    help="Free waypoints (waypoints encoding; default 3), or for +g 'auto' (its default): "
    "one per bend of the exact route that matters.",
)
@click.option(
    "--encoding",
    type=click.Choice(ENCODINGS),
    default="waypoints",
    show_default=True,
    help="Route encoding: free waypoints, or one cell per grid column (ISSA).",
)
@param_option("An optimizer parameter (repeatable).")
@click.option(
    "--turn-weight",
    type=NON_NEGATIVE,
    default=1.0,
    show_default=True,
    help="Weight of the ISSA turning energy in the cost.",
)
@click.option(
    "--attempts",
    type=click.IntRange(min=1),
    default=1,
    show_default=True,
    help="Optimizer runs at most: a new run (a seed derived from --seed) while the best "
    "route collides.",
)
@click.option(
    "--timing/--no-timing",
    default=True,
    show_default=True,
    help="Record planning_time_s (--no-timing writes null: byte-identical outputs per seed).",
)
@click.option(
    "--allow-collision",
    is_flag=True,
    help="Exit 0 even when the best route collides (it is written either way, flagged "
    "collision_free false): for studies of the faithful algorithms' failures.",
)
@output_option("Path GeoJSON to write.")
@max_memory_option
@summary_option
def plan(
    grid_path: str,
    start,
    goal,
    start_lonlat,
    goal_lonlat,
    algo: str,
    pop: int,
    iters: int,
    seed: int,
    waypoints: int | str | None,
    encoding: str,
    params: dict,
    turn_weight: float,
    attempts: int,
    timing: bool,
    allow_collision: bool,
    output: str,
    max_memory: int | None,
    summary_path: str | None,
) -> None:
    """Plan a route from --start to --goal on GRID.tif and write it to -o as GeoJSON.

    \b
    Exit status:
      0  the route is written and collision-free (with --allow-collision: colliding or not)
      1  bad input: one line on stderr, nothing written
      2  a usage error (an unknown option or algorithm, a missing --goal, ...)
      3  the best route found collides: it is written all the same (collision_free false,
         with the --summary), and one line on stderr says so
    """
    from usvtool.atomic import check_outputs, staged
    from usvtool.errors import UsvError
    from usvtool.grid import read_grid
    from usvtool.plan.memory import check_grid, planning
    from usvtool.plan.planner import PlanOptions, check_ends, plan_route
    from usvtool.route import write_path_geojson

    check_outputs([("-o", output), ("--summary", summary_path)])
    grid = read_grid(grid_path, lambda width, height: check_grid(grid_path, width, height,
                                                                 max_memory))  # fmt: skip
    start = _point(grid, grid_path, "start", start, start_lonlat)
    goal = _point(grid, grid_path, "goal", goal, goal_lonlat)
    try:
        check_ends(grid, start, goal)  # errors name the grid (plan_route's cannot)
    except UsvError as exc:
        raise UsvError(f"{grid_path}: {exc}") from None
    options = PlanOptions(
        algo=algo, pop=pop, iters=iters, seed=seed, waypoints=waypoints, encoding=encoding,
        params=params, turn_weight=turn_weight, attempts=attempts, timing=timing,
    )  # fmt: skip
    with planning(grid_path, grid.width, grid.height):
        result = plan_route(grid, start, goal, options)
    summary = {"output": output, "grid": grid_path, **result.summary()}
    with staged(output, summary_path) as (path_tmp, summary_tmp):  # the route renamed last
        write_path_geojson(path_tmp, result.route, grid)
        if summary_tmp:
            write_summary(summary_tmp, summary)
    emit(summary)
    if not result.route.collision_free:
        message = (
            f"{grid_path}: the best route {algo} found in {attempts} run(s) touches obstacle or "
            f"margin cells (written to {output} with collision_free false); try more --attempts, "
            "--waypoints or --iters, or another algorithm"
        )
        if not allow_collision:
            raise RouteCollides(f"{message}, or --allow-collision to accept it (exit 0)")
        log.warning(message)


def _point(grid, grid_path: str, name: str, xy, lonlat) -> tuple[float, float]:
    """The map coordinates given by ``--NAME X Y`` or ``--NAME-lonlat LON LAT`` (exactly one)."""
    from usvtool.errors import UsvError

    if (xy is None) == (lonlat is None):
        raise click.UsageError(f"give exactly one of --{name} X Y and --{name}-lonlat LON LAT")
    if xy is not None:
        x, y = float(xy[0]), float(xy[1])
        if _reads_as_lonlat(grid, x, y):
            left, bottom, right, top = (_fixed(v, 2) for v in grid.bounds)
            lonlat_text = f"{_fixed(x, 6)} {_fixed(y, 6)}"
            raise UsvError(
                f"{grid_path}: --{name} {lonlat_text} lies far outside the grid (x {left}..{right},"
                f" y {bottom}..{top} map metres) and reads as lon/lat: use --{name}-lonlat "
                f"{lonlat_text}"
            )
        return x, y
    if grid.crs is None:
        raise UsvError(f"--{name}-lonlat: {grid_path} has no CRS; give --{name} X Y in metres")
    from usvtool.geodesy import lonlat_to_map

    return lonlat_to_map(grid.crs, *lonlat)


def _reads_as_lonlat(grid, x: float, y: float) -> bool:
    """Whether map coordinates ``x, y`` look like WGS84 lon/lat given in their place: the grid
    is projected, they fit lon/lat ranges and lie farther outside the grid than its own size."""
    if grid.crs is None or getattr(grid.crs, "is_geographic", False):
        return False
    if not (-180.0 <= x <= 180.0 and -90.0 <= y <= 90.0):
        return False
    left, bottom, right, top = grid.bounds
    gap = max(left - x, x - right, bottom - y, y - top)
    return gap > max(right - left, top - bottom)


def _fixed(value: float, digits: int) -> str:
    """A coordinate for messages: ``digits`` decimals (6 for degrees, about 0.1 m; 2 for
    metres), no exponent, no trailing zeros."""
    text = f"{value:.{digits}f}".rstrip("0").rstrip(".")
    return "0" if text == "-0" else text
