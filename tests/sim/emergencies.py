"""Seeded three-ship emergencies around the UDWA paper's section 4.1 (charts/scenarios/README.md,
"Emergency three-ship encounters"): for tests/sim/test_emergencies.py and
benchmarks/bench_random_encounters.py (``--family emergency``).

Scene ``seed`` is a head-on, a crossing or an overtaking emergency by ``seed % 3``; its geometry
is drawn from one generator seeded by ``seed``, in ranges that hold the bundled scenes' values:

- head-on: the target 180-300 m ahead (±5 m across), course 180 ± 5 deg at 3-6 m/s; the blocker
  25-60 m to the own ship's starboard of it, ±30 m along, its course within 5 deg and its speed
  within 1 m/s of the target's;
- crossing: the target from starboard, course 270 ± 10 deg at 3-6 m/s, on a collision course
  8-16 s ahead; the follower 40-80 m astern of it, same course and speed;
- overtaking: the target 80-150 m ahead (±5 m across), course 0 ± 5 deg at 1.5-3 m/s; the
  blocker 30-50 m to starboard of it, ±20 m along, same course and speed.

The own ship is the ``udwa-usv`` from (0, 0) heading north at 7 m/s toward (0, 450); every ship
is 15 m long and the others keep course and speed.
"""

from __future__ import annotations

import numpy as np

KINDS = ("head-on", "crossing", "overtaking")


def kind(seed: int) -> str:
    """The kind of scene ``seed``."""
    return KINDS[seed % 3]


def ships(seed: int) -> tuple[str, list[dict]]:
    """The kind of emergency scene ``seed`` and its two other ships (scenario ``targets``)."""
    u = np.random.default_rng(seed).uniform
    what = kind(seed)

    def ship(name, x, y, heading, speed):
        return {"name": name, "start": [float(x), float(y)], "heading": float(heading),
                "speed": float(speed), "length": 15.0}  # fmt: skip

    if what == "head-on":
        rng_m, course, speed = u(180, 300), 180 + u(-5, 5), u(3, 6)
        off, along = u(25, 60), u(-30, 30)
        return what, [ship("target", u(-5, 5), rng_m, course, speed),
                      ship("blocker", off, rng_m + along, course + u(-5, 5),
                           speed + u(-1, 1))]  # fmt: skip
    if what == "crossing":  # both would be at (0, 7 tau) after tau seconds
        tau, course, speed, gap = u(8, 16), 270 + u(-10, 10), u(3, 6), u(40, 80)
        heading = np.radians(90 - course)  # the target's direction, mathematical
        dx, dy = np.cos(heading), np.sin(heading)
        x0, y0 = -dx * speed * tau, 7 * tau - dy * speed * tau
        return what, [ship("target", x0, y0, course, speed),
                      ship("follower", x0 - dx * gap, y0 - dy * gap, course, speed)]
    rng_m, speed, off = u(80, 150), u(1.5, 3), u(30, 50)
    course = u(-5, 5)
    return what, [ship("target", u(-5, 5), rng_m, course, speed),
                  ship("blocker", off, rng_m + u(-20, 20), course, speed)]


def scene(seed: int, controller: str) -> dict:
    """Scene ``seed`` as a scenario mapping (:func:`usvtool.sim.scenario.parse`)."""
    what, targets = ships(seed)
    return {
        "name": f"random-emergency-{what}-{seed}",
        "sim": {"dt": 0.1, "duration": 150, "goal_tolerance": 5},
        "own": {"start": [0, 0], "goal": [0, 450], "heading": 0, "speed": 7,
                "vessel": "udwa-usv"},
        "targets": targets,
        "controller": {"name": controller},
    }  # fmt: skip
