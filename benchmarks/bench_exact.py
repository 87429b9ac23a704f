"""The exact planners' speed, beside the previous implementation ("the plain way", from git).

For each case: reading the grid, the set-up (the collision tables of the path problem's
checker, and the navigable regions), 8-connected A* and the any-angle route, each the best of
``--repeat`` runs (this 2-core machine is shared), for the current code and for the code of git
revision ``--base`` (default HEAD: ``git show`` into a temporary package). Route lengths (cells)
must agree to 1e-6; a difference is printed and the script exits 1.

Cases: US4MD81M at 17 m cells (built once into build/bench/us4md81m_17.tif if absent) between two
pairs of water points about 50 km apart (A: a winding route from the upper bay into the Choptank
approaches, B: straight down the bay); env1 and env2 (10, 10) → (490, 490); and every bundled
chart grid of build/grids/ with the route of pipelines/report.yaml (if built).

Usage: python benchmarks/bench_exact.py [--repeat 3] [--base HEAD] [--skip-old-anyangle]
       [--cases us4md81m,env,bundled]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from usvtool.grid import read_grid

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))
BUILD = ROOT / "build"
US4 = ROOT / "charts" / "noaa" / "US4MD81M" / "US4MD81M.000"
# map metres (EPSG:32618) of cell centres; lon/lat in the comments
US4_PAIRS = {
    # -76.3766 38.9885 → -76.0882 38.6085 (49 km apart)
    "us4md81m A": ((380775.4, 4316397.3), (405255.4, 4273897.3)),
    # -76.4384 38.9387 → -76.3905 38.4920 (49.8 km apart)
    "us4md81m B": ((375335.4, 4310957.3), (378735.4, 4261317.3)),
}


def old_modules(base: str, tmp: Path):
    """The collision and exact modules of git revision ``base``, the old exact importing the
    old collision."""
    from revision import load_module, source_at

    collision = load_module("old_collision", source_at(base, "usvtool/collision.py"), tmp)
    exact_src = source_at(base, "usvtool/plan/exact.py").replace(
        "from usvtool.collision import", "from old_collision import"
    )
    return collision, load_module("old_exact", exact_src, tmp)


def best(fn, repeat: int):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def length(route) -> float:
    return float(np.hypot(*np.diff(route, axis=0).T).sum()) if route is not None else np.inf


def us4_grid() -> Path:
    path = BUILD / "bench" / "us4md81m_17.tif"
    if not path.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
        usvtool = Path(sys.executable).with_name("usvtool")
        subprocess.run(
            [str(usvtool), "-q", "preprocess", str(US4), "--cell-size", "17", "-o", str(path)],
            check=True, stdout=subprocess.DEVNULL,
        )  # fmt: skip
    return path


def cases(which: set[str]):
    if "us4md81m" in which:
        path = us4_grid()
        for name, ends in US4_PAIRS.items():
            yield name, path, ends
    if "env" in which:
        for name in ("env1", "env2"):
            yield name, ROOT / "charts" / f"{name}.tif", ((10.0, 10.0), (490.0, 490.0))
    if "bundled" in which:
        from bench_charts import bundled_ends, map_points

        for chart, ends in bundled_ends().items():
            path = BUILD / "grids" / f"{chart}.tif"
            if path.exists():
                yield chart, path, map_points(read_grid(path), ends)


def run(grid, ends, checker_cls, exact, repeat: int, skip_aa: bool):
    """Times (set-up, A*, any-angle) and route lengths (A*, any-angle) of one implementation."""
    from usvtool.plan.problem import PAD

    blocked = grid.blocked

    def setup():
        fresh = type(grid)(grid.cells, grid.transform)  # regions are cached per grid
        return checker_cls(blocked, pad=PAD), fresh.regions

    t_setup, (checker, _) = best(setup, repeat)
    t_astar, r_astar = best(lambda: exact.astar(blocked, *ends), repeat)
    if skip_aa:
        t_aa, r_aa = float("nan"), None
    else:  # the old any-angle planner once: it takes many seconds on the big grid
        reps = repeat if exact.__name__ != "old_exact" else 1
        t_aa, r_aa = best(lambda: exact.any_angle(checker, blocked, *ends), reps)
    return (t_setup, t_astar, t_aa), (length(r_astar), length(r_aa))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--base", default="HEAD")
    ap.add_argument("--cases", default="us4md81m,env,bundled")
    ap.add_argument("--skip-old-anyangle", action="store_true", help="it takes ~15 s a case")
    args = ap.parse_args()
    from usvtool.collision import SegmentChecker
    from usvtool.plan import exact
    from usvtool.plan.planner import check_ends

    failed = False
    with tempfile.TemporaryDirectory() as tmp:
        old_collision, old_exact = old_modules(args.base, Path(tmp))
        print(f"{'case':16} {'cells':>10} {'impl':4} {'read':>6} {'set-up':>7} {'A*':>7} "
              f"{'any-angle':>9} {'A* len':>9} {'AA len':>9}")  # fmt: skip
        for name, path, (start, goal) in cases(set(args.cases.split(","))):
            t_read, grid = best(lambda p=path: read_grid(p), args.repeat)
            ends = check_ends(grid, start, goal)  # also labels the regions (cached)
            rows = {}
            for impl, coll, ex in (("new", None, exact), (args.base, old_collision, old_exact)):
                cls = SegmentChecker if coll is None else coll.SegmentChecker
                skip_aa = impl != "new" and args.skip_old_anyangle
                times, rows[impl] = run(grid, ends, cls, ex, args.repeat, skip_aa)
                print(f"{name:16} {grid.cells.size:>10} {impl[:4]:4} {t_read:6.3f} "
                      + " ".join(f"{t:{n}.3f}" for t, n in zip(times, (7, 7, 9), strict=True))
                      + f" {rows[impl][0]:9.3f} {rows[impl][1]:9.3f}")  # fmt: skip
            new, old = rows["new"], rows[args.base]
            for label, a, b in (("A*", new[0], old[0]), ("any-angle", new[1], old[1])):
                if np.isfinite(b) and abs(a - b) > 1e-6:
                    print(f"  {name}: {label} length differs: {a} against {b}")
                    failed = True
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
