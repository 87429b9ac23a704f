"""Encounter simulation: the cost of one control step, and the wall time of the bundled scenarios.

1. One control step of each controller with three targets close by, on env1's grid: the dynamic
   window sampled at 21 x 21 (+ the current values: 462 pairs), a 3 s horizon at 0.1 s (30
   rollout steps; the target's configuration) and the defaults (10 s at 0.2 s). Beside it the
   plain way, the same objective one sample at a time in Python (tests/sim/plain_dwa.py,
   PythonRobotics' style), and the ratio. Median of repeated runs.
2. Every scenario in charts/scenarios/ with its own controller: simulated and wall time, steps,
   mean step time.

Usage: python benchmarks/bench_simulate.py [--repeats 300] [--scenarios] [--no-steps]
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import sys
import time
from pathlib import Path

import numpy as np

from usvtool.clearance import Clearance
from usvtool.grid import read_grid
from usvtool.sim.controllers import CONTROLLERS, Own, Targets, World, make_controller
from usvtool.sim.run import SimOptions, simulate
from usvtool.sim.scenario import read_scenario
from usvtool.sim.vessel import preset

ROOT = Path(__file__).resolve().parent.parent
OWN = Own(250.0, 20.0, math.pi / 2, 4.0, 0.0)  # env1's open water south of the islands
TARGETS = Targets(
    np.array([[250.0, 60.0], [280.0, 40.0], [220.0, 40.0]]),
    np.array([[0.0, -3.0], [-2.0, 0.0], [2.0, 0.0]]),
    np.full(3, 2.5),
)


def plain_module():
    path = ROOT / "tests" / "sim" / "plain_dwa.py"
    spec = importlib.util.spec_from_file_location("plain_dwa", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def median_ms(fn, repeats: int) -> float:
    start = time.perf_counter()
    while time.perf_counter() - start < 0.5:  # warm up: the first calls grow the heap
        fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)) * 1e3


#: The configuration of the speed target: a 3 s horizon at 0.1 s (the controllers' defaults
#: look further, 10 s at 0.2 s: measured beside it).
SPEC = {"horizon": 3.0, "step": 0.1}


def best_ms(fn, runs: int = 7, calls: int = 100) -> float:
    best = np.inf
    for _ in range(runs):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        best = min(best, (time.perf_counter() - t0) / calls)
    return float(best) * 1e3


def steps(repeats: int) -> None:
    field = Clearance(read_grid(ROOT / "charts" / "env1.tif"))
    ship = preset("iwso-dwa-usv")
    world = World(ship, np.array([250.0, 480.0]), field)
    print("one control step: 3 targets, env1 grid (ms: median of single steps, and the mean "
          "over the fastest of 7 runs of 100 steps)")  # fmt: skip
    print(f"{'controller':10} {'samples':>7} {'3 s at 0.1 s':>15} {'defaults':>15}")
    for name in CONTROLLERS:
        cells = []
        for params in (SPEC, {}):
            c = make_controller(name, **params)
            c.reset(world)
            n = c.rollouts(OWN, TARGETS).v.size
            step = median_ms(lambda c=c: c.decide(OWN, TARGETS), repeats)
            cells.append(f"{step:7.3f} {best_ms(lambda c=c: c.decide(OWN, TARGETS)):7.3f}")
        print(f"{name:10} {n:7d} {cells[0]:>15} {cells[1]:>15}")
    plain = plain_module()
    c = make_controller("dwa", **SPEC, domain=False)  # the plain loop knows no domain
    c.reset(world)
    r = c.rollouts(OWN, TARGETS)
    samples = list(zip(r.v, r.omega, strict=True))

    grid, metres = field.grid, field.metres.tolist()
    left, _, _, top = grid.bounds

    def lookup(x, y):  # the plain way: one cell at a time, in Python
        col, row = int((x - left) // grid.cell_size), int((top - y) // grid.cell_size)
        inside = 0 <= row < grid.height and 0 <= col < grid.width
        return metres[row][col] if inside else 0.0

    def loop():
        return plain.choose(OWN, TARGETS, samples, goal=world.goal, length=ship.length,
                            times=c.times, weights=c.params, clearance=lookup)  # fmt: skip

    assert loop()[0] is not None  # the plain loop finds a free sample, as the core does

    fast = median_ms(lambda: c.decide(OWN, TARGETS), repeats)
    slow = median_ms(loop, max(3, repeats // 50))
    print(f"dwa, 3 s at 0.1 s, no domain: plain per-sample loop {slow:.1f} ms, vectorised "
          f"{fast:.3f} ms: {slow / fast:.0f} x")  # fmt: skip


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


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=300)
    ap.add_argument("--no-steps", action="store_true")
    ap.add_argument("--scenarios", action="store_true", help="also run the bundled scenarios")
    args = ap.parse_args(argv)
    if not args.no_steps:
        steps(args.repeats)
    if args.scenarios:
        scenarios()


if __name__ == "__main__":
    sys.exit(main())
