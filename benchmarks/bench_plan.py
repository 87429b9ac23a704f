"""Global path planning on env1 and env2: quality and speed of every algorithm (IWSO Table 2 form).

For each environment (500 m x 500 m, start (10, 10), goal (490, 490)) and algorithm, over N seeds:
the collision-free rate, and over the collision-free routes the median length relative to the
any-angle optimum, the median turns, mot and planning time; the paper's Table 2 figures are
printed beside (its environments are not ours: its Figure 6 is not in the text, so only the
orders of magnitude compare). Then the timings: the cost of one population of 50 routes, IWSO
with 50 agents x 300 iterations, the exact planners. With ``--base REV`` the first two also with
the collision check of git revision REV (the plain way: ``--base da8affc``, the NumPy check
before it was compiled), alternating the two per seed in one process (this machine's speed
varies by up to 2 times between processes), and how many IWSO routes are the same bit for bit.

Usage: python benchmarks/bench_plan.py [--seeds 25] [--algos iwso,iwso+s] [--envs env1,env2]
       [--pop 50] [--iters 300] [--waypoints 5] [--base da8affc] [--timings-only]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path
from unittest import mock

import numpy as np

from usvtool.collision import SegmentChecker
from usvtool.grid import read_grid
from usvtool.plan import problem as problem_module
from usvtool.plan.optimizers import OPTIMIZERS
from usvtool.plan.planner import EXACT, PlanOptions, plan_route
from usvtool.plan.problem import PathProblem

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))
CHARTS = ROOT / "charts"
START, GOAL = (10.0, 10.0), (490.0, 490.0)
# IWSO paper, Table 2: length (m), steering cost, mot, time (s)
PAPER = {
    "env1": {
        "boa": (914.530, 8, 0.591, 2.056), "gwo": (802.370, 9, 0.456, 6.564),
        "mrfo": (777.267, 11, 0.794, 1.920), "woa": (801.650, 8, 0.455, 7.037),
        "ssa": (862.133, 5, 0.628, 3.472), "wso": (847.487, 7, 0.309, 5.416),
        "iwso": (710.873, 5, 0.215, 1.247),
    },
    "env2": {
        "boa": (1144.975, 19, 3.097, 7.846), "gwo": (996.773, 11, 0.947, 2.228),
        "mrfo": (950.803, 11, 0.930, 2.256), "woa": (941.590, 11, 0.977, 3.355),
        "ssa": (959.620, 15, 2.220, 6.317), "wso": (1044.975, 11, 1.024, 5.490),
        "iwso": (927.925, 10, 0.926, 1.033),
    },
}  # fmt: skip


def median_time(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def quality(env: str, algos: list[str], args) -> None:
    grid = read_grid(CHARTS / f"{env}.tif")
    optimum = plan_route(grid, START, GOAL, PlanOptions("anyangle")).route.length_m
    print(f"\n{env}: any-angle optimum {optimum:.3f} m; {args.seeds} seeds, {args.pop} agents x "
          f"{args.iters} iterations, {args.waypoints} waypoints")  # fmt: skip
    print(f"{'algorithm':10} {'free':>5} {'len/opt':>8} {'length':>8} {'turns':>5} {'mot':>7} "
          f"{'time s':>7} | paper: {'length':>8} {'turns':>5} {'mot':>6} {'time':>6}")  # fmt: skip
    for algo in algos:
        seeds = range(1) if algo.removesuffix("+s") in EXACT else range(args.seeds)
        runs = [
            plan_route(
                grid, START, GOAL, PlanOptions(algo, args.pop, args.iters, seed, args.waypoints)
            ).route
            for seed in seeds
        ]
        free = [r for r in runs if r.collision_free]
        times = np.median([r.planning_time_s for r in runs])
        row = f"{algo:10} {len(free) / len(runs):5.0%} "
        if free:
            length = np.median([r.length_m for r in free])
            turns = np.median([r.turns for r in free])
            mot = np.median([r.mot for r in free])
            row += f"{length / optimum:8.4f} {length:8.1f} {turns:5.1f} {mot:7.3f} {times:7.3f}"
        else:
            row += f"{'-':>8} {'-':>8} {'-':>5} {'-':>7} {times:7.3f}"
        paper = PAPER[env].get(algo.removesuffix("+s"))
        if paper and not algo.endswith("+s"):
            row += " | paper: {:8.1f} {:5d} {:6.3f} {:6.3f}".format(*paper)
        print(row)


def timings(args) -> None:
    grid = read_grid(CHARTS / "env1.tif")
    checkers = {"now": SegmentChecker}
    if args.base:  # the plain way: an earlier revision's check (NumPy before 6ce2f5b)
        from revision import load_module, source_at

        source = source_at(args.base, "usvtool/collision.py")
        checkers[args.base] = load_module("old_collision", source, Path(tempfile.mkdtemp()))
        checkers[args.base] = checkers[args.base].SegmentChecker
    print(f"\nTimings on env1 ({grid.width} x {grid.height} cells), medians"
          + (f", alternating the check of {args.base} and the current one:" if args.base else ":"))
    cost, seconds, routes = ({name: [] for name in checkers} for _ in range(3))
    for seed in range(max(args.seeds, 5)):  # alternating: both see the same minutes
        for name, cls in checkers.items():
            with mock.patch.object(problem_module, "SegmentChecker", cls):
                problem = PathProblem(grid, START, GOAL, waypoints=args.waypoints)
                X = np.random.default_rng(seed).uniform(problem.lower, problem.upper,
                                                        (50, problem.dim))  # fmt: skip
                cost[name].append(median_time(lambda p=problem, X=X: p(X), 30))
                options = PlanOptions("iwso", 50, 300, seed, args.waypoints)
                route = plan_route(grid, START, GOAL, options).route
            seconds[name].append(route.planning_time_s)
            routes[name].append(route.points)
    for name in checkers:
        print(f"  [{name}] cost of 50 random routes ({args.waypoints} waypoints): "
              f"{np.median(cost[name]) * 1e3:.3f} ms; IWSO 50 x 300: "
              f"{np.median(seconds[name]):.3f} s (best {min(seconds[name]):.3f} s)")  # fmt: skip
    if args.base:
        same = sum(np.array_equal(a, b) for a, b in zip(*routes.values(), strict=True))
        print(f"  the same IWSO route bit for bit in {same} of {len(routes['now'])} seeds")
    for env in ("env1", "env2"):
        g = read_grid(CHARTS / f"{env}.tif")
        t_any = median_time(lambda g=g: plan_route(g, START, GOAL, PlanOptions("anyangle")), 7)
        t_astar = median_time(lambda g=g: plan_route(g, START, GOAL, PlanOptions("astar")), 3)
        print(f"  {env}: any-angle {t_any:.3f} s, 8-connected A* {t_astar:.3f} s (with checks)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=25)
    ap.add_argument("--algos", default=",".join([*OPTIMIZERS, "iwso+s", "astar", "astar+s"]))
    ap.add_argument("--envs", default="env1,env2")
    ap.add_argument("--pop", type=int, default=50)
    ap.add_argument("--iters", type=int, default=300)
    ap.add_argument("--waypoints", type=int, default=3)
    ap.add_argument("--base", help="also time the collision check of this git revision")
    ap.add_argument("--timings-only", action="store_true", help="skip the quality tables")
    args = ap.parse_args()
    if not args.timings_only:
        for env in args.envs.split(","):
            quality(env, args.algos.split(","), args)
    timings(args)


if __name__ == "__main__":
    main()
