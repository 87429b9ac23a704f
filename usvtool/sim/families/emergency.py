"""``emergency``: the UDWA paper's three-ship emergencies (section 4.1), drawn around the
bundled ``charts/scenarios/emergency-*.yaml`` (their README says how those were built).

The own ship (``vessel``, 15 m ``udwa-usv``) from (0, 0) heading north at ``own_speed`` toward
(0, 450); two other ships of ``length`` keep course and speed. Drawn uniformly, in ranges that
hold the bundled scenes' values:

- ``head-on``: the target 180-300 m ahead (±5 m across), course 180 ± 5 deg at 3-6 m/s; the
  blocker 25-60 m to the own ship's starboard of it, ±30 m along, its course within 5 deg and
  its speed within 1 m/s of the target's;
- ``crossing``: the target from starboard, course 270 ± 10 deg at 3-6 m/s, on a collision
  course 8-16 s ahead; the follower 40-80 m astern of it, same course and speed;
- ``overtaking``: the target 80-150 m ahead (±5 m across), course 0 ± 5 deg at 1.5-3 m/s; the
  blocker 30-50 m to starboard of it, ±20 m along, same course and speed.

Promise: the target is of the kind's class at the start (head-on, crossing-give-way,
overtaking), the crossing target on a collision course (CPA under one own length), the blocker
to the own ship's starboard of the target, and every ship clear (:func:`~.base.crowding`).
Scene ``s`` of kind ``k`` keeps the seed of the generator this family was before it moved here
(tests/sim/emergencies.py: scene ``3 s + k``, ``k`` the kind's index), so its scenes are those
the benchmarks and docs/controllers.md measured.
"""

from __future__ import annotations

import numpy as np

from usvtool.angles import wrap180
from usvtool.params import POSITIVE, Param
from usvtool.sim.families.base import (
    Draw,
    Family,
    class_names,
    crowding,
    duration_option,
    own_ship,
    scenario,
    ship,
    start_situation,
    vessel_option,
)
from usvtool.sim.vessel import PRESETS

GOAL = (0.0, 450.0)
CLASS = {"head-on": "head-on", "crossing": "crossing-give-way", "overtaking": "overtaking"}


class Emergency(Family):
    name = "emergency"
    kinds = ("head-on", "crossing", "overtaking")
    controller = "udwa"
    parameters = {
        "own_speed": Param(7.0, "the own ship's speed at the start, m/s", POSITIVE),
        "length": Param(15.0, "the other ships' length, m", POSITIVE),
        "vessel": vessel_option("udwa-usv"),
        "duration": duration_option(150.0),
    }
    about = {"head-on": "a target dead ahead, a blocker to starboard of it",
             "crossing": "a target from starboard on a collision course, a follower astern",
             "overtaking": "a slower target ahead, a blocker to starboard of it"}  # fmt: skip

    def generator(self, kind: str, scene: int) -> np.random.Generator:
        return np.random.default_rng(3 * scene + self.kinds.index(kind))

    def draw(self, kind: str, rng: np.random.Generator, opts: dict) -> Draw:
        u = rng.uniform
        length, v_own = opts["length"], opts["own_speed"]
        if kind == "head-on":
            rng_m, course, speed = u(180, 300), 180 + u(-5, 5), u(3, 6)
            off, along = u(25, 60), u(-30, 30)
            targets = [ship("target", u(-5, 5), rng_m, course, speed, length),
                       ship("blocker", off, rng_m + along, course + u(-5, 5), speed + u(-1, 1),
                            length)]  # fmt: skip
        elif kind == "crossing":  # both would be at (0, v_own tau) after tau seconds
            tau, course, speed, gap = u(8, 16), 270 + u(-10, 10), u(3, 6), u(40, 80)
            heading = np.radians(90 - course)  # the target's direction, mathematical
            dx, dy = np.cos(heading), np.sin(heading)
            x0, y0 = -dx * speed * tau, v_own * tau - dy * speed * tau
            targets = [
                ship("target", x0, y0, course, speed, length),
                ship("follower", x0 - dx * gap, y0 - dy * gap, course, speed, length),
            ]
        else:
            rng_m, speed, off = u(80, 150), u(1.5, 3), u(30, 50)
            course = u(-5, 5)
            targets = [
                ship("target", u(-5, 5), rng_m, course, speed, length),
                ship("blocker", off, rng_m + u(-20, 20), course, speed, length),
            ]
        own = own_ship((0.0, 0.0), GOAL, 0.0, v_own, opts["vessel"])
        return Draw(scenario(own, targets, opts["duration"], self.controller))

    def reject(self, kind: str, draw: Draw, opts: dict) -> str | None:
        s = draw.scenario
        if class_names(s)[0] != CLASS[kind]:
            return f"target not {CLASS[kind]}"
        situation = start_situation(s)
        if kind == "crossing":
            if situation.dcpa[0] >= PRESETS[opts["vessel"]]["length"]:
                return "target not on a collision course"
        elif wrap180(situation.beta[1]) <= wrap180(situation.beta[0]):
            return "blocker not to starboard of the target"
        return crowding(s)
