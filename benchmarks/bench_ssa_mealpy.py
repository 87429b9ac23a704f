"""usvtool's SSA against mealpy 3.0.3's OriginalSSA on env1, with the same cost (issue 14, item 5).

Both minimise the path problem's dimensionless cost (``PathProblem.search()``: 3 waypoints as
offsets from the straight route, in units of the start-goal distance) from (10, 10) to
(490, 490) on ``charts/env1.tif`` with 50 sparrows over 25 seeds. mealpy gets the same box and
the cost of one route per call (its default ``mode="single"``: sparrows updated one after
another). Per configuration: evaluations per run, runs within 5 % of the any-angle optimum
(``ok``: collision-free and length <= 1.05 x optimum), collision-free runs, and the median
length / optimum over the collision-free runs.

Budgets: usvtool's SSA evaluates ``pop + round(0.15 pop)`` = 58 routes per iteration, mealpy's
``pop + (pop - int(0.1 pop))`` = 95 (every sparrow but the best 5 is a scout); "matched" runs
usvtool for 491 iterations (mealpy's 28 550 evaluations), and with ``--mealpy-matched`` mealpy
for 183 (usvtool's 17 450; slow).

``--ablation`` switches mealpy's departures on one at a time in usvtool's SSA (:class:`Switched`,
a subclass overriding the parts of the phases a switch changes), then all but one, and runs
ISSA with the same bounds rule. Findings: docs/optimizers.md ("SSA against mealpy").

mealpy is a benchmark-only comparison, not a dependency: without it the mealpy rows are skipped
with a message. Its 3.0.3 wheel pins ``numpy<=1.26.0`` but runs with numpy 2; install it
without its dependencies: ``pip install --no-deps mealpy==3.0.3 pandas``.

Usage: python benchmarks/bench_ssa_mealpy.py [--seeds 25] [-j 2] [--ablation] [--no-mealpy]
       [--mealpy-matched]
"""

from __future__ import annotations

import argparse
import time
from multiprocessing import Pool
from pathlib import Path

import numpy as np

from usvtool.collision import is_collision_free
from usvtool.grid import read_grid
from usvtool.plan.optimizers import make_optimizer
from usvtool.plan.optimizers.issa import ISSA
from usvtool.plan.optimizers.ssa import SSA
from usvtool.plan.optimizers.ssa_redraw import SSARedraw
from usvtool.plan.planner import PlanOptions, plan_route
from usvtool.plan.problem import PathProblem
from usvtool.route import route_length

ENV1 = Path(__file__).resolve().parent.parent / "charts" / "env1.tif"
START, GOAL = (10.0, 10.0), (490.0, 490.0)
POP, ITERS, WAYPOINTS = 50, 300, 3
BAR = 1.05  # "within 5 % of the optimum"
SWITCHES = ("redraw", "sign", "all_scouts", "scalar_beta", "flyoff")


class Switched(SSA):
    """usvtool's SSA with mealpy 3.0.3 OriginalSSA's departures as switches (all off: ``ssa``):
    :class:`SSA` itself, overriding only the parts of its phases that a switch changes.

    ``redraw``: out-of-box coordinates redrawn uniformly in the box (:class:`SSARedraw`), not
    clipped; ``sign``: producers ``x exp(+i / (alpha iter_max))``, an exponent above 5 replaced
    by ``U(0, 1)``; ``all_scouts``: every sparrow but the best ``int(0.1 n)`` is a scout and all
    take the to-best move (mealpy tests ``f < f_g`` on the wrong sparrow, never true);
    ``scalar_beta``: one ``beta`` per scout, not per coordinate; ``flyoff``: rank
    ``i > n/2 + 1`` flies off (mealpy's 0-based ``idx > int(n/2)``). ``alarm_product`` is not
    mealpy's: eq. 1's alarm branch as the ISSA paper prints it, ``x Q`` instead of ``x + Q L``.
    """

    name = "ssa-switched"
    defaults = {**SSA.defaults, **dict.fromkeys((*SWITCHES, "alarm_product"), False)}

    def _safe_move(self, X, rank):
        if not self.params["sign"]:
            return super()._safe_move(X, rank)
        alpha = 1.0 - self.rng.random((X.shape[0], 1))
        des = rank / (alpha * self.iters)
        return X * np.exp(np.where(des > 5, self.rng.random((X.shape[0], 1)), des))

    def _alarm_move(self, X):
        if not self.params["alarm_product"]:
            return super()._alarm_move(X)
        return X * self.rng.standard_normal((X.shape[0], 1))

    def _flies_off(self, rank, n):
        return rank > n / 2 + (1 if self.params["flyoff"] else 0)

    def _scouts_of(self, F):
        if not self.params["all_scouts"]:
            return super()._scouts_of(F)
        return np.argsort(F, kind="stable")[int(0.1 * F.size) :]

    def _to_best(self, f):
        return super()._to_best(f) | self.params["all_scouts"]

    def _beta(self, n, d):
        return self.rng.standard_normal((n, 1) if self.params["scalar_beta"] else (n, d))

    def clip(self, X):
        return SSARedraw.clip(self, X) if self.params["redraw"] else super().clip(X)


class ISSARedraw(ISSA):
    """ISSA with :class:`SSARedraw`'s bounds rule (a measurement, not a registered variant)."""

    clip = SSARedraw.clip


_SETUP: dict = {}


def _setup() -> dict:
    """The grid, the path problem, its search view and the optimum (once per process)."""
    if not _SETUP:
        grid = read_grid(ENV1)
        problem = PathProblem(grid, START, GOAL, waypoints=WAYPOINTS)
        optimum = plan_route(grid, START, GOAL, PlanOptions("anyangle")).route.length_m
        _SETUP.update(grid=grid, problem=problem, search=problem.search(), optimum=optimum)
    return _SETUP


def _judge(z: np.ndarray) -> tuple[float, bool]:
    """Length / optimum and collision-freedom of the route of search variables ``z``."""
    s = _setup()
    problem, grid = s["problem"], s["grid"]
    points = problem.to_map(problem.decode(s["search"].to_problem(z))[0])
    free = is_collision_free(grid, points, problem.checker)
    return route_length(grid, points) / s["optimum"], free


def _cost_one(z: np.ndarray) -> float:
    return float(_setup()["search"](z[None])[0])


def _mealpy(iters: int, seed: int) -> tuple[np.ndarray, int]:
    from mealpy import FloatVar
    from mealpy.swarm_based.SSA import OriginalSSA

    search = _setup()["search"]
    model = OriginalSSA(epoch=iters, pop_size=POP)
    bounds = FloatVar(lb=search.lower, ub=search.upper)
    problem = {"bounds": bounds, "minmax": "min", "obj_func": _cost_one, "log_to": None}
    best = model.solve(problem, seed=seed)
    return best.solution, model.nfe_counter


def run(job: tuple) -> tuple[float, bool, int]:
    """One run of ``(kind, iters, switches, seed)``: kind ``mealpy``, ``switched``,
    ``issa-redraw`` or a registered optimizer. Returns (length / optimum, free, evaluations)."""
    kind, iters, switches, seed = job
    if kind == "mealpy":
        z, evaluations = _mealpy(iters, seed)
        return (*_judge(z), evaluations)
    if kind == "switched":
        optimizer = Switched(POP, iters, seed, **switches)
    elif kind == "issa-redraw":
        optimizer = ISSARedraw(POP, iters, seed)
    else:
        optimizer = make_optimizer(kind, POP, iters, seed)
    search = _setup()["search"]
    result = optimizer.minimize(search, search.lower, search.upper)
    return (*_judge(result.x), result.evaluations)


def summarise(label: str, runs: list, seconds: float) -> None:
    ratio = np.array([r[0] for r in runs])
    free = np.array([r[1] for r in runs])
    ok = int(np.sum(free & (ratio <= BAR)))
    median = f"{np.median(ratio[free]):8.4f}" if free.any() else f"{'-':>8}"
    n = len(runs)
    print(f"{label:46} {runs[0][2]:6d} {ok:3d}/{n:<3d} {free.sum():3d}/{n:<3d} {median} "
          f"{seconds:7.1f}", flush=True)  # fmt: skip


def mealpy_missing() -> str | None:
    """Why the mealpy rows cannot run, or None."""
    try:
        import mealpy
    except ImportError:
        return "mealpy is not installed (pip install --no-deps mealpy==3.0.3 pandas)"
    if mealpy.__version__ != "3.0.3":
        return f"mealpy {mealpy.__version__} is installed, the comparison is with 3.0.3"
    return None


def configurations(args) -> list[tuple[str, tuple]]:
    per_ssa, per_mealpy = POP + round(0.15 * POP), 2 * POP - int(0.1 * POP)
    matched_ssa = round(per_mealpy * ITERS / per_ssa)  # 491
    matched_mealpy = round(per_ssa * ITERS / per_mealpy)  # 183
    rows = [
        ("ssa, 50 x 300", ("ssa", ITERS, None)),
        (f"ssa, 50 x {matched_ssa} (mealpy's evaluations)", ("ssa", matched_ssa, None)),
        ("ssa-redraw, 50 x 300", ("ssa-redraw", ITERS, None)),
        (f"ssa-redraw, 50 x {matched_ssa}", ("ssa-redraw", matched_ssa, None)),
    ]
    why = "--no-mealpy given" if args.no_mealpy else mealpy_missing()
    if why:
        print(f"mealpy rows skipped: {why}")
    else:
        rows.append(("mealpy OriginalSSA, 50 x 300", ("mealpy", ITERS, None)))
        if args.mealpy_matched:
            rows.append((f"mealpy OriginalSSA, 50 x {matched_mealpy} (usvtool's evaluations)",
                         ("mealpy", matched_mealpy, None)))  # fmt: skip
    if args.ablation:
        every = dict.fromkeys(SWITCHES, True)
        rows += [(f"ssa + {key}", ("switched", ITERS, {key: True})) for key in SWITCHES]
        rows.append(("ssa + all five (mealpy's rules, vectorised)", ("switched", ITERS, every)))
        rows += [
            (f"all five - {key}", ("switched", ITERS, {**every, key: False})) for key in SWITCHES
        ]
        rows += [
            ("ssa + alarm_product (ISSA's printed eq. 1)",
             ("switched", ITERS, {"alarm_product": True})),
            ("issa, 50 x 300", ("issa", ITERS, None)),
            ("issa with the redraw rule, 50 x 300", ("issa-redraw", ITERS, None)),
        ]  # fmt: skip
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=25)
    ap.add_argument("-j", "--jobs", type=int, default=2)
    ap.add_argument("--ablation", action="store_true", help="switch mealpy's rules one by one")
    ap.add_argument("--no-mealpy", action="store_true", help="skip the (slow) mealpy runs")
    ap.add_argument("--mealpy-matched", action="store_true",
                    help="also run mealpy at usvtool's evaluations (slow)")  # fmt: skip
    args = ap.parse_args()
    rows = configurations(args)
    print(f"env1, {args.seeds} seeds, {POP} sparrows, {WAYPOINTS} waypoints, any-angle optimum "
          f"{_setup()['optimum']:.1f} m; ok: free and length <= {BAR} x optimum\n")  # fmt: skip
    print(f"{'configuration':46} {'evals':>6} {'ok':>7} {'free':>7} {'len/opt':>8} {'time s':>7}")
    with Pool(args.jobs) as pool:
        for label, (kind, iters, switches) in rows:
            t0 = time.perf_counter()
            jobs = [(kind, iters, switches, seed) for seed in range(args.seeds)]
            summarise(label, pool.map(run, jobs), time.perf_counter() - t0)


if __name__ == "__main__":
    main()
