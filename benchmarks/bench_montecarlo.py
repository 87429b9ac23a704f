"""Encounter simulation at Monte-Carlo scale (issue 24): the control step, the scene families'
runs one by one and as a batch, and PythonRobotics' DWA beside ours.

1. The control step of each controller at the defaults (10 s at 0.2 s) and at 3 s at 0.1 s,
   beside the previous revision's NumPy core and the plain per-sample loop: the table of
   benchmarks/bench_simulate.py (imported, not copied).
2. A family batch at ``-j 1`` and ``-j 2`` (``--workers``: those given): ``usvtool batch`` from
   the command line on a subset of pipelines/families.yaml (the first ``--scenes`` scenes of
   every seeded kind, the 22 Imazu cases, every controller; ``--full``: the pipeline itself,
   1 460 runs), each into a fresh directory: its wall time, runs per second, the jobs running at
   once on average, the table's time, what 600 runs and the full pipeline take at that rate, and
   whether the tables are the same bytes. Beside it (unless ``--no-plain``) the plain way, a new
   ``usvtool simulate`` process per run, on ten of the batch's runs (their own command lines):
   what a run pays for its start-up.
3. The per-run wall of each family kind (the first batch's ``timings.csv``): runs, mean, median
   and longest.
4. ``--peer FILE``: PythonRobotics' ``dynamic_window_approach.py`` (a copy the user gives; the
   project does not carry it), loaded from FILE, and one step of its ``dwa_control`` at its own
   defaults (its ``Config()``, the start of its ``main``: at rest at the origin heading pi/8,
   goal (10, 10), its 15 obstacles) beside one step of ours (dwa, 3 targets on env1's grid, at
   3 s at 0.1 s and at the defaults), the best of runs, in this process, and the ratio.
   Without it, one line says it is skipped.

Usage: python benchmarks/bench_montecarlo.py [--runs 7] [--scenes 2 | --full] [--peer FILE]
       [--no-steps] [--no-batch] [--workers 1 2] [--no-plain]
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parent.parent
BENCHMARKS = Path(__file__).resolve().parent
FAMILIES = ROOT / "pipelines" / "families.yaml"
USV = [sys.executable, "-m", "usvtool.cli"]
#: The runs of the issue's throughput target (item 3: 600 runs in 2 minutes on 2 cores).
TARGET_RUNS = 600
#: PythonRobotics' start (its ``main``): the state [x, y, yaw, v, omega] and the goal.
PEER_START = (0.0, 0.0, math.pi / 8.0, 0.0, 0.0)
PEER_GOAL = (10.0, 10.0)


def bench_simulate():
    """benchmarks/bench_simulate.py as a module (the step's table and its timers)."""
    sys.path.insert(0, str(BENCHMARKS))
    import bench_simulate as module

    return module


# --- 1. the step ------------------------------------------------------------------------------


def steps(runs: int) -> None:
    sim = bench_simulate()
    with tempfile.TemporaryDirectory() as tmp:
        sim.steps(sim.previous_controllers(sim.BASE, Path(tmp)), runs)


# --- 2, 3. the family batch -------------------------------------------------------------------


def family_pipeline(scenes: int | None) -> str:
    """pipelines/families.yaml with the first ``scenes`` scenes of each seeded kind (None: as
    it is), its root this checkout."""
    pipeline = yaml.safe_load(FAMILIES.read_text())
    pipeline["root"] = str(ROOT)
    for entry in pipeline["families"]:
        if scenes is not None and "scenes" in entry:
            entry["scenes"] = {"first": 0, "count": scenes}
    return yaml.safe_dump(pipeline, sort_keys=False)


def run_batch(pipeline: Path, out: Path, workers: int) -> tuple[float, dict]:
    """``usvtool batch PIPELINE -j WORKERS -o OUT`` in a new process: (wall s, its summary)."""
    t0 = time.perf_counter()
    proc = subprocess.run([*USV, "batch", str(pipeline), "-j", str(workers), "-o", str(out)],
                          cwd=ROOT, capture_output=True, text=True)  # fmt: skip
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        sys.exit(f"bench_montecarlo: the batch -j {workers} failed: {proc.stderr.strip()[-300:]}")
    return wall, json.loads(proc.stdout)


def job_walls(out: Path) -> list[tuple[str, float]]:
    """(case, wall s) of each run of the batch in ``out`` (its case ENTRY/KIND/sNNN)."""
    from usvtool.results import read_results

    return [(r.case, r.number) for r in read_results(out / "timings.csv")
            if r.metric == "wall_time_s"]  # fmt: skip


def same_table(a: bytes, b: bytes) -> str:
    """Whether two metrics tables are the same bytes, and if not, whether their keys differ (the
    code changed between the batches: a job's key hashes its stage's code)."""
    if a == b:
        return "the same bytes"
    keys = [{line.split(b",")[0] for line in t.splitlines()[1:]} for t in (a, b)]
    if keys[0] != keys[1]:
        return "DIFFERENT keys (did the code change between the two batches?)"
    return "DIFFERENT values"


def one_process_per_run(out: Path, count: int = 10) -> tuple[float, float]:
    """The plain way: ``count`` of the batch's runs, each its own ``usvtool simulate`` process
    in a fresh directory (its command line from its job.json): (the median wall of a process,
    the median wall of the same runs in the batch's worker)."""
    records = sorted((json.loads(p.read_text()) for p in (out / "runs").glob("*/job.json")),
                     key=lambda r: r["key"])[:count]  # fmt: skip
    alone = []
    for record in records:
        with tempfile.TemporaryDirectory() as tmp:
            t0 = time.perf_counter()
            proc = subprocess.run([*USV, *record["args"]], cwd=tmp, capture_output=True, text=True)
            alone.append(time.perf_counter() - t0)
            if proc.returncode != 0:
                sys.exit(f"bench_montecarlo: {' '.join(record['args'])}: {proc.stderr.strip()}")
    return statistics.median(alone), statistics.median(r["wall_time_s"] for r in records)


def batches(scenes: int | None, workers: list[int], plain: bool) -> None:
    with tempfile.TemporaryDirectory(prefix="bench-montecarlo-") as name:
        tmp = Path(name)
        pipeline = tmp / "families.yaml"
        pipeline.write_text(family_pipeline(scenes))
        what = "" if scenes is None else f", the first {scenes} scene(s) of each seeded kind"
        print(f"\nfamily batch: pipelines/families.yaml{what}, every controller; usvtool batch "
              f"from the command line, load average {os.getloadavg()[0]:.2f} at start")  # fmt: skip
        print(f"{'':5} {'runs':>5} {'wall s':>7} {'runs/s':>7} {'at once':>7} {'table s':>7} | "
              f"{f'{TARGET_RUNS} runs s':>10} {'1460 runs s':>11}")  # fmt: skip
        tables = {}
        for count in workers:
            out = tmp / f"j{count}"
            wall, summary = run_batch(pipeline, out, count)
            runs = summary["done"]
            busy = sum(w for _, w in job_walls(out)) / wall
            rate = runs / wall
            print(f"-j {count:<2} {runs:5d} {wall:7.1f} {rate:7.2f} {busy:7.2f} "
                  f"{summary['stage_time_s']['table']:7.2f} | {TARGET_RUNS / rate:10.0f} "
                  f"{1460 / rate:11.0f}")  # fmt: skip
            tables[count] = (out / "metrics.csv").read_bytes()
        first = tmp / f"j{workers[0]}"
        for count in workers[1:]:
            print(f"metrics.csv of -j {workers[0]} and -j {count}: "
                  f"{same_table(tables[workers[0]], tables[count])}")  # fmt: skip
        if plain:
            alone, in_worker = one_process_per_run(first)
            print(f"the plain way, a new usvtool simulate process per run (10 of the runs): "
                  f"median {alone:.3f} s a run, {in_worker:.3f} s in the batch's worker: "
                  f"{alone - in_worker:.3f} s of start-up a run")  # fmt: skip
        per_kind(job_walls(first), workers[0])


def per_kind(walls: list[tuple[str, float]], workers: int) -> None:
    kinds: dict[str, list[float]] = defaultdict(list)
    for case, wall in walls:
        kinds[case.rsplit("/", 1)[0]].append(wall)
    print(f"\nper-run wall of each family kind (s, the -j {workers} batch's timings.csv; load "
          f"average {os.getloadavg()[0]:.2f} at the end)")  # fmt: skip
    print(f"{'family/kind':26} {'runs':>4} {'mean':>6} {'median':>6} {'longest':>7}")
    for kind, values in sorted(kinds.items()):
        print(f"{kind:26} {len(values):4d} {statistics.mean(values):6.3f} "
              f"{statistics.median(values):6.3f} {max(values):7.3f}")  # fmt: skip


# --- 4. PythonRobotics' DWA -------------------------------------------------------------------


def load_peer(path: Path):
    """PythonRobotics' ``dynamic_window_approach.py`` at ``path``, imported under its own name
    (its ``main`` runs only as a script, so no animation), ``show_animation`` set False; matplotlib,
    which it imports, on its Agg backend. SystemExit with one line when it is not such a file."""
    if not path.is_file():
        sys.exit(f"bench_montecarlo: --peer {path}: no such file")
    os.environ.setdefault("MPLBACKEND", "Agg")
    spec = importlib.util.spec_from_file_location("dynamic_window_approach", path)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except Exception as exc:  # the user's file: whatever it raises, one line
        sys.exit(f"bench_montecarlo: --peer {path}: does not import ({type(exc).__name__}: {exc})")
    module.show_animation = False
    missing = [n for n in ("dwa_control", "Config") if not hasattr(module, n)]
    if missing:
        sys.exit(f"bench_montecarlo: --peer {path}: has no {' nor '.join(missing)} (not "
                 "PythonRobotics' dynamic_window_approach.py?)")  # fmt: skip
    return module


def peer_step(module, best_ms, runs: int) -> tuple[float, int | None, object]:
    """One ``dwa_control`` step at the module's own defaults: (ms, the best of ``runs`` runs of
    3 calls; the samples it rolled out, counted through its ``predict_trajectory`` when it has
    one, else None; its Config)."""
    config = module.Config()
    ob = getattr(config, "ob", None)
    if ob is None:
        sys.exit("bench_montecarlo: --peer: its Config has no ob (the obstacles; an older copy of "
                 "the file?)")  # fmt: skip
    goal = np.array(PEER_GOAL)

    def step():
        return module.dwa_control(np.array(PEER_START), config, goal, ob)

    samples = None
    rollout = getattr(module, "predict_trajectory", None)
    if rollout is not None:
        calls = []
        module.predict_trajectory = lambda *a, **k: calls.append(1) or rollout(*a, **k)
        try:
            step()
        finally:
            module.predict_trajectory = rollout
        samples = len(calls)
    return best_ms(step, runs, calls=3), samples, config


def ours(sim, runs: int) -> dict[str, tuple[float, int]]:
    """Our dwa's step on bench_simulate's case (3 targets on env1's grid) at 3 s at 0.1 s and at
    the defaults: {label: (ms, samples)}."""
    from usvtool.clearance import Clearance
    from usvtool.grid import read_grid
    from usvtool.sim.controllers import World, make_controller
    from usvtool.sim.vessel import preset

    world = World(preset("iwso-dwa-usv"), np.array([250.0, 480.0]),
                  Clearance(read_grid(ROOT / "charts" / "env1.tif")))  # fmt: skip
    figures = {}
    for label, params in (("3 s at 0.1 s", sim.SPEC), ("defaults, 10 s at 0.2 s", {})):
        c = make_controller("dwa", **params)
        c.reset(world)
        samples = c.rollouts(sim.OWN, sim.TARGETS).v.size
        figures[label] = (sim.best_ms(lambda c=c: c.decide(sim.OWN, sim.TARGETS), runs), samples)
    return figures


def peer(path: Path | None, runs: int) -> None:
    if path is None:
        print("\nPythonRobotics' DWA: skipped (give --peer FILE, a copy of its "
              "dynamic_window_approach.py; the project does not carry it)")  # fmt: skip
        return
    sim = bench_simulate()
    module = load_peer(path)
    theirs, samples, config = peer_step(module, sim.best_ms, runs)
    horizon = getattr(config, "predict_time", None)
    dt = getattr(config, "dt", None)
    print(f"\nPythonRobotics' dwa_control at its own defaults ({path}): "
          f"{samples if samples is not None else '?'} samples, {horizon} s at {dt} s, "
          f"{len(config.ob)} obstacles: {theirs:.2f} ms a step (best of {runs} runs of "
          "3)")  # fmt: skip
    for label, (ms, n) in ours(sim, runs).items():
        print(f"  ours, dwa at {label} ({n} samples, 3 targets and env1's grid): {ms:.3f} ms "
              f"a step; theirs / ours = {theirs / ms:.1f}")  # fmt: skip


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=7, help="runs of the step timings (best of)")
    ap.add_argument("--scenes", type=int, default=2, help="scenes of each seeded kind")
    ap.add_argument("--full", action="store_true", help="pipelines/families.yaml as it is")
    ap.add_argument("--peer", type=Path, metavar="FILE",
                    help="PythonRobotics' dynamic_window_approach.py, timed beside "
                    "ours")  # fmt: skip
    ap.add_argument("--no-steps", action="store_true", help="skip the step's table")
    ap.add_argument("--no-batch", action="store_true", help="skip the family batches")
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2], metavar="N",
                    help="the batches' -j, in order (the per-kind walls: the first's)")  # fmt: skip
    ap.add_argument("--no-plain", action="store_true",
                    help="skip the plain way (a new process per run)")  # fmt: skip
    args = ap.parse_args(argv)
    print(f"bench_montecarlo: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}")
    if not args.no_steps:
        steps(args.runs)
    if not args.no_batch:
        batches(None if args.full else args.scenes, args.workers, not args.no_plain)
    peer(args.peer, args.runs)


if __name__ == "__main__":
    sys.exit(main())
