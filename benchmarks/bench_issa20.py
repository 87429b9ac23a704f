"""The ISSA paper's 20 x 20 experiment (section 4, Table 3) on the bundled ``charts/grid20.tif``.

50 runs each of PSO (the paper's settings, ``pso-issa``), SSA and ISSA with the paper's encoding
(one cell per grid column, ``--encoding columns``), 100 sparrows x 500 iterations, from cell
(1, 1) to cell (20, 20) (centres (0.5, 0.5) and (19.5, 19.5) in metres). Fitness = route length +
turning energy (0.4 per right-angle turn, 0.2 per obtuse one) + the collision penalty (zero for a
collision-free route). Printed beside the paper's Table 3; its grid (Figure 10) is not in the
text, so ``grid20`` is our own map in its spirit and only the trends compare.

Usage: python benchmarks/bench_issa20.py [--runs 50] [--pop 100] [--iters 500]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from usvtool.grid import read_grid
from usvtool.plan.planner import PlanOptions, plan_route

GRID = Path(__file__).resolve().parent.parent / "charts" / "grid20.tif"
START, GOAL = (0.5, 0.5), (19.5, 19.5)
ALGOS = {"pso-issa": "PSO", "ssa": "SSA", "issa": "ISSA"}
# Table 3: optimum fitness, number of turns, mean fitness, mean time (s), variance
PAPER = {
    "pso-issa": (33.68, 11, 35.96, 0.60, 17.03),
    "ssa": (33.17, 10, 35.34, 0.67, 18.62),
    "issa": (29.81, 3, 30.11, 0.94, 9.33),
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=50)
    ap.add_argument("--pop", type=int, default=100)
    ap.add_argument("--iters", type=int, default=500)
    args = ap.parse_args()
    grid = read_grid(GRID)
    optimum = plan_route(grid, START, GOAL, PlanOptions("anyangle")).route
    print(f"grid20: {args.runs} runs, {args.pop} x {args.iters}, columns encoding; any-angle "
          f"optimum {optimum.length_m:.2f} (fitness {optimum.fitness:.2f}, "
          f"{optimum.turns} turns)\n")  # fmt: skip
    print(f"{'':8} {'optimum':>8} {'turns':>5} {'mean':>7} {'var':>8} {'free':>5} {'mean*':>7} "
          f"{'var*':>6} {'time s':>6} | paper: {'optimum':>7} {'turns':>5} {'mean':>6} "
          f"{'var':>6} {'time':>5}")  # fmt: skip
    for algo, label in ALGOS.items():
        runs = [
            plan_route(
                grid, START, GOAL, PlanOptions(algo, args.pop, args.iters, seed, encoding="columns")
            ).route
            for seed in range(args.runs)
        ]
        fitness = np.array([r.fitness for r in runs])
        free = np.array([r.collision_free for r in runs])
        best = runs[int(np.argmin(fitness))]
        time_s = np.mean([r.planning_time_s for r in runs])
        ok = fitness[free]
        ok_mean, ok_var = (ok.mean(), ok.var(ddof=1)) if ok.size > 1 else (np.nan, np.nan)
        p_opt, p_turns, p_mean, p_time, p_var = PAPER[algo]
        print(f"{label:8} {best.fitness:8.2f} {best.turns:5d} {fitness.mean():7.2f} "
              f"{fitness.var(ddof=1):8.2f} {free.mean():5.0%} {ok_mean:7.2f} {ok_var:6.2f} "
              f"{time_s:6.2f} | paper: {p_opt:7.2f} {p_turns:5d} {p_mean:6.2f} {p_var:6.2f} "
              f"{p_time:5.2f}")  # fmt: skip
    print("\nvar: sample variance of the final fitness over the runs; * over the collision-free"
          " runs only (a colliding route pays 40 per colliding segment); turns: of the best.")


if __name__ == "__main__":
    main()
