"""benchmarks/bench_charts.py reads the bundled routes through usvtool.pipeline: one source."""

import numpy as np
import pytest
from affine import Affine

from usvtool.batch.commands import ends_args
from usvtool.grid import Grid
from usvtool.pipeline import Ends, load


@pytest.fixture(scope="module")
def bench(benchmark):
    return benchmark("bench_charts")


def test_the_bench_reads_the_route_matrix_of_the_pipeline(bench):
    ends = bench.bundled_ends()
    assert ends == load().routes["report"].ends
    # every route chart but the 25-million-cell approach cell, which is preprocessed only
    assert set(ends) == set(load().charts) - {"us4md81m"}
    assert ends_args(ends["grid20"]) == ["--start", "0.5", "0.5", "--goal", "19.5", "19.5"]
    assert ends["us5ma12m"].frame == "lonlat"


def test_lon_lat_ends_become_map_metres(bench):
    grid = Grid(np.zeros((10, 10), np.uint8), Affine(10, 0, 330000, 0, -10, 4690000), "EPSG:32619")
    # a route's ends are in one frame; the lon/lat pair goes through the grid's CRS
    assert bench.map_points(grid, Ends((1, 2), (3, 4))) == ((1.0, 2.0), (3.0, 4.0))
    _, goal = bench.map_points(grid, Ends((-70.9, 42.33), (-70.9, 42.33), "lonlat"))
    # 1.9 degrees west of zone 19N's central meridian (69 W) at 42.33 N: about
    # 500 km - 1.9 x 111.3 km x cos(42.33) = 343.6 km east; 42.33 x 111.1 km = 4 703 km north,
    # less the ellipsoid's flattening near 4 688 km (pyproj: 343 459, 4 688 165)
    assert goal == pytest.approx((343_600, 4_688_000), abs=1_000)
