"""The path cost compiled (usvtool/plan/cost_kernels.py) against its NumPy path, and whole plans.

1. One evaluation of a population (decode and cost, what the optimizers call every iteration):
   the NumPy path (``PathProblem._decode_python`` + ``_cost_python``, and the guided problem's)
   patched in, and the compiled one, over the populations a plan of IWSO, ISSA, IWSO+g (on env2)
   and ISSA ``columns`` (on grid20) evaluates (recorded from the run; the same costs checked).
2. Whole plans (``plan_route``, as ``usvtool plan`` runs them, without the process start): each
   kind of the report's plan jobs, with the compiled cost and with the NumPy path patched in,
   alternating per repeat in one process (this shared machine's speed varies between processes
   and over minutes); the routes of both are checked to be the same bits.

Minimum over repeats (the machine is shared: the minimum is the least disturbed run).

Usage: python benchmarks/bench_cost.py [--repeats 5] [--evals 300] [--no-plans]

Measured (2026-12-06, this shared 2-core machine, NumPy 2.4, numba 0.68; CPU time, the least
of 5 repeats):

    evaluation of a population              numpy µs  compiled µs  speed-up
    iwso, 100 routes                           103.4         51.8      2.0x
    issa, 50 routes                            134.5         87.3      1.5x
    iwso+g, 100 routes                         315.4         57.9      5.4x
    issa columns, 100 routes                   626.2        483.0      1.3x
    iwso K=11, 100 routes                      205.6        119.1      1.7x

    whole plan (s, plan_route)                 numpy     compiled  speed-up
    wso                                        0.079        0.063      1.3x
    iwso                                       0.205        0.133      1.5x
    ssa                                        0.158        0.104      1.5x
    issa                                       0.103        0.081      1.3x
    pso                                        0.107        0.074      1.5x
    gwo                                        0.120        0.089      1.3x
    woa                                        0.130        0.097      1.3x
    mrfo                                       0.154        0.104      1.5x
    boa                                        0.073        0.056      1.3x
    iwso+g                                     0.640        0.280      2.3x
    ssa columns                                0.550        0.396      1.4x
    issa columns                               0.377        0.323      1.2x
    iwso K=11                                  0.311        0.207      1.5x

Whole ``usvtool plan`` processes (user + sys CPU, the identity jobs on the report's env2 and
grid20 grids, 8 alternations of the package before and after): iwso 1.17 → 1.19 s (the least;
medians 1.27, 1.35: the plan's 0.07 s is within this machine's noise, and a process now loads
the cost kernels from numba's cache, 0.02-0.035 s), issa ``columns`` 1.42 → 1.37 s, iwso+g
1.65 → 1.37 s (medians 2.01 → 1.56 s). The process start (imports, the grid, the checker's
tables) is about 1 s of every job.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from usvtool.grid import read_grid
from usvtool.plan.guided import GuidedProblem
from usvtool.plan.planner import PlanOptions, plan_route
from usvtool.plan.problem import PathProblem, Search

ROOT = Path(__file__).resolve().parent.parent
CHARTS = ROOT / "charts"
JOBS = [  # (label, chart, start, goal, options) as the report's plan jobs run them
    *[(algo, "env2", (10.0, 10.0), (490.0, 490.0), dict(algo=algo, seed=16))
      for algo in ("wso", "iwso", "ssa", "issa", "pso", "gwo", "woa", "mrfo", "boa", "iwso+g")],
    *[(f"{algo} columns", "grid20", (0.5, 0.5), (19.5, 19.5),
       dict(algo=algo, seed=28, encoding="columns", pop=100, iters=500))
      for algo in ("ssa", "issa")],
    ("iwso K=11", "env2", (10.0, 10.0), (490.0, 490.0), dict(algo="iwso", seed=16, waypoints=11)),
]  # fmt: skip


def best_time(fn, repeats: int, number: int) -> float:
    """The least time of one call (seconds) over ``repeats`` batches of ``number`` calls."""
    best = np.inf
    for _ in range(repeats):
        t0 = time.process_time()
        for _ in range(number):
            fn()
        best = min(best, (time.process_time() - t0) / number)
    return best


class numpy_path:
    """The NumPy decode and cost patched into both problems, for the ``with`` block."""

    NAMES = ("decode", "cost")

    def __enter__(self):
        self.saved = []
        for cls in (PathProblem, GuidedProblem):
            for name in self.NAMES:
                if hasattr(cls, f"_{name}_python"):
                    self.saved.append((cls, name, cls.__dict__[name]))
                    setattr(cls, name, getattr(cls, f"_{name}_python"))
        return self

    def __exit__(self, *exc):
        for cls, name, fn in self.saved:
            setattr(cls, name, fn)


def populations(grid, start, goal, options) -> list[tuple[object, np.ndarray]]:
    """The problem and the populations (its variables) that a plan evaluates, in order."""
    seen = []
    original = Search.__call__

    def record(self, Z):
        seen.append((self.problem, self.to_problem(Z)))
        return original(self, Z)

    Search.__call__ = record
    try:
        plan_route(grid, start, goal, PlanOptions(**options, timing=False))
    finally:
        Search.__call__ = original
    return seen


def evaluations(args) -> None:
    print(f"{'evaluation of a population':38} {'numpy µs':>9} {'compiled µs':>12} {'speed-up':>9}")
    grids = {name: read_grid(CHARTS / f"{name}.tif") for name in ("env2", "grid20")}
    for label, chart, start, goal, options in JOBS:
        if options["algo"] not in ("iwso", "issa", "iwso+g"):
            continue
        seen = populations(grids[chart], start, goal, options)
        step = max(1, len(seen) // args.evals)
        seen = seen[::step]

        def run(seen=seen):
            for p, X in seen:
                p(X)

        compiled = best_time(run, args.repeats, 1) / len(seen)
        with numpy_path():
            plain = best_time(run, args.repeats, 1) / len(seen)
            want = [p(X).tobytes() for p, X in seen]
        assert [p(X).tobytes() for p, X in seen] == want, label
        n = seen[0][1].shape[0]
        print(f"{label + f', {n} routes':38} {plain * 1e6:9.1f} {compiled * 1e6:12.1f} "
              f"{plain / compiled:8.1f}x")  # fmt: skip


def plans(args) -> None:
    print(f"\n{'whole plan (s, plan_route)':38} {'numpy':>9} {'compiled':>12} {'speed-up':>9}")
    grids = {name: read_grid(CHARTS / f"{name}.tif") for name in ("env2", "grid20")}
    for label, chart, start, goal, options in JOBS:
        opts = PlanOptions(**options, timing=False)
        times = {"numpy": np.inf, "compiled": np.inf}
        routes = {}
        for _ in range(args.repeats):
            for way in times:
                with numpy_path() if way == "numpy" else _nothing():
                    t0 = time.process_time()
                    result = plan_route(grids[chart], start, goal, opts)
                    times[way] = min(times[way], time.process_time() - t0)
                routes[way] = (np.asarray(result.route.points).tobytes(), result.summary())
        assert routes["numpy"] == routes["compiled"], label
        print(f"{label:38} {times['numpy']:9.3f} {times['compiled']:12.3f} "
              f"{times['numpy'] / times['compiled']:8.1f}x")  # fmt: skip


class _nothing:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        pass


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--evals", type=int, default=300, help="populations timed per plan")
    ap.add_argument("--no-plans", action="store_true", help="only the evaluations")
    args = ap.parse_args()
    evaluations(args)
    if not args.no_plans:
        plans(args)


if __name__ == "__main__":
    main()
