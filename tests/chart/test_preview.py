"""The preview PNG a person reads: class colours, no-data hatching, legend, title, scale bar."""

import json
from pathlib import Path

import cv2
import numpy as np
import pytest
from affine import Affine

from usvtool.chart.georef import Frame
from usvtool.chart.preview import (
    HATCH,
    PAD,
    ROW,
    render_preview,
    scale_length,
    title_line,
)
from usvtool.chart.sources import RasterChart
from usvtool.grid import MARGIN, NAVIGABLE, OBSTACLE, Grid

# The class colours over plain water (212, 234, 238), by hand: 0.4 x water + 0.6 x tint, rounded.
COLOURS = {
    NAVIGABLE: (212, 234, 238),
    OBSTACLE: (205, 112, 113),  # tint (200, 30, 30): 84.8 + 120, 93.6 + 18, 95.2 + 18
    MARGIN: (235, 214, 95),  # tint (250, 200, 0): 84.8 + 150, 93.6 + 120, 95.2 + 0
}
CELL = 10.0  # metres
RES = 5.0  # metres per preview pixel: 2 pixels a cell, so no cell lines
CHARTS = Path(__file__).resolve().parents[2] / "charts"


@pytest.fixture(scope="module")
def scene():
    """A 40 x 30 grid of 10 m cells: an obstacle block ringed by margin, and the west 10
    columns outside the chart (obstacles in the grid, invalid in the chart image)."""
    cells = np.zeros((30, 40), np.uint8)
    cells[:, :10] = OBSTACLE
    cells[10:20, 25:35] = MARGIN
    cells[12:18, 27:33] = OBSTACLE
    grid = Grid(cells, Affine(CELL, 0, 0, 0, -CELL, 300), None,
                {"source": "/data/charts/bay.png", "margin_m": 5.0})  # fmt: skip
    rgb = np.empty((120, 160, 3), np.uint8)  # 2.5 m pixels over the same 400 x 300 m
    rgb[:] = COLOURS[NAVIGABLE]
    valid = np.ones((120, 160), bool)
    valid[:, :40] = False
    chart = RasterChart.from_rgb(rgb, valid, Frame(Affine(2.5, 0, 0, 0, -2.5, 300), 160, 120),
                                 "image")  # fmt: skip
    return grid, chart, render_preview(grid, chart, RES)


def map_pixels(img, rows, cols):
    """Preview pixels of grid rows/cols (slices), 2 preview pixels a cell."""
    r, c = rows, cols
    return img[2 * r.start : 2 * r.stop, 2 * c.start : 2 * c.stop].reshape(-1, 3)


def colours(pixels):
    return {tuple(int(v) for v in p) for p in np.unique(pixels, axis=0)}


def test_each_class_has_its_colour(scene):
    _, _, img = scene
    assert colours(map_pixels(img, slice(0, 30), slice(12, 24))) == {COLOURS[NAVIGABLE]}
    assert colours(map_pixels(img, slice(12, 18), slice(27, 33))) == {COLOURS[OBSTACLE]}
    assert colours(map_pixels(img, slice(10, 12), slice(25, 35))) == {COLOURS[MARGIN]}
    # outside the chart: hatched, grey with darker diagonals, never the obstacle red
    assert colours(map_pixels(img, slice(0, 30), slice(0, 10))) == set(HATCH)


def test_the_four_classes_are_clearly_different():
    shown = [*COLOURS.values(), HATCH[0]]
    for i, a in enumerate(shown):
        for b in shown[i + 1 :]:
            assert np.linalg.norm(np.subtract(a, b, dtype=float)) > 60, (a, b)


def test_legend_and_title_strip(scene):
    grid, _, img = scene
    h = 2 * grid.height
    assert img.shape[0] == h + 3 * ROW + PAD  # map (60 rows) + title, legend and scale rows
    strip = img[h:]
    assert (img[h] == 255).all()  # the strip starts white under the map
    assert (strip[:ROW] < 80).all(axis=2).sum() > 100  # the title's letters
    legend = strip[ROW : 2 * ROW].reshape(-1, 3)
    for colour in [*COLOURS.values(), *HATCH]:  # every class's swatch, as the map shows it
        assert (legend == colour).all(axis=1).sum() >= 30, colour
    assert title_line(grid) == "bay.png   cell 10 m   margin 5 m"


def test_scale_bar_has_a_round_length(scene):
    _, _, img = scene
    # map 80 px of 5 m = 400 m; a quarter is 100 m: a 100 m bar, 20 px
    assert scale_length(RES * 80 / 4) == 100
    row = img[2 * 30 + 2 * ROW + 12]
    black = (row < 40).all(axis=1)
    assert black[PAD : PAD + 20].all() and not black[PAD + 20 : PAD + 26].any()
    assert not black[:PAD].any()


def test_scale_lengths():
    assert [scale_length(x) for x in (7.0, 20.0, 3400.0, 99.9, 0.07)] == [5, 20, 2000, 50, 0.05]


def test_same_grid_same_bytes(scene):
    grid, chart, img = scene
    again = render_preview(grid, chart, RES)
    assert cv2.imencode(".png", again)[1].tobytes() == cv2.imencode(".png", img)[1].tobytes()


def test_default_size_and_no_chart():
    """Without a resolution the longest side is 1200 pixels; without a chart the water is
    plain and nothing is outside."""
    cells = np.zeros((20, 60), np.uint8)
    cells[5:10, 5:10] = OBSTACLE
    grid = Grid(cells, Affine(2.0, 0, 0, 0, -2.0, 40), None, {})
    img = render_preview(grid)
    assert img.shape[1] == 1200 and img.shape[0] == 400 + 3 * ROW + PAD
    assert not (img[:400] == HATCH[1]).all(axis=2).any()
    assert title_line(grid) == "the grid   cell 2 m"


def test_too_fine_a_resolution_names_the_option_and_a_value_that_works():
    from usvtool.chart.preview import preview_frame
    from usvtool.chart.rendering import MAX_PIXELS
    from usvtool.errors import UsvError

    grid = Grid(np.zeros((10, 10), np.uint8), Affine(10_000, 0, 0, 0, -10_000, 100_000), None,
                {"source": "big.tif"})  # fmt: skip
    with pytest.raises(UsvError) as err:
        render_preview(grid, None, 1.0)
    # 100 km square: sqrt(1e10 / 5e7) = 14.14 m -> 14.2 m (7043 x 7043 = 49.6 Mpx; 14.1 m:
    # 7093 x 7093 = 50.3 Mpx, too many)
    assert str(err.value) == (
        "--preview-resolution 1 m: the preview of big.tif would be 100000 x 100000 pixels "
        "(limit 50 million); use --preview-resolution 14.2 or more"
    )
    frame = preview_frame(grid.bounds, 14.2, "x")
    assert frame.width * frame.height <= MAX_PIXELS
    with pytest.raises(UsvError):
        preview_frame(grid.bounds, 14.1, "x")


def test_the_suggestion_counts_the_edge_pixels():
    """70 710.6 m square: the area gives sqrt(5.0e9 / 5e7) = 9.99992 -> 10.0 m, but 10 m pixels
    need 7072 x 7072 = 50.01 M (whole pixels over the edges); 10.1 m gives 7002 x 7002."""
    from usvtool.chart.rendering import limited_frame
    from usvtool.errors import UsvError

    with pytest.raises(UsvError, match=r"use --opt 10.1 or more$"):
        limited_frame((0, 0, 70_710.6, 70_710.6), 1.0, None, "x", "--opt")


def test_cli_preview_at_a_resolution(tmp_path, usv):
    """A plain 300 x 200 m image in 3.75 m cells (80 x 54 cells: 300 x 202.5 m), previewed at
    5 m per pixel: a 60 x 41 pixel map."""
    img = np.empty((80, 120, 3), np.uint8)
    img[:] = COLOURS[NAVIGABLE]
    cv2.circle(img, (60, 40), 18, (201, 185, 122), -1)  # an island, S-52 land colour
    src = tmp_path / "chart.png"
    cv2.imwrite(str(src), cv2.cvtColor(img, cv2.COLOR_RGB2BGR))
    out, prev = tmp_path / "grid.tif", tmp_path / "grid.png"
    r = usv("preprocess", src, "-o", out, "--resolution", 2.5, "--preview", prev,
            "--preview-resolution", 5)  # fmt: skip
    assert r.exit_code == 0, r.stderr
    img = cv2.imread(str(prev))
    assert img.shape[0] == 41 + 3 * ROW + PAD
    assert json.loads(r.stdout)["preview"] == str(prev)


def test_cli_preview_resolution_needs_preview(tmp_path, usv):
    r = usv("preprocess", "chart.png", "-o", tmp_path / "g.tif", "--preview-resolution", 5)
    assert r.exit_code == 2 and "--preview-resolution" in r.stderr


@pytest.fixture(scope="module")
def us4md81m_preview(tmp_path_factory):
    """US4MD81M (55 x 78 km) at 400 m cells, with its preview (background at 200 m)."""
    from click.testing import CliRunner

    from usvtool.cli import cli

    d = tmp_path_factory.mktemp("us4md81m")
    cell = CHARTS / "noaa" / "US4MD81M" / "US4MD81M.000"
    args = ["preprocess", str(cell), "-o", str(d / "g.tif"), "--cell-size", "400",
            "--preview", str(d / "g.png")]  # fmt: skip
    r = CliRunner().invoke(cli, args, catch_exceptions=False)
    assert r.exit_code == 0, r.stderr
    return json.loads(r.stdout), cv2.cvtColor(cv2.imread(str(d / "g.png")), cv2.COLOR_BGR2RGB)


def test_real_cell_outside_coverage_is_hatched(us4md81m_preview):
    summary, img = us4md81m_preview
    assert img.shape[1] >= 600 and img.shape[0] > 1200  # 1200 px tall map + the strip
    # the coverage's bounding box holds no-coverage corners (north-west, south-east): hatched
    corner = img[:40, :40].reshape(-1, 3)
    assert colours(corner) == set(HATCH)
    hatched = sum((img[:1200] == c).all(axis=2).sum() for c in HATCH)
    assert 0.02 < hatched / (img.shape[1] * 1200) < 0.3
    # the S-52 land under the obstacle tint: LANDA (201, 185, 122) blended 0.4 / 0.6 with red
    assert (img[:1200] == (200, 92, 67)).all(axis=2).sum() > 10_000
