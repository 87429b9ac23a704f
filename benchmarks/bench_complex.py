"""Global path planning on generated complex maps and the bundled charts (issue 14, item 2).

Maps: the kinds of ``charts/make_complex.py`` (island fields of three densities, walls with
gaps, a winding channel, a harbour), generated for ``--map-seed`` into ``OUT/maps/`` and
preprocessed in-process (1 m cells, 3 m margin, as env1/env2), each checked connected by the
exact planner; and the bundled charts with a route in pipelines/report.yaml (env1, env2,
grid20, grid50 from charts/, the NOAA charts from build/grids/ when `make report` has made
them). For each map and algorithm (every optimizer, its ``+s`` and its ``+g`` variant; the
exact ``anyangle`` route is the reference) over ``--seeds`` seeds, 50 x 300, single runs: the
collision-free rate, the median length / any-angle optimum, turns and mot over the
collision-free runs (``nan`` when there is none) and the median planning time of all runs.
The ``+g`` rows say ``ok`` when every seed is collision-free, the median length is within 5 %
of the optimum and the median turns and mot are below the exact route's. Jobs run in ``-j``
worker processes; every run is written to ``OUT/runs.csv`` and the table so far to
``OUT/complex.csv`` (both atomically) each time a map and algorithm's seeds are all done, so a
long run can be read while it goes on; the table is printed at the end.

In-process rather than through ``usvtool batch`` (whose pipelines also accept ``+g``): the
generated maps are made and checked here, and one process keeps each map's grid.

Usage: python benchmarks/bench_complex.py [--seeds 25] [--maps walls,channel] [--charts env1]
       [--algos iwso,ssa] [--variants ,+s,+g] [--map-seed 0] [-j 2] [-o build/complex]
With ``-j 1`` on a shared machine the 11 ``+g`` variants over the 6 maps and env1, env2, grid20
and grid50 at 25 seeds (2750 runs) took 27 minutes (``--variants +g``), the faithful and ``+s``
ones there (5500 runs) about 30 (``--variants ,+s``); the NOAA charts (``--charts``) add more.
"""

from __future__ import annotations

import argparse
import csv
import importlib.util
import io
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))
_spec = importlib.util.spec_from_file_location("make_complex", ROOT / "charts" / "make_complex.py")
make_complex = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(make_complex)

BUNDLED = ("env1", "env2", "grid20", "grid50", "us5ma12m", "head_of_passes", "rudee_inlet",
           "south_san_diego")  # fmt: skip
COLUMNS = ("map", "algorithm", "runs", "free", "len_opt", "turns", "mot", "time_s", "ok")
RUN_COLUMNS = ("map", "algorithm", "seed", "collision_free", "length_m", "turns", "mot", "time_s")


def load_map(name: str, out: Path, map_seed: int):
    """``(grid, start, goal)`` of a generated kind (written to ``out/maps``) or bundled chart."""
    from bench_charts import bundled_case

    if name in make_complex.KINDS:
        doc, grid = make_complex.connected_map(name, map_seed)
        (out / "maps").mkdir(parents=True, exist_ok=True)
        make_complex.write_map(out / "maps" / f"{name}.geojson", doc)
        return grid, tuple(doc["start"]), tuple(doc["goal"])
    return bundled_case(name) or sys.exit(
        f"bench_complex: no grid for {name!r} (run `make report` for the NOAA charts)"
    )


_MAPS: dict = {}


def _plan(job: tuple) -> tuple:
    """One route: ``(map, algorithm, seed, collision_free, length, turns, mot, time)``."""
    from usvtool.plan.planner import PlanOptions, plan_route

    name, out, map_seed, algo, seed = job
    if name not in _MAPS:
        _MAPS[name] = load_map(name, out, map_seed)
    grid, start, goal = _MAPS[name]
    r = plan_route(grid, start, goal, PlanOptions(algo, seed=seed)).route
    return name, algo, seed, r.collision_free, r.length_m, r.turns, r.mot, r.planning_time_s


def table(results: list[tuple]) -> list[dict]:
    """Rows per map and algorithm (module docstring), in the order of the results."""
    groups: dict[tuple[str, str], list[tuple]] = {}
    for r in results:
        groups.setdefault(r[:2], []).append(r)
    rows = []
    for (name, algo), runs in groups.items():
        exact = groups[(name, "anyangle")][0]
        free = [r for r in runs if r[3]]
        med = {i: float(np.median([r[i] for r in free])) if free else np.nan for i in (4, 5, 6)}
        seconds = float(np.median([r[7] for r in runs]))
        ok = ""
        if algo.endswith("+g"):
            good = len(free) == len(runs) and med[4] <= 1.05 * exact[4] and med[5] < exact[5]
            ok = "yes" if good and med[6] < exact[6] else "no"
        rows.append({"map": name, "algorithm": algo, "runs": len(runs),
                     "free": f"{len(free) / len(runs):.2f}", "len_opt": f"{med[4] / exact[4]:.4f}",
                     "turns": f"{med[5]:g}", "mot": f"{med[6]:.3f}", "time_s": f"{seconds:.3f}",
                     "ok": ok})  # fmt: skip
    return rows


def _csv(rows, columns) -> str:
    text = io.StringIO()
    writer = csv.DictWriter(text, columns, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return text.getvalue()


def write_tables(out: Path, results: list[tuple]) -> list[dict]:
    """Write ``out/runs.csv`` (every run so far) and ``out/complex.csv`` (their table, when the
    exact routes are in); returns the table's rows."""
    from usvtool.atomic import write_text

    write_text(out / "runs.csv", _csv([dict(zip(RUN_COLUMNS, r, strict=True)) for r in results],
                                      RUN_COLUMNS))  # fmt: skip
    exact = {r[0] for r in results if r[1] == "anyangle"}
    rows = table([r for r in results if r[0] in exact])
    write_text(out / "complex.csv", _csv(rows, COLUMNS))
    return rows


def main() -> None:
    from usvtool.plan.optimizers import OPTIMIZERS

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=25)
    ap.add_argument("--maps", default=",".join(make_complex.KINDS))
    ap.add_argument("--charts", default=",".join(BUNDLED))
    ap.add_argument("--algos", default=",".join(OPTIMIZERS))
    ap.add_argument("--variants", default=",+s,+g", help="suffixes, '' for the faithful ones")
    ap.add_argument("--map-seed", type=int, default=0)
    ap.add_argument("-j", "--jobs", type=int, default=2)
    ap.add_argument("-o", "--out", default=str(ROOT / "build" / "complex"))
    args = ap.parse_args()
    out = Path(args.out)
    names = [n for n in (*args.maps.split(","), *args.charts.split(",")) if n]
    algos = [a + v for a in args.algos.split(",") for v in args.variants.split(",")]
    jobs = [(n, out, args.map_seed, "anyangle", 0) for n in names]
    jobs += [(n, out, args.map_seed, a, s) for n in names for a in algos for s in range(args.seeds)]
    out.mkdir(parents=True, exist_ok=True)
    results: list[tuple] = []
    with ProcessPoolExecutor(args.jobs) as pool:
        for result in pool.map(_plan, jobs, chunksize=max(1, args.seeds)):
            results.append(result)
            done = len(results) - len(names)  # the exact routes come first
            if done >= 0 and done % args.seeds == 0:
                rows = write_tables(out, results)
    print(f"{args.seeds} seeds, 50 x 300, single runs; map seed {args.map_seed}")
    print(" ".join(f"{c:>16}" if c in ("map", "algorithm") else f"{c:>8}" for c in COLUMNS))
    for row in rows:
        print(" ".join(f"{row[c]:>16}" if c in ("map", "algorithm") else f"{row[c]:>8}"
                       for c in COLUMNS))  # fmt: skip


if __name__ == "__main__":
    main()
