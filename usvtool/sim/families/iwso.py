"""``iwso``: the IWSO-DWA paper's encounter kinds (section 5.3: overtaking, head-on, port side
and starboard crossing) and static obstacles on the route (section 5.2), drawn around the
bundled ``charts/scenarios/env1-*.yaml`` and ``env2-*.yaml`` (the paper's coordinates).

The own ship (``vessel``, the 2.5 m ``iwso-dwa-usv``) from (250, 50) heading north at
``own_speed`` (4 m/s, the paper's) toward (250, 400) (350 m, env1's run); targets of ``length``
(2.5 m) keep course and speed. Drawn uniformly, in ranges that hold the eight bundled
encounters (env1's and env2's values in brackets):

- ``head-on``: the target 150-330 m ahead (320, 170), ±3 m across, course 180 ± 5 deg at
  1.5-3.5 m/s (3, 2);
- ``crossing-port`` / ``crossing-starboard``: the target from port, course 90 ± 10 deg (90), or
  from starboard, 270 ± 10 (270), at 2.5-4.5 m/s (4, 3), crossing the own track 15-25 s ahead
  (env1 20 s, env2 18-23 s) within ±15 m of where the own ship is then (env1 0 and 10 m ahead,
  env2 5 m ahead and 13 m astern);
- ``overtaking``: the target 60-120 m ahead (90, 80), ±3 m across, course 0 ± 5 deg at
  1.5-3 m/s (2, 2.5);
- ``static``: no target; a map (``<stem>.map.tif``, 1 m cells, 300 m x 450 m of open water
  around the run, no CRS) with 1-3 round islands of radius 8-``island_max`` m (25) centred
  30-70 % of the way along the straight route and at most 0.6 radius off it.

Promise: the target is of the kind's class at the start (head-on, crossing-stand-on from port,
crossing-give-way from starboard, overtaking) and clear (:func:`~.base.crowding`), a crossing
target's CPA is within 4 own lengths (10 m; the bundled ones pass at 0-8 m); a static scene's
straight route crosses an island, its start and goal lie at least 10 own lengths (25 m) from
any island, and a passage that keeps one own length from every island joins them.
"""

from __future__ import annotations

import numpy as np
from affine import Affine

from usvtool.grid import NAVIGABLE, OBSTACLE, Grid
from usvtool.params import POSITIVE, Param
from usvtool.sim.families.base import (
    Draw,
    Family,
    MapFile,
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

START, GOAL = (250.0, 50.0), (250.0, 400.0)
#: The static map: (left, bottom, right, top) in metres, 1 m cells.
MAP_BOUNDS = (100.0, 0.0, 400.0, 450.0)
CLASS = {"head-on": "head-on", "crossing-port": "crossing-stand-on",
         "crossing-starboard": "crossing-give-way", "overtaking": "overtaking"}  # fmt: skip
#: A crossing target's CPA is within this many own lengths.
CPA_LENGTHS = 4.0
#: The static kind: start and goal this many own lengths from any island.
CLEAR_LENGTHS = 10.0


class Iwso(Family):
    name = "iwso"
    kinds = ("head-on", "crossing-port", "crossing-starboard", "overtaking", "static")
    controller = "gdwa"
    parameters = {
        "own_speed": Param(4.0, "the own ship's speed at the start, m/s", POSITIVE),
        "length": Param(2.5, "the target's length, m", POSITIVE),
        "island_max": Param(
            25.0, "static: the largest island radius, m (the smallest is 8)", POSITIVE
        ),
        "vessel": vessel_option("iwso-dwa-usv"),
        "duration": duration_option(150.0),
    }
    about = {"head-on": "a target dead ahead on the reciprocal course",
             "crossing-port": "a target from port crossing ahead (own stands on)",
             "crossing-starboard": "a target from starboard crossing ahead (own gives way)",
             "overtaking": "a slower target ahead on the own course",
             "static": "round islands on the straight route, a map"}  # fmt: skip

    def draw(self, kind: str, rng: np.random.Generator, opts: dict) -> Draw:
        u = rng.uniform
        own = own_ship(START, GOAL, 0.0, opts["own_speed"], opts["vessel"])
        x0, y0 = START
        length = opts["length"]
        if kind == "static":
            grid = islands(rng, opts["island_max"])
            return Draw(scenario(own, [], opts["duration"], self.controller, map=""),
                        {"map": ("map.tif", MapFile(grid))})  # fmt: skip
        if kind == "head-on":
            target = ship("target", x0 + u(-3, 3), y0 + u(150, 330), 180 + u(-5, 5),
                          u(1.5, 3.5), length)  # fmt: skip
        elif kind == "overtaking":
            target = ship("target", x0 + u(-3, 3), y0 + u(60, 120), u(-5, 5), u(1.5, 3), length)
        else:  # where the target crosses the own track, after tau seconds
            side = 90.0 if kind == "crossing-port" else 270.0
            tau, course, speed, miss = u(15, 25), side + u(-10, 10), u(2.5, 4.5), u(-15, 15)
            h = np.radians(course)
            cross = (x0, y0 + opts["own_speed"] * tau + miss)
            target = ship("target", cross[0] - speed * tau * np.sin(h),
                          cross[1] - speed * tau * np.cos(h), course, speed, length)  # fmt: skip
        return Draw(scenario(own, [target], opts["duration"], self.controller))

    def reject(self, kind: str, draw: Draw, opts: dict) -> str | None:
        if kind == "static":
            return _static_problem(draw.files["map"][1].grid, opts["vessel"])
        s = draw.scenario
        if class_names(s)[0] != CLASS[kind]:
            return f"target not {CLASS[kind]}"
        reach = CPA_LENGTHS * PRESETS[opts["vessel"]]["length"]
        if kind.startswith("crossing") and start_situation(s).dcpa[0] > reach:
            return "target passes clear"
        return crowding(s)


def islands(rng: np.random.Generator, largest: float) -> Grid:
    """Open water over :data:`MAP_BOUNDS` with 1-3 round islands on the straight route."""
    left, bottom, right, top = MAP_BOUNDS
    cols, rows = int(right - left), int(top - bottom)
    x = left + 0.5 + np.arange(cols)[None, :]
    y = top - 0.5 - np.arange(rows)[:, None]
    cells = np.full((rows, cols), NAVIGABLE, np.uint8)
    (x0, y0), (x1, y1) = START, GOAL
    for _ in range(int(rng.integers(1, 4))):
        radius = rng.uniform(8.0, max(8.0, largest))
        f, off = rng.uniform(0.3, 0.7), rng.uniform(-0.6, 0.6) * radius
        cx, cy = x0 + f * (x1 - x0) + off, y0 + f * (y1 - y0)  # the route runs north
        cells[(x - cx) ** 2 + (y - cy) ** 2 <= radius**2] = OBSTACLE
    return Grid(cells, Affine(1.0, 0.0, left, 0.0, -1.0, top))


def _static_problem(grid: Grid, vessel: str) -> str | None:
    """Why a static scene's map breaks the promise (module docstring), or None."""
    from scipy.ndimage import distance_transform_edt, label

    length = PRESETS[vessel]["length"]
    clearance = distance_transform_edt(grid.cells != OBSTACLE) * grid.cell_size
    ends = [grid.cell_of(*START), grid.cell_of(*GOAL)]
    (x0, y0), (x1, y1) = START, GOAL
    steps = np.linspace(0.0, 1.0, int(np.hypot(x1 - x0, y1 - y0) / grid.cell_size) * 2 + 1)
    line = {grid.cell_of(x0 + t * (x1 - x0), y0 + t * (y1 - y0)) for t in steps}
    if all(grid.cells[r, c] != OBSTACLE for r, c in line):
        return "no island on the route"
    if min(clearance[r, c] for r, c in ends) < CLEAR_LENGTHS * length:
        return "start or goal near an island"
    regions = label(clearance >= length)[0]
    if regions[ends[0]] != regions[ends[1]]:
        return "no passage an own length from the islands"
    return None
