"""``wind``: wind of seeded direction and strength for the UDWA paper's weather claim (section
4.2), around the bundled ``charts/scenarios/wind-*.yaml`` (their README says how those were
built and why the halves are split by the start-goal line).

The own ship (``vessel``, the 15 m ``udwa-usv``) from (50, 50) heading 45 at ``own_speed`` (5
m/s) toward (650, 650) over open water, goal tolerance 10 m, like the bundled runs. The wind
comes from ``wind_from`` ± ``spread`` deg (drawn uniformly; by default from anywhere), and:

- ``halves``: a field raster (``<stem>.wind.tif``: 700 m x 700 m in 10 m cells, no CRS, bands
  ``wind_speed`` and ``wind_from``): strong (5.5-7 m/s, force 4, the paper's strongest) on one
  side of the start-goal line and weak (0.3-1.5 m/s, force 1) on the other, the side drawn, a
  linear ramp ``ramp`` m (20) wide across the line;
- ``uniform``: ``weather: {wind_speed, wind_from}``, 0.3-7 m/s (forces 1-4, the paper's Table 2).

Promise: a halves field is force 4 on its strong side and force 1 on its weak side, 50 m off the
line half-way along it; a uniform wind is of forces 1-4.
"""

from __future__ import annotations

import numpy as np
from affine import Affine

from usvtool.params import NON_NEGATIVE, POSITIVE, Param
from usvtool.sim.families.base import (
    Draw,
    Family,
    duration_option,
    own_ship,
    scenario,
    vessel_option,
)
from usvtool.sim.weather import beaufort

START, GOAL = (50.0, 50.0), (650.0, 650.0)
SIZE, CELL = 700.0, 10.0
STRONG, WEAK = (5.5, 7.0), (0.3, 1.5)
#: The unit normal of the start-goal line, to its right (looking from the start).
RIGHT = np.array([GOAL[1] - START[1], START[0] - GOAL[0]]) / np.hypot(*np.subtract(GOAL, START))
#: Where a halves field is checked: this far off the start-goal line, half-way along it.
PROBE = 50.0


class WindRaster:
    """A wind field over the local frame [0, SIZE]^2: ``speed`` and ``wind_from`` (compass
    degrees) per cell, row 0 the northern one; ``write(path)`` writes its GeoTIFF."""

    def __init__(self, speed: np.ndarray, wind_from: float):
        self.speed = speed.astype(np.float32)
        self.wind_from = np.full(speed.shape, wind_from, np.float32)

    def at(self, x: float, y: float) -> float:
        """The speed of the cell holding (x, y)."""
        return float(self.speed[int((SIZE - y) // CELL), int(x // CELL)])

    def write(self, path) -> None:
        import rasterio

        profile = dict(driver="GTiff", height=self.speed.shape[0], width=self.speed.shape[1],
                       count=2, dtype="float32", transform=Affine(CELL, 0.0, 0.0, 0.0, -CELL, SIZE),
                       compress="deflate")  # fmt: skip
        with rasterio.open(path, "w", **profile) as ds:
            ds.write(self.speed, 1)
            ds.write(self.wind_from, 2)
            ds.set_band_description(1, "wind_speed")
            ds.set_band_description(2, "wind_from")
            ds.update_tags(1, units="m/s")
            ds.update_tags(2, units="degrees (compass, direction the wind comes from)")


def halves(strong: float, weak: float, strong_right: bool, ramp: float) -> np.ndarray:
    """Cell speeds: ``strong`` to the right of the start-goal line (looking from the start;
    south-east here) when ``strong_right``, else to its left, ``weak`` on the other side, a
    linear ramp ``ramp`` m wide between (their mean on the line)."""
    n = int(round(SIZE / CELL))
    centres = (np.arange(n) + 0.5) * CELL
    x, y = centres[None, :], (SIZE - centres)[:, None]
    nx, ny = RIGHT
    right = (x - START[0]) * nx + (y - START[1]) * ny  # signed distance, > 0 to the right
    side = right if strong_right else -right
    share = np.clip(0.5 + side / ramp, 0.0, 1.0)
    return weak + (strong - weak) * share


class Wind(Family):
    name = "wind"
    kinds = ("halves", "uniform")
    controller = "udwa"
    parameters = {
        "own_speed": Param(5.0, "the own ship's speed at the start, m/s", POSITIVE),
        "wind_from": Param(225.0, "the middle of the wind's directions, compass deg", NON_NEGATIVE),
        "spread": Param(180.0, "the wind comes from wind_from ± spread deg", NON_NEGATIVE),
        "ramp": Param(20.0, "halves: the width of the ramp across the line, m", POSITIVE),
        "vessel": vessel_option("udwa-usv"),
        "duration": duration_option(240.0),
    }
    about = {"halves": "strong wind on one side of the route, weak on the other (a field)",
             "uniform": "one wind everywhere"}  # fmt: skip

    def draw(self, kind: str, rng: np.random.Generator, opts: dict) -> Draw:
        u = rng.uniform
        wind_from = float((opts["wind_from"] + u(-opts["spread"], opts["spread"])) % 360.0)
        own = own_ship(START, GOAL, 45.0, opts["own_speed"], opts["vessel"])
        settings = dict(duration=opts["duration"], controller=self.controller, goal_tolerance=10.0)
        if kind == "uniform":
            weather = {"wind_speed": float(u(WEAK[0], STRONG[1])), "wind_from": wind_from}
            return Draw(scenario(own, [], weather=weather, **settings))
        speed = halves(u(*STRONG), u(*WEAK), bool(rng.integers(2)), opts["ramp"])
        return Draw(
            scenario(own, [], weather={"field": ""}, **settings),
            {"weather.field": ("wind.tif", WindRaster(speed, wind_from))},
        )

    def reject(self, kind: str, draw: Draw, opts: dict) -> str | None:
        if kind == "uniform":
            force = int(beaufort(draw.scenario["weather"]["wind_speed"]))
            return None if 1 <= force <= 4 else f"force {force}"
        field = draw.files["weather.field"][1]
        middle = np.add(START, GOAL) / 2
        forces = sorted(int(beaufort(field.at(*(middle + k * PROBE * RIGHT)))) for k in (1, -1))
        return None if forces == [1, 4] else f"forces {forces} off the line, not 1 and 4"
