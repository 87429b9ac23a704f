"""Encounter simulation: the cost of one control step, against the number of targets, numba's
start-up, and the wall time of the bundled scenarios.

1. One control step of each DWA controller with three targets close by, on env1's grid: the dynamic
   window sampled at 21 x 21 (+ the current values: 462 pairs; udwa+ 441), at the defaults
   (a 10 s horizon at 0.2 s) and at 3 s at 0.1 s. Beside it, in the same process and
   alternating, the previous revision's NumPy core (``--base``, loaded by benchmarks/revision.py
   with its own vessel module) and the ratio; then the plain way, the same objective one sample
   at a time in Python (tests/sim/plain_dwa.py, PythonRobotics' style). Each figure is the best
   of ``--runs`` runs of 50 steps (this shared 2-core machine's timings vary by up to two times
   between runs; the best is the repeatable one). Then the field's baselines (``vo``, issue
   33) beside dwa at the defaults, now only (they have no base revision); and sbmpc's
   re-evaluation step and its mean step (one re-evaluation a second) beside dwa.
2. One udwa step at the defaults against the number of targets (1, 3, 10, 30, 50, 100, 300),
   now and at ``--base``: targets within 100 m (every one within reach of the rollouts: the
   worst case) and spread over a 2 km disc (most beyond reach, skipped by the distance bound).
3. numba's start-up (``--startup``): importing numba, loading the compiled kernels from the cache,
   compiling them afresh; and ``usvtool simulate`` on bundled scenarios from the command line:
   the wall time of the run, of the same scenario cut to one step (all but the stepping), and
   their difference.
4. Many ships (``--ships``): scenes of 30, 100 and 300 replayed tracks (AIS-like CSVs, a fix
   every 10 s, straight courses through a 3 km square around the own ship's route) of 60, 120
   and 240 s at 0.1 s: the peak resident size of ``usvtool simulate`` (``VmHWM``, as
   benchmarks/bench_memory.py measures it) beside the guard's estimate, a least-squares fit of
   the peak to ``a + b x ships x steps`` with its worst residual, the mean step time, and the
   guard's one-line refusal of the longest scene under a small ``--max-memory``.
5. Every scenario in charts/scenarios/ with its own controller (``--scenarios``): simulated and
   wall time, steps, mean step time.
6. Whole runs per period (``--periods``): the run loop of ``usvtool simulate`` (observe, decide,
   advance; not the set-up nor the verdicts) on Imazu case 13 (3 339 periods with udwa) and
   emergency crossing scene 0, seed 1, in this process: ms per period of the loop and of the
   decisions alone, best of ``--runs`` runs; with ``--base-tree DIR`` beside another checkout's
   (``git worktree add DIR REV``), run by run alternately in processes of its own.

Figures of item 6 for the step's glue work (commits 25abfc7..71e1a55: the period window's step
in one compiled call, the wind field's fast paths, no imports in the step, heading_reward and
wrap_pi without the modulo inside (-2 pi, 2 pi), the ramps' ufuncs without numba's wrapper, the
grid collision test in floats), before (52810c2) and after, each in fresh processes of its own
(``--period-run``), the two trees alternately, best of 3-5 runs on the shared 2-core machine
(two other busy processes: +-8 % between runs), seed 1; ms per period of the loop (deciding),
x the loop's ratio:

scene                 controller         before          after     x
imazu 13              dwa        0.117 (0.103) 0.093 (0.081)  1.26
imazu 13              gdwa       0.210 (0.185) 0.161 (0.139)  1.30
imazu 13              ccdwa      0.128 (0.111) 0.098 (0.085)  1.31
imazu 13              udwa       0.128 (0.111) 0.099 (0.085)  1.29
imazu 13              udwa+      0.194 (0.177) 0.165 (0.150)  1.18
imazu 13              vo         0.082 (0.068) 0.079 (0.065)  1.04
imazu 13              sbmpc      0.070 (0.055) 0.064 (0.052)  1.09
emergency crossing 0  dwa        0.122 (0.106) 0.091 (0.079)  1.34
emergency crossing 0  gdwa       0.148 (0.132) 0.111 (0.098)  1.33
emergency crossing 0  ccdwa      0.135 (0.120) 0.108 (0.095)  1.25
emergency crossing 0  udwa       0.176 (0.159) 0.149 (0.135)  1.18
emergency crossing 0  udwa+      0.198 (0.182) 0.161 (0.148)  1.23
emergency crossing 0  vo         0.086 (0.074) 0.080 (0.069)  1.07
emergency crossing 0  sbmpc      0.083 (0.070) 0.082 (0.071)  1.01
wind halves 0         dwa        0.120 (0.094) 0.085 (0.072)  1.41
wind halves 0         udwa       0.192 (0.166) 0.142 (0.127)  1.35
wind halves 0         udwa+      0.273 (0.246) 0.214 (0.198)  1.28

The DWA controllers' periods 1.18-1.41 times faster, vo and sbmpc within the noise (their own
code unchanged). Whole jobs as a batch worker runs them (in one process, usvtool.cli in turn:
the scene, the run, the verdicts, the files; the Transformer made once per pair of CRSs),
7 scenes x 8 controllers (with udwa-calm), best of 3: 23.1 s before, 17.0 s after (1.36 x).
With this revision ``--periods`` times "now" in this process after the others' runs, which
penalised vo and sbmpc (0.6-0.9 x); fresh processes for both trees are the fair comparison.

Start-up (item 3), the kernels loaded at their first calls rather than at import
(usvtool.lazy_kernels.declared; c0802a3 before): the CPU of a ``usvtool simulate`` process on
emergency head-on scene 0, seed 1, best of 5 in fresh processes, the two trees alternately on
the shared 2-core machine (busy: +-15 %), before -> after: udwa 1.28 -> 1.07 s, dwa 1.13 ->
0.86, vo 1.12 -> 0.84, gdwa 1.32 -> 0.96, sbmpc 0.84-1.10 -> 1.02-1.05 (it loaded only the
tracker's kernels before too: the same within the noise). A DWA run loads 9 kernels (its step's
and the tracker's, at the controller's reset: not inside the first step's timing), vo 5, sbmpc
2, where importing the modules loaded 37. The step's code is the same (the same signatures):
``step_time_ms`` and whole runs in one process the same within the noise (dwa 0.076-0.082 s
before, 0.078-0.082 after), the outputs of the 384 identity jobs the same bytes.

Usage: python benchmarks/bench_simulate.py [--runs 7] [--base REV] [--no-steps] [--targets]
       [--startup] [--ships] [--scenarios] [--periods [--base-tree DIR]]
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

from usvtool.clearance import Clearance
from usvtool.grid import read_grid
from usvtool.sim import memory
from usvtool.sim.controllers import (
    CONTROLLERS,
    DynamicWindow,
    Own,
    Targets,
    World,
    make_controller,
)
from usvtool.sim.run import SimOptions, simulate
from usvtool.sim.scenario import read_scenario
from usvtool.sim.vessel import preset

sys.path.insert(0, str(Path(__file__).resolve().parent))
import revision  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
OWN = Own(250.0, 20.0, math.pi / 2, 4.0, 0.0)  # env1's open water south of the islands
TARGETS = Targets(
    np.array([[250.0, 60.0], [280.0, 40.0], [220.0, 40.0]]),
    np.array([[0.0, -3.0], [-2.0, 0.0], [2.0, 0.0]]),
    np.full(3, 2.5),
)
#: The last revision with the NumPy core (before the compiled kernels and the parts).
BASE = "6480c82"
#: The configuration of the issue's second speed figure: 3 s at 0.1 s (the defaults: 10 s at 0.2).
SPEC = {"horizon": 3.0, "step": 0.1}
COUNTS = (1, 3, 10, 30, 50, 100, 300)


def previous_controllers(base: str, tmp: Path):
    """The controllers module of revision ``base`` (its base, the five controllers and its own
    vessel module, loaded under other names beside the current package): its ``make`` and its
    ``World``, ``Own``, ``Targets``."""
    renames = {
        "from usvtool.sim import vessel as vessel_model": "import prev_vessel as vessel_model",
        "usvtool.sim.controllers.base": "prev_base",
        "usvtool.sim.controllers.dwa": "prev_dwa",
        "usvtool.sim.controllers.udwa": "prev_udwa",
    }
    modules = {}
    for name in ("vessel", "base", "dwa", "ccdwa", "gdwa", "udwa", "udwa_plus"):
        path = "usvtool/sim/vessel.py" if name == "vessel" else f"usvtool/sim/controllers/{name}.py"
        source = revision.source_at(base, path)
        for old, new in renames.items():
            source = source.replace(old, new)
        modules[name] = revision.load_module(f"prev_{name}", source, tmp)
    classes = {m.__dict__[c].name: m.__dict__[c] for m, c in (
        (modules["dwa"], "DWA"), (modules["gdwa"], "GDWA"), (modules["ccdwa"], "CCDWA"),
        (modules["udwa"], "UDWA"), (modules["udwa_plus"], "UDWAPlus"))}  # fmt: skip
    base_module = modules["base"]
    return (lambda name, **params: classes[name](**params)), base_module, modules["vessel"]


def best_ms(fn, runs: int, calls: int = 50) -> float:
    """The mean time of one call in the fastest of ``runs`` runs of ``calls`` calls (ms)."""
    fn()
    best = math.inf
    for _ in range(runs):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        best = min(best, (time.perf_counter() - t0) / calls)
    return best * 1e3


def side_by_side(now, before, runs: int) -> tuple[float, float]:
    """(now, before): each the best of ``runs`` runs, the two alternating run by run (the
    machine's load falls on both alike)."""
    a = b = math.inf
    for _ in range(runs):
        a = min(a, best_ms(now, 1))
        b = min(b, best_ms(before, 1))
    return a, b


class Step:
    """One controller's step in one world, now and at the base revision."""

    def __init__(self, prev, name: str, params: dict, clearance, ship, goal, targets):
        make, old, _ = prev
        self.now = make_controller(name, **params)
        self.now.reset(World(ship, goal, clearance))
        self.before = make(name, **params)
        self.before.reset(old.World(ship, goal, clearance))
        self.own_now, self.own_before = OWN, old.Own(*vars(OWN).values())
        self.targets = targets
        self.targets_before = old.Targets(targets.pos, targets.vel, targets.length)

    def samples(self) -> int:
        return self.now.rollouts(self.own_now, self.targets).v.size

    def same_choice(self) -> bool:
        a = self.now.decide(self.own_now, self.targets)
        b = self.before.decide(self.own_before, self.targets_before)
        return (a.v, a.omega, a.events) == (b.v, b.omega, b.events)

    def times(self, runs: int) -> tuple[float, float]:
        return side_by_side(lambda: self.now.decide(self.own_now, self.targets),
                            lambda: self.before.decide(self.own_before, self.targets_before),
                            runs)  # fmt: skip


#: The controllers with a base revision to compare with: the DWA family.
DWA_CONTROLLERS = tuple(n for n, cls in CONTROLLERS.items() if issubclass(cls, DynamicWindow))
#: The field's baselines (issue 33), timed beside dwa at the same step; no base revision.
BASELINES = ("vo",)


def baselines(runs: int) -> None:
    """One step of each baseline controller beside dwa's: 3 targets, env1's grid, defaults."""
    field = Clearance(read_grid(ROOT / "charts" / "env1.tif"))
    ship, goal = preset("iwso-dwa-usv"), np.array([250.0, 480.0])
    print("\nthe baselines beside dwa, one control step: 3 targets, env1's grid, defaults (ms, "
          "best of runs of 50 steps)")  # fmt: skip
    for name in ("dwa", *(b for b in BASELINES if b in CONTROLLERS)):
        c = make_controller(name)
        c.reset(World(ship, goal, field))
        print(f"{name:10} {best_ms(lambda c=c: c.decide(OWN, TARGETS), runs):7.3f}")


def sbmpc_steps(runs: int) -> None:
    """sbmpc (issue 33) beside dwa: its re-evaluation step (every call evaluates the 52
    behaviours over the horizon: ``update=0``) and its mean step at the defaults (one
    re-evaluation a second, the behaviour held between: 1 in 10 steps at 0.1 s)."""
    if "sbmpc" not in CONTROLLERS:
        return
    field = Clearance(read_grid(ROOT / "charts" / "env1.tif"))
    ship, goal = preset("iwso-dwa-usv"), np.array([250.0, 480.0])
    print("\nsbmpc beside dwa, one control step: 3 targets, env1's grid (ms, best of runs of 50 "
          "steps)")  # fmt: skip
    for label, name, params in (("dwa", "dwa", {}),
                                ("sbmpc re-evaluation", "sbmpc", {"update": 0.0}),
                                ("sbmpc mean (1 s hold)", "sbmpc", {})):  # fmt: skip
        c = make_controller(name, **params)
        c.reset(World(ship, goal, field))
        print(f"{label:22} {best_ms(lambda c=c: c.decide(OWN, TARGETS), runs):7.3f}")


def steps(prev, runs: int) -> None:
    field = Clearance(read_grid(ROOT / "charts" / "env1.tif"))
    ship, goal = preset("iwso-dwa-usv"), np.array([250.0, 480.0])
    print("one control step: 3 targets, env1's grid (ms, best of runs of 50 steps; now, the "
          "base revision's NumPy core in the same process, and the ratio)")  # fmt: skip
    print(f"{'controller':10} {'samples':>7} | {'defaults: now':>13} {'before':>7} {'x':>5} | "
          f"{'3 s at 0.1 s: now':>17} {'before':>7} {'x':>5} | same choice")  # fmt: skip
    for name in DWA_CONTROLLERS:
        cells, same = [], True
        for params in ({}, SPEC):
            step = Step(prev, name, params, field, ship, goal, TARGETS)
            same &= step.same_choice()
            now, before = step.times(runs)
            cells.append(f"{now:7.3f} {before:7.3f} {before / now:5.1f}")
        print(f"{name:10} {step.samples():7d} | {cells[0]:>27} | {cells[1]:>31} | {same}")
    plain = plain_module()
    c = make_controller("dwa", **SPEC, domain=False)  # the plain loop knows no domain
    c.reset(World(ship, goal, field))
    r = c.rollouts(OWN, TARGETS)
    samples = list(zip(r.v, r.omega, strict=True))
    grid, metres = field.grid, field.metres.tolist()
    left, _, _, top = grid.bounds

    def lookup(x, y):  # the plain way: one cell at a time, in Python
        col, row = int((x - left) // grid.cell_size), int((top - y) // grid.cell_size)
        inside = 0 <= row < grid.height and 0 <= col < grid.width
        return metres[row][col] if inside else 0.0

    def loop():
        return plain.choose(OWN, TARGETS, samples, goal=goal, length=ship.length,
                            times=c.times, weights=c.params, clearance=lookup)  # fmt: skip

    assert loop()[0] is not None  # the plain loop finds a free sample, as the core does
    fast = best_ms(lambda: c.decide(OWN, TARGETS), runs)
    slow = best_ms(loop, 3, calls=2)
    print(f"dwa, 3 s at 0.1 s, no domain: plain per-sample loop {slow:.1f} ms, compiled "
          f"{fast:.3f} ms: {slow / fast:.0f} x")  # fmt: skip


def plain_module():
    path = ROOT / "tests" / "sim" / "plain_dwa.py"
    spec = importlib.util.spec_from_file_location("plain_dwa", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def crowd(k: int, radius: float, rng) -> Targets:
    """``k`` targets of 15 m spread uniformly over a disc of ``radius`` metres around the own
    ship (none within 20 m), at 0-6 m/s on random courses."""
    r = np.sqrt(rng.uniform((20 / radius) ** 2, 1, k)) * radius
    bearing = rng.uniform(0, 2 * np.pi, k)
    pos = np.column_stack([OWN.x + r * np.cos(bearing), OWN.y + r * np.sin(bearing)])
    course, speed = rng.uniform(0, 2 * np.pi, k), rng.uniform(0, 6, k)
    return Targets(pos, np.column_stack([speed * np.cos(course), speed * np.sin(course)]),
                   np.full(k, 15.0))  # fmt: skip


def many_targets(prev, runs: int) -> None:
    ship, goal = preset("udwa-usv"), np.array([250.0, 900.0])
    print("\none udwa step at the defaults (462 samples, 10 s at 0.2 s; the UDWA boat at 4 m/s, "
          "open water) against the number of targets (ms, best of runs of 50 steps)")  # fmt: skip
    print(f"{'targets':>7} | {'within 100 m: now':>17} {'before':>7} | "
          f"{'over 2 km: now':>14} {'before':>7} | same choice")  # fmt: skip
    for k in COUNTS:
        cells, same = [], True
        for radius in (100.0, 2000.0):
            targets = crowd(k, radius, np.random.default_rng(k))
            step = Step(prev, "udwa", {}, None, ship, goal, targets)
            same &= step.same_choice()
            now, before = step.times(max(2, runs // (1 + k // 30)))
            cells.append(f"{now:7.3f} {before:7.3f}")
        print(f"{k:7d} | {cells[0]:>25} | {cells[1]:>22} | {same}")


def run(code: str, env=None) -> float:
    """Wall seconds of ``python -c code`` in a fresh process."""
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], check=True, env=env, cwd=ROOT)
    return time.perf_counter() - t0


#: Every rollout kernel loaded (their signatures are loaded at the first call, not at import).
LOAD_ALL = ("from usvtool.sim import rollout_kernels as k; "
            "k.load(*[n for n, v in vars(k).items() if isinstance(v, k.Dispatcher)])")  # fmt: skip


def process_cpu(args: list[str], runs: int = 5) -> float:
    """The least CPU seconds (user + system) of ``usvtool *args`` in a fresh process."""
    best = float("inf")
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(runs):
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            subprocess.run([sys.executable, "-m", "usvtool.cli", *args], check=True, cwd=tmp,
                           stdout=subprocess.DEVNULL)  # fmt: skip
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            best = min(best, after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return best


def startup() -> None:
    print("\nCPU of a usvtool simulate process, emergency head-on scene 0 (s, best of 5)")
    for controller in ("udwa", "dwa", "vo", "sbmpc", "gdwa"):
        cpu = process_cpu(["simulate", "--family", "emergency", "--kind", "head-on", "--scene",
                           "0", "--controller", controller, "--seed", "1", "-o", "t.csv",
                           "--events", "e.json", "--scenario-out", "s.yaml"])  # fmt: skip
        print(f"{controller:6} {cpu:5.2f}")
    print("\nnumba's start-up (a fresh process each, best of 3; s)")
    numpy_s = min(run("import numpy") for _ in range(3))
    numba_s = min(run("import numpy, numba") for _ in range(3))
    cached = min(run(LOAD_ALL) for _ in range(3))
    with tempfile.TemporaryDirectory() as cache:  # an empty cache: every kernel compiled
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        fresh = run(LOAD_ALL, env)
    print(f"python + numpy {numpy_s:.2f}; + numba {numba_s:.2f} (numba's import "
          f"{numba_s - numpy_s:.2f}); + the kernels from the cache {cached:.2f} "
          f"({cached - numba_s:.2f} more); compiled afresh {fresh:.2f}")  # fmt: skip
    print("\nusvtool simulate from the command line (s, best of 3: the whole run; the same "
          "scenario cut to one step: the start-up, reading, evaluating and writing; the "
          "difference: the stepping)")  # fmt: skip
    with tempfile.TemporaryDirectory() as tmp:
        for name in ("emergency-head-on", "env1-crossing-port", "rudee-inlet-channel"):
            path = ROOT / "charts" / "scenarios" / f"{name}.yaml"
            cut = one_step(path, Path(tmp))
            whole = min(simulate_wall(path, Path(tmp)) for _ in range(3))
            start = min(simulate_wall(cut, Path(tmp)) for _ in range(3))
            print(f"{name:24} {whole:5.2f} {start:5.2f} {whole - start:5.2f}")


def simulate_wall(path: Path, tmp: Path) -> float:
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", "from usvtool.cli import main; main()", "simulate",
                    str(path), "-o", str(tmp / "t.csv")], check=True, capture_output=True)
    return time.perf_counter() - t0


def one_step(path: Path, tmp: Path) -> Path:
    """A copy of scenario ``path`` in ``tmp`` that lasts one step (its files named absolutely)."""
    data = yaml.safe_load(path.read_text())
    data["sim"]["duration"] = data["sim"]["dt"]
    here = path.parent

    def absolute(name):
        return str((here / name).resolve())

    for key in ("map", "route"):
        if key in data:
            data[key] = absolute(data[key])
    if isinstance(data.get("weather"), dict) and "field" in data["weather"]:
        data["weather"]["field"] = absolute(data["weather"]["field"])
    for target in data.get("targets", []):
        if "track" in target:
            target["track"] = absolute(target["track"])
    cut = tmp / f"{path.stem}-one-step.yaml"
    cut.write_text(yaml.safe_dump(data))
    return cut


def tracks_scene(d: Path, ships: int, duration: float, seed: int = 0) -> Path:
    """A scene of ``ships`` replayed tracks in ``d`` (see the module docstring): the UDWA boat
    from (0, 0) north at 5 m/s toward a goal out of reach, on open water."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration + 10.0, 10.0)
    targets = []
    for i in range(ships):
        mid = rng.uniform(-1500, 1500, 2) + (0, 2.5 * duration)  # the square rides along
        course, speed = rng.uniform(0, 2 * np.pi), rng.uniform(1, 8)
        ahead = (t - duration / 2) * speed
        xy = mid + np.column_stack([ahead * np.cos(course), ahead * np.sin(course)])
        rows = "\n".join(f"{a:g},{x:.2f},{y:.2f}" for a, (x, y) in zip(t, xy, strict=True))
        (d / f"t{i}.csv").write_text("t,x,y\n" + rows + "\n")
        targets.append({"name": f"t{i}", "track": f"t{i}.csv", "speed": 0, "length": 15})
    scene = {"name": f"tracks-{ships}", "sim": {"dt": 0.1, "duration": duration,
                                                "goal_tolerance": 5},
             "own": {"start": [0, 0], "goal": [0, 100000], "heading": 0, "speed": 5,
                     "vessel": "udwa-usv"},
             "targets": targets, "controller": {"name": "udwa"}}  # fmt: skip
    path = d / f"tracks-{ships}-{duration:g}.yaml"
    path.write_text(yaml.safe_dump(scene))
    return path


def many_ships() -> None:
    import bench_memory

    print("\nmany ships: replayed tracks (MiB: the peak resident size, the guard's estimate)")
    print(f"{'ships':>5} {'steps':>6} | {'peak':>6} {'estimate':>8} | {'ms/step':>7} {'wall s':>6}")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        for ships in (30, 100, 300):
            for duration in (60.0, 120.0, 240.0):
                path = tracks_scene(d, ships, duration)
                t0 = time.perf_counter()
                peak, s = bench_memory.measure("simulate", path, "-o", d / "t.csv")
                wall = time.perf_counter() - t0
                steps = round(duration / 0.1)
                need = memory.run_need(memory.run_parts(make_controller("udwa"), steps, ships + 1))
                rows.append((ships + 1, steps, peak))
                print(f"{ships:5d} {steps:6d} | {peak / 2**20:6.0f} {need / 2**20:8.0f} | "
                      f"{s['step_time_ms']:7.3f} {wall:6.2f}")  # fmt: skip
        a = np.array([[1.0, k * n] for k, n, _ in rows])
        peaks = np.array([p for *_, p in rows], float)
        (fixed, per), *_ = np.linalg.lstsq(a, peaks, rcond=None)
        worst = np.abs(a @ (fixed, per) - peaks).max()
        print(f"peak = {fixed / 2**20:.0f} MiB + {per:.0f} B x ships x steps; worst residual "
              f"{worst / 2**20:.1f} MiB")  # fmt: skip
        refused = subprocess.run(
            [sys.executable, "-c", "from usvtool.cli import main; main()", "simulate",
             str(tracks_scene(d, 300, 3600.0)), "-o", str(d / "t.csv"), "--max-memory", "1G"],
            capture_output=True, text=True,
        )  # fmt: skip
        print(f"300 tracks for an hour under --max-memory 1G: exit {refused.returncode}, "
              f"{refused.stderr.strip()}")  # fmt: skip


def scenarios() -> None:
    print("\nbundled scenarios, each with its own controller")
    print(f"{'scenario':34} {'controller':10} {'sim s':>7} {'steps':>6} {'wall s':>7} "
          f"{'ms/step':>8} {'arrived':>7}")  # fmt: skip
    for path in sorted((ROOT / "charts" / "scenarios").glob("*.yaml")):
        scenario = read_scenario(path)
        t0 = time.perf_counter()
        result = simulate(scenario, SimOptions())
        wall = time.perf_counter() - t0
        s = result.summary()
        n = len(result.trace.t) - 1
        print(f"{path.stem:34} {s['controller']:10} {s['time_s']:7.1f} {n:6d} {wall:7.2f} "
              f"{s['step_time_ms']:8.3f} {str(s['arrived']):>7}")  # fmt: skip


#: The runs of ``--periods``: (family, kind, scene) and the controllers.
PERIOD_SCENES = (("imazu", "13", 0), ("emergency", "crossing", 0))
PERIOD_CONTROLLERS = ("dwa", "gdwa", "ccdwa", "udwa", "udwa+", "vo", "sbmpc")


def period_run(path: Path, name: str) -> tuple[float, float, int]:
    """One run of scenario ``path`` with controller ``name``, seed 1, as ``usvtool simulate``
    loops (observe, decide, advance): (s per period, s deciding per period, periods)."""
    from usvtool.sim import run as sim_run

    scenario = read_scenario(path)
    controller = make_controller(name)
    n_steps = int(round(scenario.sim.duration / scenario.sim.dt))
    voyage = sim_run.Voyage(scenario, sim_run._Setup(scenario), n_steps, 1)
    controller.reset(voyage.world)
    decide = 0.0
    t0 = time.perf_counter()
    while not voyage.over:
        own, targets, encounter = voyage.observe()
        t1 = time.perf_counter()
        d = controller.decide(own, targets, encounter)
        decide += time.perf_counter() - t1
        voyage.advance(d.v, d.omega, d.events)
    loop = time.perf_counter() - t0
    return loop / voyage.step, decide / voyage.step, voyage.step


def periods(runs: int, base_tree: str | None) -> None:
    """Whole runs per period (the module docstring, item 6): now, in this process, and, with
    ``base_tree``, another checkout's ``usvtool`` (``git worktree add /tmp/ref REV``) in a
    process of its own (``--period-run``), the two alternating run by run."""
    from usvtool.sim.families import make_scene, write_scene

    print(f"\nwhole runs, ms per period (the loop; deciding), best of {runs} runs, seed 1"
          + (f"; beside {base_tree}" if base_tree else ""))  # fmt: skip
    with tempfile.TemporaryDirectory() as tmp:
        for family, kind, number in PERIOD_SCENES:
            path = Path(tmp) / f"{family}-{kind}.yaml"
            write_scene(make_scene(family, kind, number), path)
            for name in PERIOD_CONTROLLERS:
                now = before = (math.inf, math.inf)
                steps = period_run(path, name)[2]  # and a first run, warming up
                for _ in range(runs):
                    now = min(now, period_run(path, name)[:2])
                    if base_tree:
                        env = {**os.environ, "PYTHONPATH": base_tree}
                        out = subprocess.run([sys.executable, __file__, "--period-run", str(path),
                                              name], env=env, check=True, capture_output=True,
                                             text=True).stdout.split()  # fmt: skip
                        before = min(before, (float(out[0]), float(out[1])))
                row = f"{family} {kind} {number:<3} {name:6} {steps:5d} periods: " \
                      f"{now[0] * 1e3:6.3f} ({now[1] * 1e3:6.3f})"  # fmt: skip
                if base_tree:
                    row += f" | before {before[0] * 1e3:6.3f} ({before[1] * 1e3:6.3f}) | " \
                           f"x {before[0] / now[0]:4.2f} ({before[1] / now[1]:4.2f})"  # fmt: skip
                print(row, flush=True)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--base", default=BASE, help="the revision to compare with (the NumPy core)")
    ap.add_argument("--no-steps", action="store_true")
    ap.add_argument("--targets", action="store_true", help="the step against the targets")
    ap.add_argument("--startup", action="store_true", help="numba's start-up, the command line")
    ap.add_argument("--ships", action="store_true", help="memory and time of many replayed tracks")
    ap.add_argument("--scenarios", action="store_true", help="also run the bundled scenarios")
    ap.add_argument("--periods", action="store_true", help="whole runs' time per period")
    ap.add_argument("--base-tree", help="--periods: also another checkout's (a directory)")
    ap.add_argument("--period-run", nargs=2, metavar=("SCENARIO", "CONTROLLER"),
                    help="one run's s per period and deciding (--base-tree's processes)")
    args = ap.parse_args(argv)
    if args.period_run:  # the second of two runs (the first warms up), as --periods times
        for _ in range(2):
            loop, decide, _ = period_run(Path(args.period_run[0]), args.period_run[1])
        print(loop, decide)
        return
    with tempfile.TemporaryDirectory() as tmp:
        prev = previous_controllers(args.base, Path(tmp)) if not args.no_steps or args.targets \
            else None  # fmt: skip
        if not args.no_steps:
            steps(prev, args.runs)
            baselines(args.runs)
            sbmpc_steps(args.runs)
        if args.targets:
            many_targets(prev, args.runs)
    if args.startup:
        startup()
    if args.ships:
        many_ships()
    if args.scenarios:
        scenarios()
    if args.periods:
        periods(args.runs, args.base_tree)


if __name__ == "__main__":
    sys.exit(main())
