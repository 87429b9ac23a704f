"""Printed lines that cross water are clutter; piers, jetties and breakwaters stay obstacles.

Seeded, generated charts at 1 m per pixel: land with a black 1-pixel coastline, a lake holding
ordinary text (it sets the chart's stroke width to 2 px), and a channel one to three grid cells
wide running from the west edge to the east edge, aligned with the grid's cells of ``k`` pixels
(``k`` 4 or 6 px: the bundled charts have 3 to 6 pixels per 3.75 m cell). One printed line
crosses the channel, bold enough (3 to 5 px, at least the stroke width plus one) that the ink
rule used to read it as a structure from the shore: a graticule line, a magenta dashed limit, a
bridge (two parallel lines with wings), a river-mile line from bank to bank, a long straight
line at a shallow angle. The channel must stay one navigable body on the grid (OpenCV's
labelling of the gridded chart's navigable cells, no safety margin: a one-cell channel has none
to spare). Beside them, structures that end in water must stay obstacles.
"""

import cv2
import numpy as np
import pytest
from affine import Affine

from usvtool.chart import gridding
from usvtool.chart.georef import Frame
from usvtool.chart.ink import resolve
from usvtool.grid import NAVIGABLE
from usvtool.plan.planner import PlanOptions, plan_route

CELLS = 40  # the chart is CELLS x CELLS grid cells
BLACK, MAGENTA = 0, 1  # ink layers; black is the dark one
LINES = ("graticule", "limit", "bridge", "mile", "creek line")


class Chart:
    """A generated chart: land, ink and layers (H, W), the drawn symbol, and its geometry."""

    def __init__(self, seed: int, k: int, channel: int):
        self.rng = np.random.default_rng(seed)
        self.k, self.size = k, CELLS * k
        self.top = (CELLS // 2) * k  # the channel's first pixel row
        self.bottom = self.top + channel * k  # one past its last
        self.land = np.ones((self.size, self.size), bool)
        self.land[self.top : self.bottom] = False
        self.land[4 * k : 12 * k, 6 * k : 34 * k] = False  # the lake
        self.ink = np.zeros_like(self.land, np.uint8)
        self.layers = np.zeros_like(self.ink)
        self.symbol = np.zeros_like(self.ink)
        # the coastline: land pixels next to water, in black
        water = (~self.land).astype(np.uint8)
        self.ink[(cv2.dilate(water, np.ones((3, 3), np.uint8)) > 0) & self.land] = 1
        for row, text in ((5, "12 7 9"), (7, "Lake 4")):
            cv2.putText(self.ink, text, (7 * k, row * k + 4), cv2.FONT_HERSHEY_PLAIN, 0.9, 1, 1,
                        cv2.LINE_8)  # fmt: skip

    def line(self, a, b, thick: int, layer: int = BLACK):
        mark = np.zeros_like(self.ink)
        cv2.line(mark, tuple(int(v) for v in a), tuple(int(v) for v in b), 1, thick, cv2.LINE_8)
        self.symbol |= mark
        self.ink |= mark
        self.layers[mark > 0] = layer

    def across(self, angle: float, reach: float) -> tuple[np.ndarray, np.ndarray]:
        """The ends of a segment through the channel's middle at ``angle`` degrees from the
        east, reaching ``reach`` pixels beyond the channel's banks."""
        mid = np.array([self.size * self.rng.uniform(0.4, 0.6), (self.top + self.bottom) / 2])
        d = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle))])
        half = ((self.bottom - self.top) / 2 + reach) / abs(d[1])
        return mid - half * d, mid + half * d

    def grid(self, mode: str = "auto"):
        """(navigable cells, hazard pixels, land pixels) of the chart read by the ink rule."""
        ink = self.ink.astype(bool)
        new_land, hazard = resolve(ink, self.land, mode, self.layers, [BLACK])
        res = 1.0
        src = Frame(Affine(res, 0, 0, 0, -res, self.size * res), self.size, self.size)
        dst = gridding.grid_frame(src.bounds, self.k * res)
        fraction = gridding.occupancy_fraction(new_land | hazard, src, dst)
        cells = gridding.swell(gridding.obstacles_from_fraction(fraction), self.k * res, 0.0)
        return cells == NAVIGABLE, hazard, new_land


def draw(kind: str, seed: int, k: int, channel: int) -> Chart:
    chart = Chart(seed, k, channel)
    rng = chart.rng
    thick = int(rng.integers(3, 5))
    if kind == "graticule":  # a meridian over the whole chart
        a, b = chart.across(float(rng.uniform(80, 100)), chart.size)
        chart.line(a, b, thick)
    elif kind == "limit":  # magenta dashes along a line over the whole chart
        a, b = chart.across(float(rng.uniform(55, 125)), chart.size)
        dash, gap = int(rng.integers(10, 15)), int(rng.integers(4, 7))
        length = np.hypot(*(b - a))
        for s in np.arange(0, length, dash + gap):
            chart.line(a + (b - a) * s / length, a + (b - a) * min(s + dash, length) / length,
                       4, MAGENTA)  # fmt: skip
    elif kind == "bridge":  # two parallel lines from land to land, with wings
        angle = float(rng.uniform(70, 110))
        a, b = chart.across(angle, 6)
        normal = np.array([np.sin(np.radians(angle)), -np.cos(np.radians(angle))])
        for side in (-1, 1):
            offset = side * float(rng.uniform(2.5, 4)) * normal
            chart.line(a + offset, b + offset, 3)
            for end, out in ((a, -1), (b, 1)):
                tip = end + offset + 5 * side * normal
                chart.line(end + offset, tip + 3 * out * (b - a) / np.hypot(*(b - a)), 3)
    elif kind == "mile":  # a river-mile line from bank to bank, a tick at each end
        angle = float(rng.uniform(60, 120))
        a, b = chart.across(angle, 4)
        chart.line(a, b, thick)
        for end in (a, b):
            normal = 4 * np.array([np.sin(np.radians(angle)), -np.cos(np.radians(angle))])
            chart.line(end - normal, end + normal, thick)
    else:  # a long straight line crossing the creek at a shallow angle
        a, b = chart.across(float(rng.choice([-1, 1]) * rng.uniform(25, 40)), chart.size)
        chart.line(a, b, thick)
    return chart


CASES = [(kind, seed, k, channel)
         for seed, kind in enumerate(LINES)
         for channel in (1, 2, 3)
         for k in ((6,) if channel == 1 else (4, 6))]  # fmt: skip


def one_body(navigable: np.ndarray, chart: Chart) -> bool:
    """Whether the channel's west and east ends are in one navigable body (8-connected)."""
    _, labels = cv2.connectedComponents(navigable.astype(np.uint8), connectivity=8)
    row = chart.top // chart.k
    west, east = labels[row, 0], labels[row, -1]
    return bool(west and west == east)


@pytest.mark.parametrize("kind, seed, k, channel", CASES)
def test_a_printed_line_across_a_channel_keeps_it_open(kind, seed, k, channel):
    chart = draw(kind, seed, k, channel)
    navigable, hazard, _ = chart.grid()
    assert one_body(navigable, chart), f"{kind}: the channel is closed"
    assert not (hazard & (chart.symbol > 0))[chart.top : chart.bottom].any()


def test_a_route_passes_the_lines():
    """The any-angle planner finds a route along a two-cell channel crossed by a graticule line
    and by a bridge, from its west end to its east end."""
    for kind in ("graticule", "bridge"):
        chart = draw(kind, 7, 6, 2)
        navigable, _, _ = chart.grid()
        from usvtool.grid import Grid

        cells = np.where(navigable, 0, 1).astype(np.uint8)
        grid = Grid(cells, Affine(6.0, 0, 0, 0, -6.0, chart.size), None, {})
        y = chart.size - (chart.top + chart.k) * 1.0
        result = plan_route(grid, (3.0, y), (chart.size - 3.0, y), PlanOptions(algo="anyangle"))
        assert result.route.collision_free, kind
        assert result.route.length_m < 1.05 * (chart.size - 6.0), kind  # along the channel


def test_bridges_as_obstacles_on_request():
    """``auto+bridges``: a bridge of dark ink closes the channel; a magenta limit does not."""
    bridge = draw("bridge", 2, 6, 2)
    navigable, hazard, _ = bridge.grid("auto+bridges")
    assert not one_body(navigable, bridge) and hazard[bridge.symbol > 0].any()
    limit = draw("limit", 1, 6, 2)
    navigable, _, _ = limit.grid("auto+bridges")
    assert one_body(navigable, limit)


def pier(chart: Chart, kind: str):
    """A structure from the lake's south shore (or the channel's north bank) ending in water."""
    rng, k = chart.rng, chart.k
    shore = 12 * k - 1  # the lake's last water row
    x = float(rng.uniform(22, 26) * k)  # east of the text
    length = float(rng.uniform(3, 4) * k)
    if kind == "pier":  # a thick stroke from the shore
        angle = np.radians(rng.uniform(-30, 30))
        chart.line((x, shore + 2), (x + length * np.sin(angle), shore - length * np.cos(angle)),
                   int(rng.integers(4, 6)))  # fmt: skip
    elif kind == "double pier":  # two outlines from the shore, joined at the head
        for dx in (0, 7):
            chart.line((x + dx, shore + 2), (x + dx, shore - length), 3)
        chart.line((x, shore - length), (x + 7, shore - length), 3)
    elif kind == "arm":  # a harbour arm: out from the shore, then along it
        chart.line((x, shore + 2), (x, shore - length), 4)
        chart.line((x, shore - length), (x + length, shore - length), 4)
    elif kind == "breakwater":  # free-standing, long and straight
        chart.line((7 * k, 10 * k), (33 * k, 10 * k), 4)
    else:  # a jetty from the channel's north bank, ending halfway across
        top = chart.top
        chart.line((x, top - 3), (x + 3, top + (chart.bottom - top) // 2 - 2), 4)


@pytest.mark.parametrize("kind", ["pier", "double pier", "arm", "breakwater", "jetty"])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_structures_ending_in_water_stay_obstacles(kind, seed):
    chart = Chart(seed, 4 + 2 * (seed % 2), 3)
    pier(chart, kind)
    _, hazard, new_land = chart.grid()
    symbol = chart.symbol > 0
    assert (hazard | new_land)[symbol].mean() > 0.95, kind


# Along the channel: roads and rails drawn beside a creek, graticule ticks, leader lines.
ALONG = ("rail", "road", "ticks", "leader")


def along(kind: str, seed: int, k: int, channel: int) -> Chart:
    """A chart whose channel has a printed ``kind`` beside it or over it (see :data:`ALONG`).

    - rail / road: two parallel lines along the channel on its north bank (the creek-side one
      from two pixels inside the land to one pixel over the water, so sometimes touching it or
      standing on its edge), 3 px bold, the paper white between them (it reads as water), and
      for a rail cross-ties every 6 to 9 px from line to line;
    - ticks: short graticule ticks, 2 or 3 px, from both banks into the water (a third of the
      channel at most) and a cross over the water;
    - leader: a thin line (1 or 2 px) from a label on the north land across the channel, ending
      on the south land.
    """
    chart = Chart(seed, k, channel)
    rng, top, bottom = chart.rng, chart.top, chart.bottom
    x0, x1 = 0, chart.size - 1
    if kind in ("rail", "road"):
        near = top + int(rng.integers(-2, 2))  # the creek-side line's middle row
        gap = int(rng.integers(4, 7))  # between the lines' middles
        far = near - gap
        chart.land[far + 1 : near] = False  # the paper between them
        chart.line((x0, near), (x1, near), 3)
        chart.line((x0, far), (x1, far), 3)
        if kind == "rail":
            for x in range(int(rng.integers(2, 6)), chart.size, int(rng.integers(6, 10))):
                chart.line((x, far), (x, near), 2)
    elif kind == "ticks":
        thick = int(rng.integers(2, 4))
        reach = max(2, (bottom - top) // 3)
        for x in rng.integers(2 * k, chart.size - 2 * k, 6):
            chart.line((x, top - 2), (x, top + reach - 1), thick)
            chart.line((x + 3, bottom + 1), (x + 3, bottom - reach), thick)
        cx, cy, arm = chart.size // 2, (top + bottom) // 2, int(rng.integers(3, 6))
        chart.line((cx - arm, cy), (cx + arm, cy), thick)
        chart.line((cx, cy - arm), (cx, cy + arm), thick)
    else:  # a leader line from a label north of the channel to the south land
        x = int(rng.integers(8 * k, 28 * k))
        cv2.putText(chart.ink, "Pipe", (x, top - 3 * k), cv2.FONT_HERSHEY_PLAIN, 0.9, 1, 1,
                    cv2.LINE_8)  # fmt: skip
        end = x + int(rng.integers(-4 * k, 4 * k))
        chart.line((x + 10, top - 3 * k + 2), (end, bottom + 2 * k), int(rng.integers(1, 3)))
    return chart


ALONG_CASES = [(kind, seed, k, channel)
               for kind in ALONG
               for seed in range(3)
               for channel in (1, 2, 3)
               for k in ((6,) if channel == 1 else (4, 6))]  # fmt: skip


@pytest.mark.parametrize("kind, seed, k, channel", ALONG_CASES)
def test_lines_along_or_over_a_channel_keep_it_open(kind, seed, k, channel):
    chart = along(kind, seed, k, channel)
    navigable, hazard, _ = chart.grid()
    assert one_body(navigable, chart), f"{kind}: the channel is closed"

