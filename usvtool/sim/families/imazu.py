"""``imazu``: the 22 encounters of the Imazu problem (Imazu 1987, as tabulated by Sawada, Sato
and Majima 2021, J. Mar. Sci. Technol. 26, Table 4), at the published proportions by default
(docs/families.md gives the table, its sources, this reading of them and the two scales).

Every ship meets the own ship at one point, the CPA, after ``tcpa`` seconds: the own ship from
(0, 0) heading north at ``own_speed`` (CPA at (0, own_speed x tcpa), goal as far beyond it),
each target on its course at the own ship's speed, but a target ahead on the own course (the
one being overtaken), at ``overtaken_speed`` times it, so it starts between the own ship and
the CPA. Targets are ``length`` m long and keep course and speed; the own ship
is ``own_length`` m long, its top speed ``top_speed`` times ``own_speed`` (each written as a
vessel override where it differs from the preset's). Not seeded: each case is one scene.

The defaults keep the published proportions (:data:`PUBLISHED`): 5 m ships at 4 m/s, the CPA
150 s ahead (beyond the verdicts' onset, a TCPA of 120 s, as the published 30 min are beyond a
ship's), the CPA 600 m = 120 lengths off; :data:`COMPRESSED` gives the earlier USV scale (15 m at
7 m/s, 60 s, every encounter starting inside the onset).

Promise: every target is of its tabulated class at the start (:data:`CASES`), on a collision
course (CPA under 1 m, at ``tcpa``), and clear (:func:`~.base.crowding`).
"""

from __future__ import annotations

import numpy as np

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
    toward,
    vessel_option,
)
from usvtool.sim.vessel import PRESETS

HO, GW, SO, OT = "head-on", "crossing-give-way", "crossing-stand-on", "overtaking"
#: Case -> its targets: (compass course, overtaken, the class at the start). Courses of the
#: table (its -90 is 270); "overtaken": the target ahead on the own course, slower.
CASES: dict[str, tuple[tuple[float, bool, str], ...]] = {
    "01": ((180, False, HO),),
    "02": ((270, False, GW),),
    "03": ((0, True, OT),),
    "04": ((45, False, SO),),
    "05": ((180, False, HO), (270, False, GW)),
    "06": ((350, False, GW), (315, False, GW)),
    "07": ((0, True, OT), (315, False, GW)),
    "08": ((180, False, HO), (270, False, GW)),
    "09": ((330, False, GW), (270, False, GW)),
    "10": ((270, False, GW), (15, False, SO)),
    "11": ((90, False, SO), (330, False, GW)),
    "12": ((315, False, GW), (350, False, GW)),
    "13": ((180, False, HO), (10, False, SO), (45, False, SO)),
    "14": ((350, False, GW), (315, False, GW), (270, False, GW)),
    "15": ((0, True, OT), (315, False, GW), (270, False, GW)),
    "16": ((45, False, SO), (90, False, SO), (270, False, GW)),
    "17": ((0, True, OT), (10, False, SO), (315, False, GW)),
    "18": ((225, False, GW), (345, False, GW), (330, False, GW)),
    "19": ((15, False, SO), (345, False, GW), (225, False, GW)),
    "20": ((0, True, OT), (345, False, GW), (270, False, GW)),
    "21": ((345, False, GW), (15, False, SO), (270, False, GW)),
    "22": ((0, True, OT), (315, False, GW), (270, False, GW)),
}


#: The defaults: the published proportions (docs/families.md).
PUBLISHED = {"own_speed": 4.0, "tcpa": 150.0, "length": 5.0, "own_length": 5.0, "duration": 450.0}
#: The compressed scale the family had before (udwa-usv at its 7 m/s and length, 60 s to the CPA):
#: ``--family-option`` each of these.
COMPRESSED = {"own_speed": 7.0, "tcpa": 60.0, "length": 15.0, "own_length": 15.0,
              "duration": 180.0}  # fmt: skip


class Imazu(Family):
    name = "imazu"
    kinds = tuple(CASES)
    seeded = False
    max_draws = 1  # one scene per case: a second draw would be the same
    controller = "udwa"
    parameters = {
        "own_speed": Param(PUBLISHED["own_speed"], "the own ship's speed, m/s "
                           "(every target's but the overtaken)", POSITIVE),
        "tcpa": Param(PUBLISHED["tcpa"], "the time at which every ship reaches the CPA, s",
                      POSITIVE),
        "overtaken_speed": Param(0.7, "the overtaken target's speed over the own ship's", POSITIVE),
        "length": Param(PUBLISHED["length"], "the targets' length, m", POSITIVE),
        "own_length": Param(PUBLISHED["own_length"], "the own ship's length, m", POSITIVE),
        "top_speed": Param(1.0, "the own ship's top speed over own_speed (1: it cannot speed "
                           "up, so it meets the targets as tabulated)", POSITIVE),
        "vessel": vessel_option("udwa-usv"),
        "duration": duration_option(PUBLISHED["duration"]),
    }
    about = {case: ", ".join(f"{c[2]} (course {c[0]:g})" for c in ships)
             for case, ships in CASES.items()}  # fmt: skip

    def draw(self, kind: str, rng: np.random.Generator, opts: dict) -> Draw:
        v, tcpa = opts["own_speed"], opts["tcpa"]
        cpa = (0.0, v * tcpa)
        targets = []
        for i, (course, overtaken, _) in enumerate(CASES[kind]):
            speed = v * opts["overtaken_speed"] if overtaken else v
            x, y = (round(float(c), 6) + 0.0 for c in toward(cpa, course, -speed * tcpa))
            targets.append(ship(f"ts{i + 1}", x, y, course, speed, opts["length"]))
        own = own_ship((0.0, 0.0), (0.0, 2 * v * tcpa), 0.0, v, opts["vessel"])
        preset = PRESETS[opts["vessel"]]
        for key, value in (("length", opts["own_length"]), ("max_speed", v * opts["top_speed"])):
            if value != preset[key]:  # the preset's own figures are not repeated
                own[key] = float(value)
        return Draw(scenario(own, targets, opts["duration"], self.controller))

    def reject(self, kind: str, draw: Draw, opts: dict) -> str | None:
        s = draw.scenario
        expected = [c[2] for c in CASES[kind]]
        if class_names(s) != expected:
            return f"classes {class_names(s)} not {expected}"
        at = start_situation(s)
        if (at.dcpa >= 1.0).any() or (np.abs(at.tcpa - opts["tcpa"]) > 1e-3 * opts["tcpa"]).any():
            return "a target not on a collision course at tcpa"
        return crowding(s)
