"""Encounter controllers on seeded random scenes: collisions, arrivals, closest distances.

Each scene: the own ship from (0, 0) heading north toward a goal straight ahead, among one to
three targets on straight courses, placed and aimed at random (uniform, from one generator
seeded by the scene's number, so scene ``i`` is the same for every controller and every run).
Two families, scaled to the vessel (``--family``):

- ``small`` (the random geometries of tests/sim/test_properties.py): the ``iwso-dwa-usv``
  (2.5 m) at 4 m/s, goal (0, 160), targets of 2.5 m at x in [-60, 60], y in [20, 150] m,
  0.5-4 m/s, 45 s;
- ``large`` (the UDWA paper's boat and the scale of its emergency encounters): the ``udwa-usv``
  (15 m) at 7 m/s, goal (0, 450), targets of 15 m at x in [-120, 120], y in [80, 400] m,
  1-6 m/s, 90 s.

- ``emergency`` (the UDWA paper's section 4.1 three-ship emergencies, varied: the scene family
  ``emergency``, usvtool/sim/families/emergency.py): the ``udwa-usv`` at 7 m/s toward (0, 450);
  scene ``i`` is scene ``i // 3`` of the kind ``i % 3`` (head-on, crossing, overtaking) as in
  charts/scenarios/emergency-*.yaml, with a third ship that blocks the starboard escape, its
  geometry drawn at random around the bundled one, 150 s.

For each controller the script prints the collisions, the arrivals, the median and 5th
percentile of the closest centre distance over the scenes, and the median arrival time; with
``--versus A,B``, scene by scene, how often A keeps further from every ship than B (and by 10 %
or more), per kind of scene. Not a test: figures for docs/controllers.md.

Usage: python benchmarks/bench_random_encounters.py [--scenes 60] [--family small]
       [--controllers dwa,gdwa,ccdwa,udwa] [--param NAME=VALUE ...] [--versus udwa,ccdwa ...] [-j 1]
"""

from __future__ import annotations

import argparse
import json
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from usvtool.sim.families import make_scene
from usvtool.sim.families.emergency import Emergency
from usvtool.sim.run import SimOptions, simulate
from usvtool.sim.scenario import parse

FAMILIES = {
    "small": {"vessel": "iwso-dwa-usv", "speed": 4.0, "goal": 160.0, "length": 2.5,
              "x": (-60.0, 60.0), "y": (20.0, 150.0), "v": (0.5, 4.0), "duration": 45.0},
    "large": {"vessel": "udwa-usv", "speed": 7.0, "goal": 450.0, "length": 15.0,
              "x": (-120.0, 120.0), "y": (80.0, 400.0), "v": (1.0, 6.0), "duration": 90.0},
}  # fmt: skip


def scene(family: str, seed: int, controller: str) -> dict:
    """Scene ``seed`` of ``family`` as a scenario mapping (usvtool.sim.scenario.parse)."""
    if family == "emergency":
        scenario = make_scene("emergency", emergency_kind(seed), seed // 3).draw.scenario
        return {**scenario, "controller": {"name": controller}}
    f = FAMILIES[family]
    rng = np.random.default_rng(seed)
    targets = []
    for i in range(int(rng.integers(1, 4))):
        targets.append({
            "name": f"t{i}",
            "start": [float(rng.uniform(*f["x"])), float(rng.uniform(*f["y"]))],
            "heading": float(rng.uniform(0, 360)),
            "speed": float(rng.uniform(*f["v"])),
            "length": f["length"],
        })  # fmt: skip
    return {
        "name": f"random-{family}-{seed}",
        "sim": {"dt": 0.1, "duration": f["duration"], "goal_tolerance": 5},
        "own": {"start": [0, 0], "goal": [0, f["goal"]], "heading": 0, "speed": f["speed"],
                "vessel": f["vessel"]},
        "targets": targets,
        "controller": {"name": controller},
    }  # fmt: skip


def emergency_kind(seed: int) -> str:
    """The kind of emergency scene ``seed``."""
    return Emergency.kinds[seed % 3]


def one(job: tuple) -> tuple:
    family, seed, controller, params = job
    s = simulate(parse(scene(family, seed, controller), f"scene {seed}"),
                 SimOptions(params=params)).summary()  # fmt: skip
    return (controller, seed, s["collision"] is not None, s["arrived"], s["closest_distance_m"],
            s["time_s"])  # fmt: skip


def versus(results: list[tuple], a: str, b: str, family: str) -> None:
    """Scene by scene: how often ``a`` keeps further from every ship than ``b``."""
    closest = {(r[0], r[1]): r[4] for r in results}
    collided = {(r[0], r[1]) for r in results if r[2]}
    seeds = sorted({r[1] for r in results})
    kinds = {s: emergency_kind(s) if family == "emergency" else "all" for s in seeds}
    for kind in sorted(set(kinds.values())):
        pairs = [(closest[a, s], closest[b, s]) for s in seeds if kinds[s] == kind]
        pairs = [(x, y) for x, y in pairs if x is not None and y is not None]
        further = sum(x > y for x, y in pairs)
        clearly = sum(x >= 1.1 * y for x, y in pairs)
        ratio = np.median([x / y for x, y in pairs]) if pairs else float("nan")
        hits = [sum((c, s) in collided for s in seeds if kinds[s] == kind) for c in (a, b)]
        print(f"{a} vs {b}, {kind}: further in {further} of {len(pairs)} scenes, by 10 % or more "
              f"in {clearly}; median ratio {ratio:.2f}; collisions {hits[0]} and "
              f"{hits[1]}")  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", type=int, default=60)
    ap.add_argument("--first", type=int, default=0, help="the first scene's seed")
    ap.add_argument("--family", choices=[*sorted(FAMILIES), "emergency"], default="small")
    ap.add_argument("--controllers", default="dwa,gdwa,ccdwa,udwa")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                    help="a controller parameter for every controller (JSON value or text)")
    ap.add_argument("--versus", metavar="A,B", action="append", default=[],
                    help="compare two of the controllers scene by scene (repeatable)")
    ap.add_argument("-j", "--jobs", type=int, default=1)
    args = ap.parse_args()
    params = {}
    for item in args.param:
        name, _, text = item.partition("=")
        try:
            params[name] = json.loads(text)
        except json.JSONDecodeError:
            params[name] = text
    controllers = args.controllers.split(",")
    seeds = range(args.first, args.first + args.scenes)
    jobs = [(args.family, s, c, params) for c in controllers for s in seeds]
    with ProcessPoolExecutor(args.jobs) as pool:
        results = list(pool.map(one, jobs, chunksize=4))
    print(f"{args.scenes} {args.family} scenes (seeds {seeds.start}-{seeds.stop - 1}), "
          f"params {params or 'defaults'}")  # fmt: skip
    print(f"{'controller':12} {'collisions':>10} {'arrived':>8} {'median m':>9} {'p5 m':>7} "
          f"{'median s':>9}")  # fmt: skip
    for c in controllers:
        rows = [r[1:] for r in results if r[0] == c]
        closest = np.array([r[3] for r in rows if r[3] is not None])
        times = [r[4] for r in rows if r[2]]
        print(f"{c:12} {sum(r[1] for r in rows):10d} {sum(r[2] for r in rows):8d} "
              f"{np.median(closest):9.1f} {np.percentile(closest, 5):7.1f} "
              f"{np.median(times) if times else float('nan'):9.1f}")  # fmt: skip
    for pair in args.versus:
        versus(results, *pair.split(","), args.family)


if __name__ == "__main__":
    main()
