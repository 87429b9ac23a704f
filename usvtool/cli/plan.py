"""``usvtool plan``: a global route on a navigation grid, written as a path GeoJSON."""

from __future__ import annotations

import logging

import click

from usvtool.cli.options import (
    NON_NEGATIVE,
    emit,
    output_option,
    param_option,
    seed_option,
    summary_option,
    write_summary,
)
from usvtool.plan.planner import algorithm_names
from usvtool.plan.problem import ENCODINGS
from usvtool.plan.shorten import SUFFIX

log = logging.getLogger(__name__)


def _algo(ctx, param, value: str) -> str:
    names = algorithm_names()
    if value.removesuffix(SUFFIX) not in names:
        raise click.BadParameter(
            f"{value!r} is not one of {', '.join(names)} (each also with the suffix {SUFFIX})"
        )
    return value


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
    help=f"One of {', '.join(algorithm_names())}; add {SUFFIX} for route shortening.",
)
@click.option("--pop", type=click.IntRange(min=2), default=50, show_default=True, help="Agents.")
@click.option(
    "--iters", type=click.IntRange(min=1), default=300, show_default=True, help="Iterations."
)
@seed_option
@click.option(
    "--waypoints",
    type=click.IntRange(min=1),
    default=3,
    show_default=True,
    help="Free waypoints (waypoints encoding).",
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
@output_option("Path GeoJSON to write.")
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
    waypoints: int,
    encoding: str,
    params: dict,
    turn_weight: float,
    attempts: int,
    timing: bool,
    output: str,
    summary_path: str | None,
) -> None:
    """Plan a route from --start to --goal on GRID.tif and write it to -o as GeoJSON."""
    from usvtool.atomic import check_outputs, staged
    from usvtool.errors import UsvError
    from usvtool.grid import read_grid
    from usvtool.plan.planner import PlanOptions, check_ends, plan_route
    from usvtool.route import write_path_geojson

    check_outputs([("-o", output), ("--summary", summary_path)])
    grid = read_grid(grid_path)
    start = _point(grid, grid_path, "start", start, start_lonlat)
    goal = _point(grid, grid_path, "goal", goal, goal_lonlat)
    try:
        check_ends(grid, start, goal)  # errors name the grid (plan_route's cannot)
    except UsvError as exc:
        raise UsvError(f"{grid_path}: {exc}") from None
    options = PlanOptions(
        algo=algo, pop=pop, iters=iters, seed=seed, waypoints=waypoints, encoding=encoding,
        params=params, turn_weight=turn_weight, attempts=attempts, timing=timing,
    )
    result = plan_route(grid, start, goal, options)
    if not result.route.collision_free:
        log.warning(
            "%s: the best route %s found in %d run(s) touches obstacle or margin cells (written "
            "with collision_free false); try more --attempts, --waypoints or --iters, or another "
            "algorithm",
            grid_path, algo, attempts,
        )
    summary = {"output": output, "grid": grid_path, **result.summary()}
    with staged(output, summary_path) as (path_tmp, summary_tmp):  # the route renamed last
        write_path_geojson(path_tmp, result.route, grid)
        if summary_tmp:
            write_summary(summary_tmp, summary)
    emit(summary)


def _point(grid, grid_path: str, name: str, xy, lonlat) -> tuple[float, float]:
    """The map coordinates given by ``--NAME X Y`` or ``--NAME-lonlat LON LAT`` (exactly one)."""
    from usvtool.errors import UsvError

    if (xy is None) == (lonlat is None):
        raise click.UsageError(f"give exactly one of --{name} X Y and --{name}-lonlat LON LAT")
    if xy is not None:
        return float(xy[0]), float(xy[1])
    if grid.crs is None:
        raise UsvError(f"--{name}-lonlat: {grid_path} has no CRS; give --{name} X Y in metres")
    from usvtool.geodesy import lonlat_to_map

    return lonlat_to_map(grid.crs, *lonlat)
