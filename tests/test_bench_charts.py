"""benchmarks/bench_charts.py reads the bundled routes from pipelines/routes.mk: one source."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest
from affine import Affine

from usvtool.grid import Grid

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def bench():
    path = ROOT / "benchmarks" / "bench_charts.py"
    spec = importlib.util.spec_from_file_location("bench_charts", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_bundled_chart_has_its_route(bench):
    ends = bench.bundled_ends()
    assert set(ends) == {"env1", "env2", "grid20", "grid50", "us5ma12m", "head_of_passes",
                         "rudee_inlet", "south_san_diego"}  # fmt: skip
    assert ends["grid20"] == ["--start", "0.5", "0.5", "--goal", "19.5", "19.5"]
    assert ends["us5ma12m"][0] == "--start-lonlat" and ends["us5ma12m"][3] == "--goal-lonlat"


def test_lon_lat_ends_become_map_metres(bench):
    grid = Grid(np.zeros((10, 10), np.uint8), Affine(10, 0, 330000, 0, -10, 4690000), "EPSG:32619")
    start, goal = bench.map_points(grid, ["--start", "1", "2", "--goal-lonlat", "-70.9", "42.33"])
    assert start == (1.0, 2.0)
    # 1.9 degrees west of zone 19N's central meridian (69 W) at 42.33 N: about
    # 500 km - 1.9 x 111.3 km x cos(42.33) = 343.6 km east; 42.33 x 111.1 km = 4 703 km north,
    # less the ellipsoid's flattening near 4 688 km (pyproj: 343 459, 4 688 165)
    assert goal == pytest.approx((343_600, 4_688_000), abs=1_000)
