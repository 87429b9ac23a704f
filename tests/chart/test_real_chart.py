"""The image pipeline on a real chart, checked against the chart's own vector truth.

US5MA12M is drawn in S-52 colours with soundings, contours and coastline (the clutter), the
drawing goes through the image pipeline, and the land found is compared with the cell's land
polygons rasterised independently by ``render --truth``. The vector path is checked at known
places of Boston Harbor.
"""

import pytest
import rasterio

from usvtool.chart.preprocessing import PreprocessOptions, preprocess
from usvtool.chart.rendering import render_cell, write_chart, write_truth
from usvtool.chart.s57 import read_cell
from usvtool.geodesy import WGS84, transformer

THOMPSON_ISLAND = (-71.0106, 42.3148)
NANTASKET_ROADS = (-70.9219, 42.3122)  # dredged channel, 11.0 m
BETWEEN_STRIPS = (-70.9, 42.26)  # outside the cell's CATCOV=1 coverage


@pytest.fixture(scope="module")
def rendering(enc, tmp_path_factory):
    tmp = tmp_path_factory.mktemp("enc")
    rgb, truth, frame = render_cell(read_cell(enc), 15.0)
    write_chart(tmp / "chart.tif", rgb, frame)
    write_truth(tmp / "truth.tif", truth, frame)
    return tmp / "chart.tif", tmp / "truth.tif"


@pytest.mark.parametrize("channel", ["membership", "chromatic"])
def test_land_iou_of_the_image_pipeline_on_a_real_cell(rendering, channel):
    chart, truth_path = rendering
    result = preprocess(chart, PreprocessOptions(cell_size=15.0, channel=channel))
    with rasterio.open(truth_path) as ds:
        truth = ds.read(1)
    covered, land = truth != 255, truth == 1
    found = result.segmentation.land
    iou = (found & land & covered).sum() / ((found | land) & covered).sum()
    assert iou >= 0.95


def cell_at(grid, lon, lat):
    return grid.cells[grid.cell_of(*transformer(WGS84, grid.crs).transform(lon, lat))]


def test_vector_path_on_the_real_cell(enc):
    result = preprocess(enc, PreprocessOptions(cell_size=20.0))
    grid = result.grid
    assert grid.crs.to_epsg() == 32619 and result.summary()["source_kind"] == "s57"
    assert cell_at(grid, *THOMPSON_ISLAND) == 1
    assert cell_at(grid, *NANTASKET_ROADS) == 0
    assert cell_at(grid, *BETWEEN_STRIPS) == 1  # no coverage: not navigable
    assert result.summary()["min_depth_m"] == 1.2
