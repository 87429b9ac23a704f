"""Gridding rule and swelling, hand-computed on tiny grids."""

import numpy as np
import pytest
from affine import Affine

from usvtool.chart.georef import Frame
from usvtool.chart.gridding import grid_frame, obstacles_from_fraction, occupancy_fraction, swell
from usvtool.errors import UsvError


@pytest.mark.parametrize(
    ("margin_cells", "ring"),
    [
        (0.0, 0),  # no margin
        (0.5, 8),  # the paper's rule: one ring of 8 neighbours (gap 0)
        (1.0, 8),  # gap of the next ring is exactly 1 cell: not < 1
        (1.01, 20),  # + the 12 cells at gap 1: (±2, 0..±1), (0..±1, ±2)
        (1.5, 24),  # + the 4 corners (±2, ±2) at gap sqrt(2) = 1.414
        (2.01, 36),  # + (±3, 0..±1), (0..±1, ±3): 12 cells at gap 2; (±3, ±2) has gap 2.24
    ],
)
def test_swelling_one_obstacle_cell(margin_cells, ring):
    obstacle = np.zeros((9, 9), bool)
    obstacle[4, 4] = True
    cells = swell(obstacle, 4.0, margin_cells * 4.0)
    assert cells[4, 4] == 1
    assert int((cells == 2).sum()) == ring
    # the margin is symmetric
    assert (cells == cells[::-1]).all() and (cells == cells.T).all()


def test_swelling_is_measured_between_cell_squares():
    # obstacle at (0, 0), free cell at offset (3, 3): gap = sqrt(2^2 + 2^2) cells = 2.83
    obstacle = np.zeros((5, 5), bool)
    obstacle[0, 0] = True
    assert swell(obstacle, 1.0, 2.82)[3, 3] == 0
    assert swell(obstacle, 1.0, 2.84)[3, 3] == 2


def tiny_frame(w, h, res):
    return Frame(Affine(res, 0, 0, 0, -res, h * res), w, h)


def test_gridding_rule_on_a_tiny_image():
    # 4 x 4 pixels of 1 m, 2 m cells: 2 x 2 grid, each cell covers 4 pixels
    blocked = np.zeros((4, 4), bool)
    blocked[0, 0] = True  # one pixel in the north-west cell: share 1/4
    blocked[3, 2:4] = True  # two pixels in the south-east cell: share 2/4
    src = tiny_frame(4, 4, 1.0)
    dst = grid_frame(src.bounds, 2.0)
    share = occupancy_fraction(blocked, src, dst)
    assert share.tolist() == [[0.25, 0.0], [0.0, 0.5]]
    assert obstacles_from_fraction(share, 0.0).tolist() == [[True, False], [False, True]]
    assert obstacles_from_fraction(share, 0.25).tolist() == [[False, False], [False, True]]


def test_grid_extending_past_the_chart_counts_only_the_chart_part():
    blocked = np.zeros((3, 3), bool)
    blocked[:, 0] = True
    src = tiny_frame(3, 3, 1.0)
    dst = grid_frame(src.bounds, 2.0)  # 2 x 2 cells over 3 x 3 px: frame covers 4 x 4 m
    share = occupancy_fraction(blocked, src, dst)
    # the south-west cell covers pixel column 0 (blocked) and 1 (free) in row 2 only
    assert share[1, 0] == pytest.approx(0.5)
    assert share[1, 1] == 0.0


def test_absurd_grids_are_refused_with_a_suggestion():
    with pytest.raises(UsvError, match=r"larger than the chart"):
        grid_frame((0, 0, 100, 50), 60.0)
    with pytest.raises(UsvError, match=r"use --cell-size \d"):
        grid_frame((0, 0, 100_000, 100_000), 1.0)


def test_cell_shares_agree_with_gdal_average_resampling():
    """Independent check: GDAL's area-weighted average (rasterio.warp.reproject) gives the same
    shares on a random mask with 9.4 m pixels and 10 m cells (no common alignment)."""
    from rasterio.warp import Resampling, reproject

    rng = np.random.default_rng(5)
    blocked = rng.random((97, 131)) < 0.3
    src = tiny_frame(131, 97, 9.4)
    dst = grid_frame(src.bounds, 10.0)
    ours = occupancy_fraction(blocked, src, dst)
    gdal = np.full((dst.height, dst.width), np.nan, np.float32)
    reproject(blocked.astype(np.float32), gdal, src_transform=src.transform,
              dst_transform=dst.transform, src_crs="EPSG:32619", dst_crs="EPSG:32619",
              src_nodata=np.nan, dst_nodata=np.nan, resampling=Resampling.average)  # fmt: skip
    inside = ~np.isnan(gdal)
    assert inside.mean() > 0.95
    assert np.abs(ours[inside] - gdal[inside]).max() < 1e-5
