"""Global path planning on the bundled charts' routes of `make report`, over several seeds.

For each chart (the grids `make report` writes to build/grids/, the start and goal of the route
matrix of pipelines/report.yaml, read by usvtool.pipeline) and optimizer: the collision-free
rate over N seeds, and over the collision-free routes the median length relative to the
any-angle optimum and the median planning time (all runs of a seed). `make report` plans one
seed; this shows how typical that seed's outcome is. With ``--attempts N`` each seed runs the
optimizer up to N times until its route is collision-free (``usvtool plan --attempts``), and
``runs`` gives the mean number of runs.

Usage: python benchmarks/bench_charts.py [--seeds 10] [--charts us5ma12m,grid50]
       [--algos ssa,issa] [--pop 50] [--iters 300] [--waypoints 3] [--attempts 1]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from usvtool.geodesy import WGS84, transformer
from usvtool.grid import read_grid
from usvtool.pipeline import Ends, load
from usvtool.plan.optimizers import OPTIMIZERS
from usvtool.plan.planner import PlanOptions, plan_route

ROOT = Path(__file__).resolve().parent.parent
GRIDS = ROOT / "build" / "grids"


def bundled_ends() -> dict[str, Ends]:
    """The start and goal of each chart of the bundled route matrix (pipelines/report.yaml)."""
    return load().routes["report"].ends


def map_points(grid, ends: Ends) -> tuple[tuple[float, float], tuple[float, float]]:
    """The start and goal in the grid's map metres (lon/lat ends projected to its CRS)."""
    points = [ends.start, ends.goal]
    if ends.frame == "lonlat":
        to_map = transformer(WGS84, grid.crs)
        points = [to_map.transform(*p) for p in points]
    start, goal = (tuple(float(v) for v in p) for p in points)
    return start, goal


def bundled_case(name: str):
    """``(grid, start, goal)`` of a bundled chart's route (its grid from charts/, else from
    build/grids/ where `make report` writes it), or None if there is no such grid."""
    for folder in (ROOT / "charts", GRIDS):
        if (folder / f"{name}.tif").exists():
            grid = read_grid(folder / f"{name}.tif")
            return (grid, *map_points(grid, bundled_ends()[name]))
    return None


def main() -> None:
    ends = bundled_ends()
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--charts", default="us5ma12m,head_of_passes,grid20,grid50")
    ap.add_argument("--algos", default=",".join(OPTIMIZERS))
    ap.add_argument("--pop", type=int, default=50)
    ap.add_argument("--iters", type=int, default=300)
    ap.add_argument("--waypoints", type=int, default=3)
    ap.add_argument("--attempts", type=int, default=1)
    args = ap.parse_args()
    for chart in args.charts.split(","):
        path = GRIDS / f"{chart}.tif"
        if chart not in ends or not path.exists():
            sys.exit(f"bench_charts: no route or no grid for {chart!r} (run `make report` first)")
        grid = read_grid(path)
        start, goal = map_points(grid, ends[chart])
        optimum = plan_route(grid, start, goal, PlanOptions("anyangle")).route.length_m
        print(f"\n{chart}: {grid.width} x {grid.height} cells of {grid.cell_size:g} m, any-angle "
              f"optimum {optimum:.1f} m; {args.seeds} seeds, {args.pop} x {args.iters}, "
              f"{args.waypoints} waypoints, at most {args.attempts} run(s)")  # fmt: skip
        print(f"{'algorithm':10} {'free':>5} {'len/opt':>8} {'time s':>7} {'runs':>5}  free seeds")
        for algo in args.algos.split(","):
            routes = [
                plan_route(
                    grid,
                    start,
                    goal,
                    PlanOptions(
                        algo, args.pop, args.iters, seed, args.waypoints, attempts=args.attempts
                    ),
                ).route
                for seed in range(args.seeds)
            ]
            free = [r for r in routes if r.collision_free]
            ratio = np.median([r.length_m for r in free]) / optimum if free else float("nan")
            seconds = np.median([r.planning_time_s for r in routes])
            runs = np.mean([r.attempt for r in routes])
            seeds = ",".join(str(r.seed) for r in free)
            print(
                f"{algo:10} {len(free) / len(routes):5.0%} {ratio:8.4f} {seconds:7.3f} "
                f"{runs:5.2f}  {seeds}"
            )


if __name__ == "__main__":
    main()
