"""The process controller's overhead per control period (``exec``, docs/protocol.md), beside the
built-in controllers' step time.

1. The protocol's round trip: the ``exec`` controller's ``decide`` with a client whose decision
   is trivial (examples/exec/client.c and client.py with ``--trivial``: they parse the message
   and reply with the present speed and yaw rate), three targets close by on env1's grid (the
   step of benchmarks/bench_simulate.py): encoding the step, writing it, the client reading,
   parsing and replying, reading and decoding the reply and checking it against the limits.
   Beside it, the parts done in this process alone: encoding one step message, and decoding
   and checking one reply. The C client is built with ``cc -O2`` into a temporary folder.
2. The built-in controllers' decision on the same step (dwa, udwa at their defaults).
3. Whole runs: the Imazu case 13 (three targets; at the family's compressed scale, 15 m ships
   at 7 m/s) and the bundled env1-head-on, each with the C and the Python client steering
   (their rule, not trivial), and with udwa: the summary's ``step_time_ms`` (the mean
   ``decide`` of the run) and the wall time.
4. The 22 Imazu cases (``--imazu``; at the compressed scale, ``imazu.COMPRESSED``; seed 1) with
   the C client, the Python client and udwa: arrived, collision, closest centre distance (the
   outcomes docs/protocol.md gives), and whether the two clients' traces are the same.

Each figure of 1 and 2 is the best of ``--runs`` runs of ``--steps`` steps (this shared 2-core
machine's timings vary by up to two times between runs; the best is the repeatable one), in
milliseconds per period. Targets (issue 32): at most 0.1 ms with the C client, 0.3 ms with the
Python client.

Usage: python benchmarks/bench_protocol.py [--runs 5] [--steps 2000] [--no-runs] [--imazu]
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from usvtool.clearance import Clearance
from usvtool.grid import read_grid
from usvtool.sim.controllers import Own, Targets, World, make_controller
from usvtool.sim.run import SimOptions, simulate
from usvtool.sim.scenario import read_scenario
from usvtool.sim.vessel import preset

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples" / "exec"
#: benchmarks/bench_simulate.py's step: env1's open water south of the islands, three targets.
OWN = Own(250.0, 20.0, math.pi / 2, 4.0, 0.0)
TARGETS = Targets(
    np.array([[250.0, 60.0], [280.0, 40.0], [220.0, 40.0]]),
    np.array([[0.0, -3.0], [-2.0, 0.0], [2.0, 0.0]]),
    np.full(3, 2.5),
)


def world() -> World:
    grid = read_grid(ROOT / "charts" / "env1.tif")
    return World(preset("iwso-dwa-usv"), np.array([250.0, 480.0]), Clearance(grid), None, None,
                 0.1, 5.0, 1, ROOT / "charts" / "env1.tif")  # fmt: skip


def per_step(controller, steps: int, runs: int) -> float:
    """The best of ``runs`` runs of the mean ``decide`` time over ``steps`` steps (ms); the
    controller is reset (for a process: started, and greeted at the first step, not timed)."""
    best = math.inf
    for _ in range(runs):
        controller.reset(WORLD)
        controller.decide(OWN, TARGETS)  # the hello, and a first step
        t0 = time.perf_counter()
        for _ in range(steps):
            controller.decide(OWN, TARGETS)
        best = min(best, (time.perf_counter() - t0) / steps * 1e3)
        controller.close()
    return best


def best_of(f, n: int, runs: int) -> float:
    """The best of ``runs`` runs of the mean time of ``f()`` over ``n`` calls (ms)."""
    best = math.inf
    for _ in range(runs):
        t0 = time.perf_counter()
        for _ in range(n):
            f()
        best = min(best, (time.perf_counter() - t0) / n * 1e3)
    return best


def build_c(folder: Path) -> Path | None:
    cc = shutil.which("cc")
    if cc is None:
        return None
    out = folder / "client"
    subprocess.run([cc, "-O2", "-o", str(out), str(EXAMPLES / "client.c"), "-lm"], check=True)
    return out


def round_trips(client_c: Path | None, steps: int, runs: int) -> list[tuple[str, float]]:
    rows = []
    clients = [("C client (--trivial)", [str(client_c), "--trivial"])] if client_c else []
    clients.append(("Python client (--trivial)",
                    [sys.executable, str(EXAMPLES / "client.py"), "--trivial"]))  # fmt: skip
    for label, command in clients:
        rows.append((f"exec, {label}", per_step(make_controller("exec", command=command),
                                                steps, runs)))  # fmt: skip
    # this process's own part: one step's message, one reply decoded and checked
    c = make_controller("exec", command=[sys.executable])
    c.world, c._step = WORLD, 12
    rows.append(("  of which: encoding one step message",
                 best_of(lambda: c._step_message(OWN, TARGETS, None), 20000, runs)))  # fmt: skip
    reply = json.dumps({"v": OWN.v, "omega": OWN.omega}).encode()
    rows.append(("  of which: decoding and checking one reply",
                 best_of(lambda: c._command(json.loads(reply), OWN), 20000, runs)))  # fmt: skip
    for name in ("dwa", "udwa"):
        rows.append((f"{name} (built in, defaults)", per_step(make_controller(name), steps // 10,
                                                              runs)))  # fmt: skip
    return rows


def whole_runs(client_c: Path | None, tmp: Path) -> list[tuple[str, str, dict, float]]:
    from usvtool.sim.families import make_scene, write_scene
    from usvtool.sim.families.imazu import COMPRESSED

    scene = make_scene("imazu", "13", 0, dict(COMPRESSED), lambda key: key)
    write_scene(scene, tmp / "imazu-13.yaml")
    scenarios = [("imazu 13", read_scenario(tmp / "imazu-13.yaml")),
                 ("env1-head-on", read_scenario(ROOT / "charts" / "scenarios" /
                                                "env1-head-on.yaml"))]  # fmt: skip
    controllers = [("C client", "exec", {"command": [str(client_c)]})] if client_c else []
    controllers += [("Python client", "exec",
                     {"command": [sys.executable, str(EXAMPLES / "client.py")]}),
                    ("udwa", "udwa", {})]  # fmt: skip
    rows = []
    for case, scenario in scenarios:
        for label, name, params in controllers:
            t0 = time.perf_counter()
            result = simulate(scenario, SimOptions(controller=name, params=params, seed=1))
            rows.append((case, label, result.summary(), time.perf_counter() - t0))
    return rows


def imazu(client_c: Path | None, tmp: Path) -> None:
    from usvtool.sim.families import make_scene, write_scene
    from usvtool.sim.families.imazu import CASES, COMPRESSED

    controllers = [("C", "exec", {"command": [str(client_c)]})] if client_c else []
    controllers += [("Python", "exec", {"command": [sys.executable, str(EXAMPLES / "client.py")]}),
                    ("udwa", "udwa", {})]  # fmt: skip
    tally = {label: [0, 0] for label, _, _ in controllers}
    for kind in CASES:
        scene = make_scene("imazu", kind, 0, dict(COMPRESSED), lambda key: key)
        write_scene(scene, tmp / f"{kind}.yaml")
        scenario = read_scenario(tmp / f"{kind}.yaml")
        cells, traces = [], []
        for label, name, params in controllers:
            r = simulate(scenario, SimOptions(controller=name, params=params, seed=1))
            s = r.summary()
            tally[label][0] += bool(s["arrived"])
            tally[label][1] += s["collision"] is not None
            cells.append(f"{label} {'arrived' if s['arrived'] else 'not arrived'}"
                         f"{', collided' if s['collision'] else ''} {s['closest_distance_m']} m")
            if name == "exec":
                traces.append((r.trace.x, r.trace.y))
        same = len(traces) < 2 or all(np.array_equal(a, b)
                                      for a, b in zip(traces[0], traces[1], strict=True))
        print(f"  {kind}: " + "; ".join(cells) + ("" if same else "  (the clients differ)"))
    for label, (arrived, collided) in tally.items():
        print(f"  {label}: {arrived} of {len(CASES)} arrived, {collided} collided")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--no-runs", action="store_true", help="skip the whole runs (3)")
    ap.add_argument("--imazu", action="store_true", help="the 22 Imazu cases (4)")
    args = ap.parse_args(argv)
    global WORLD
    WORLD = world()
    with tempfile.TemporaryDirectory() as tmp:
        client_c = build_c(Path(tmp))
        if client_c is None:
            print("no cc on this machine: the C client is left out")
        print(f"1-2. one control period, three targets (best of {args.runs} x {args.steps} "
              "steps; the built-ins' of a tenth as many), ms")  # fmt: skip
        for label, ms in round_trips(client_c, args.steps, args.runs):
            print(f"  {label:<48} {ms:8.4f}")
        if not args.no_runs:
            print("3. whole runs: the mean decide (step_time_ms) and the wall time")
            for case, label, s, wall in whole_runs(client_c, Path(tmp)):
                print(f"  {case:<13} {label:<14} {s['step_time_ms']:8.4f} ms  "
                      f"{round(s['time_s'] / 0.1):5d} steps  {wall:6.2f} s  "
                      f"arrived {s['arrived']}, closest {s['closest_distance_m']} m")
        if args.imazu:
            print("4. the 22 Imazu cases, seed 1")
            imazu(client_c, Path(tmp))


WORLD: World | None = None

if __name__ == "__main__":
    main()
