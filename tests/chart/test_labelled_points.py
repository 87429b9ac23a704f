"""Hand-labelled points on the real NOAA raster charts 12205_2 (Rudee Inlet) and SanDiego_2, and
on 11370_3 (Mississippi River, Bringier Point to Baton Rouge), which is not bundled: its rows are
checked when the chart is in ../shared/charts/noaa (or $USVTOOL_NOAA), skipped otherwise.

Each row of ``data/labelled_points.csv`` was picked by looking at the chart: ink hazards standing
in water (structures, pier and dock bodies, jetty segments, pile, dolphin and light-pile dots, wreck
hulls) and a few land points must be obstacle cells; open channel and basin water, including
SanDiego_2's white dredged channel, and clutter drawn over water (soundings, labels, graticule,
limit and contour lines) must stay navigable. Navigable points are at least 15 m from any land or
hazard ink, so the safety margin never reaches them.
"""

import csv
import os
import re
import warnings
from pathlib import Path
from typing import NamedTuple

import cv2
import numpy as np
import pytest
import rasterio
from pyproj import Geod
from rasterio.transform import from_gcps

from usvtool.chart.preprocessing import PreprocessOptions, preprocess
from usvtool.geodesy import transformer
from usvtool.grid import NAVIGABLE, OBSTACLE

pytestmark = pytest.mark.slow  # the bundled raster charts preprocessed

POINTS = Path(__file__).parent / "data" / "labelled_points.csv"
ROOT = Path(__file__).resolve().parents[2]
CHARTS = ("12205_2.KAP", "SanDiego_2.KAP")  # bundled in charts/noaa
#: Charts outside the repository (11-13 k pixels wide, 2 MB each), with the smallest cell size
#: their grid takes (the default 3.75 m would make more than 25 million cells).
SHARED = {"11370_3.KAP": 9.2}
SHARED_DIR = Path(os.environ.get("USVTOOL_NOAA", ROOT.parent / "shared" / "charts" / "noaa"))
EXPECT = {"obstacle": OBSTACLE, "navigable": NAVIGABLE}
WATER = {(255, 255, 255), (209, 221, 239)}  # deep (white) and shallow (blue) water
CLUTTER = {(0, 0, 0), (114, 114, 114), (219, 73, 150)}  # black, grey and magenta ink
CLEAR_M = 15.0  # navigable points are this far from anything but water and clutter

class Point(NamedTuple):
    number: int  # data row of the CSV, from 1
    chart: str
    lon: float
    lat: float
    expect: str
    what: str


def _read_points() -> list[Point]:
    with POINTS.open(newline="", encoding="utf-8") as f:
        return [
            Point(i, r["chart"], float(r["lon"]), float(r["lat"]), r["expect"], r["what"])
            for i, r in enumerate(csv.DictReader(f), start=1)
        ]


ROWS = _read_points()


def _id(p: Point) -> str:
    slug = re.sub(r"[^A-Za-z0-9]+", "_", p.what).strip("_")
    return f"{Path(p.chart).stem}-r{p.number:02d}-{p.expect}-{slug}"


def chart_path(charts: Path, name: str) -> Path:
    """A labelled chart's file: bundled, or in :data:`SHARED_DIR` (skipped when absent)."""
    if name in CHARTS:
        return charts / "noaa" / name
    path = SHARED_DIR / name
    if not path.is_file():
        pytest.skip(f"{name} is not in {SHARED_DIR} (set USVTOOL_NOAA)")
    return path


@pytest.fixture(scope="module")
def grid_of(charts):
    """``grid_of(name)``: the default-options grid of a chart (a shared one at its smallest
    cell size), preprocessed once per module."""
    cache = {}

    def get(name):
        if name not in cache:
            options = PreprocessOptions(cell_size=SHARED.get(name))
            cache[name] = preprocess(chart_path(charts, name), options).grid
        return cache[name]

    return get


def test_the_csv_covers_the_charts_and_both_classes():
    for chart in CHARTS:
        rows = [p for p in ROWS if p.chart == chart]
        assert len(rows) >= 25, chart
    for chart in (*CHARTS, *SHARED):
        assert {p.expect for p in ROWS if p.chart == chart} == set(EXPECT), chart
    assert {p.chart for p in ROWS} == {*CHARTS, *SHARED}


@pytest.mark.parametrize("chart", (*CHARTS, *SHARED))
def test_points_are_what_they_say_on_the_original_kap(charts, chart):
    """Independent of the pipeline's warp: the KAP's own palette pixels, located through its GCPs.

    An obstacle point has ink or land within 3 pixels (a pile circle is hollow); a navigable
    point sits on water or on black, grey or magenta ink, with no land colour within 15 m.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with rasterio.open(chart_path(charts, chart)) as ds:
            band, cmap = ds.read(1), ds.colormap(1)
            gcps, gcp_crs = ds.gcps
    colour = np.array([cmap.get(i, (0, 0, 0, 0))[:3] for i in range(256)], np.uint8)[band]
    to_map = from_gcps(gcps)
    to_chart, to_wgs84 = transformer("EPSG:4326", gcp_crs), transformer(gcp_crs, "EPSG:4326")
    for p in (p for p in ROWS if p.chart == chart):
        col, row = (int(v) for v in ~to_map @ to_chart.transform(p.lon, p.lat))
        if p.expect == "obstacle":
            window = colour[row - 3 : row + 4, col - 3 : col + 4].reshape(-1, 3)
            assert any(tuple(c) not in WATER for c in window), _id(p)
        else:
            (x0, y0), (x1, y1) = to_map @ (col, row), to_map @ (col + 100, row)
            lons, lats = to_wgs84.transform([x0, x1], [y0, y1])
            pixel_m = Geod(ellps="WGS84").line_length(lons, lats) / 100
            radius = int(np.ceil(CLEAR_M / pixel_m))
            disk = colour[row - radius : row + radius + 1, col - radius : col + radius + 1]
            yy, xx = np.mgrid[-radius : radius + 1, -radius : radius + 1]
            seen = {tuple(map(int, c)) for c in disk[yy**2 + xx**2 <= radius**2]}
            assert seen <= WATER | CLUTTER, f"{_id(p)}: {seen - WATER - CLUTTER} within 15 m"
            assert tuple(colour[row, col]) in WATER | CLUTTER, _id(p)


@pytest.mark.parametrize("point", ROWS, ids=[_id(p) for p in ROWS])
def test_labelled_point_has_the_expected_cell(grid_of, point):
    grid = grid_of(point.chart)
    x, y = transformer("EPSG:4326", grid.crs).transform(point.lon, point.lat)
    row, col = grid.cell_of(x, y)
    assert 0 <= row < grid.height and 0 <= col < grid.width
    value = int(grid.cells[row, col])
    assert value == EXPECT[point.expect], f"{point.what}: cell {value}, want {point.expect}"


#: Points far apart in one water body of a shared chart that its grid must join (lon, lat),
#: with the cell size: Basswood Lake's main body, which the boundary's crosses at its banks cut
#: in two (2 153 890 + 250 066 cells) while strokes along a bank were no crossing candidates.
#: Each point lies 400-570 m from any land or ink (picked as the deepest cells of the two parts).
JOINED = {"14988_1.KAP": (4.3, ((-91.71922, 48.05115), (-91.79101, 48.08288)))}


@pytest.mark.parametrize("chart", JOINED)
def test_a_water_body_stays_one_body(charts, chart):
    cell_size, points = JOINED[chart]
    grid = preprocess(chart_path(charts, chart), PreprocessOptions(cell_size=cell_size)).grid
    _, labels = cv2.connectedComponents((grid.cells == NAVIGABLE).astype(np.uint8),
                                        connectivity=8)  # fmt: skip
    to_map = transformer("EPSG:4326", grid.crs)
    bodies = {int(labels[grid.cell_of(*to_map.transform(lon, lat))]) for lon, lat in points}
    assert len(bodies) == 1 and 0 not in bodies, bodies
