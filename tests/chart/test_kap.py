"""The real NOAA raster chart 11361_4 (Head of Passes): georeference, cutline, the channel."""

import warnings

import numpy as np
import pytest
import rasterio
from rasterio.transform import from_gcps
from scipy import ndimage

from usvtool.chart.preprocessing import PreprocessOptions, preprocess
from usvtool.geodesy import transformer

# lon/lat of three points of the Mississippi's main channel, north to south
CHANNEL = [(-89.2677, 29.1840), (-89.2528, 29.1557), (-89.2619, 29.1240)]
CUTLINE_NORTH, CUTLINE_SOUTH = 29.1850, 29.1233333333


@pytest.fixture(scope="module")
def result(kap):
    return preprocess(kap, PreprocessOptions())


def test_channel_points_are_water_on_the_chart_itself(kap):
    """Independent of the pipeline: the KAP's own pixels around those points are water colours
    (a 5 x 5 window: a sounding's digits may sit on the point itself)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with rasterio.open(kap) as ds:
            band, cmap = ds.read(1), ds.colormap(1)
            gcps, gcp_crs = ds.gcps
    to_chart = transformer("EPSG:4326", gcp_crs)
    inverse = ~from_gcps(gcps)
    for lon, lat in CHANNEL:
        col, row = inverse @ to_chart.transform(lon, lat)
        window = band[int(row) - 2 : int(row) + 3, int(col) - 2 : int(col) + 3].ravel()
        water = [cmap[v][:3] in ((255, 255, 255), (209, 221, 239)) for v in window]
        assert sum(water) > len(water) / 2


def test_grid_is_in_utm_16n_at_the_papers_cell_size(result):
    assert result.grid.crs.to_epsg() == 32616
    assert result.grid.cell_size == pytest.approx(3.75)
    assert result.summary()["source_kind"] == "kap"


def test_river_channel_is_one_navigable_region_from_north_edge_to_southern_water(result):
    grid = result.grid
    to_utm = transformer("EPSG:4326", grid.crs)
    labels, _ = ndimage.label(grid.cells == 0)  # 4-connected: no squeezing between corners
    cells = [grid.cell_of(*to_utm.transform(lon, lat)) for lon, lat in CHANNEL]
    ids = {labels[r, c] for r, c in cells}
    assert 0 not in ids and len(ids) == 1, "channel points navigable and connected"
    rows = np.nonzero(labels == ids.pop())[0]
    north_row = grid.cell_of(*to_utm.transform(-89.265, CUTLINE_NORTH))[0]
    south_row = grid.cell_of(*to_utm.transform(-89.265, CUTLINE_SOUTH))[0]
    assert rows.min() - north_row <= 10  # reaches the chart's northern edge (10 cells: 37 m)
    assert south_row - rows.max() <= 10  # and its southern edge


def test_outside_the_cutline_is_not_navigable(result):
    grid = result.grid
    to_utm = transformer("EPSG:4326", grid.crs)
    row, col = grid.cell_of(*to_utm.transform(-89.265, CUTLINE_SOUTH - 0.005))  # blank paper
    assert grid.cells[row, col] == 1
