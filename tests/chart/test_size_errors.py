"""Size errors name the option to change and a value that works: the grid's ``--cell-size`` on
US4MD81M (55 x 78 km), the preview's ``--preview-resolution`` (checked before the grid work)."""

import json
import re
from pathlib import Path

import cv2
import pytest

from usvtool.chart import gridding, s57
from usvtool.chart.preview import check_s57_preview
from usvtool.errors import UsvError
from usvtool.geodesy import WGS84, reproject_geometries

pytestmark = pytest.mark.slow  # large real cells gridded

NOAA = Path(__file__).resolve().parents[2] / "charts" / "noaa"
BIG = NOAA / "US4MD81M" / "US4MD81M.000"
BOSTON = NOAA / "US5MA12M.000"


def suggestion(stderr: str, option: str) -> float:
    found = re.findall(rf"use {option} ([\d.]+) or more", stderr)
    assert len(found) == 1, stderr
    return float(found[0])


@pytest.fixture(scope="module")
def big_bounds():
    """US4MD81M's coverage bounds in its UTM zone (EPSG:32618)."""
    coverage = s57.read_coverage(BIG)
    crs = s57.coverage_utm(coverage)
    return reproject_geometries([coverage], WGS84, crs)[0].bounds, crs


def test_grid_suggestion_is_the_smallest_that_works(big_bounds):
    """49 007 x 73 622 m: sqrt(3.608e9 / 25e6) = 12.01 m, so 12.1 m (12.0 m: 25.06 M cells)."""
    bounds, crs = big_bounds
    with pytest.raises(UsvError, match=r"^--cell-size 3.75 m would make 2.57e\+08 cells; "
                       r"use --cell-size 12.1 or more$"):  # fmt: skip
        gridding.grid_frame(bounds, 3.75, crs)
    gridding.grid_frame(bounds, 12.1, crs)
    with pytest.raises(UsvError):
        gridding.grid_frame(bounds, 12.0, crs)


def test_us4md81m_at_the_suggested_cell_size(tmp_path, usv, monkeypatch):
    """The whole command at the cell size the error suggests: 4051 x 6085 cells (about 3 s,
    0.5 GB on this 2-core machine)."""
    out = tmp_path / "grid.tif"
    r = usv("preprocess", BIG, "-o", out)
    assert r.exit_code == 1 and not out.exists()
    size = suggestion(r.stderr, "--cell-size")
    r = usv("preprocess", BIG, "-o", out, "--cell-size", size)
    assert r.exit_code == 0, r.stderr
    summary = json.loads(r.stdout)
    assert (summary["width"], summary["height"]) == (4051, 6085)  # ceil(49 007 / 12.1), ...
    assert 0.3 < summary["navigable_fraction"] < 0.4 and out.exists()


def no_grid_work(monkeypatch):
    """Make the grid work fail the test if it starts."""

    def refuse(*args, **kwargs):
        raise AssertionError("the grid work started")

    monkeypatch.setattr("usvtool.chart.preprocessing.preprocess", refuse)


def test_default_preview_of_a_large_cell_fits(tmp_path, usv):
    """US4MD81M at 12.1 m cells: a background at half a cell (6.05 m) would be 98 M pixels, over
    the 50 M limit; by default it is drawn at the map's own pixel, 73 622 m / 1200 = 61.4 m, so
    the map is round(4051 x 1200 / 6085) = 799 x 1200 pixels above its strip."""
    out, png = tmp_path / "grid.tif", tmp_path / "grid.png"
    r = usv("preprocess", BIG, "-o", out, "--cell-size", 12.1, "--preview", png)
    assert r.exit_code == 0, r.stderr
    image = cv2.imread(str(png))
    assert image.shape[1] == 799 and 1200 < image.shape[0] < 1300


def test_given_preview_resolution_too_fine_fails_before_the_grid(tmp_path, usv, monkeypatch):
    """US5MA12M at 10 m cells, preview at 0.5 m: 55 360 x 25 180 pixels."""
    no_grid_work(monkeypatch)
    out, png = tmp_path / "grid.tif", tmp_path / "grid.png"
    r = usv("preprocess", BOSTON, "-o", out, "--cell-size", 10, "--preview", png,
            "--preview-resolution", 0.5)  # fmt: skip
    assert r.exit_code == 1 and not out.exists() and not png.exists()
    assert "--preview-resolution 0.5 m: the preview of US5MA12M.000 would be" in r.stderr
    value = suggestion(r.stderr, "--preview-resolution")
    assert value == 2.7  # sqrt(27 680 x 12 590 / 5e7) = 2.64 m
    check_s57_preview(BOSTON, 10, value)
    with pytest.raises(UsvError):
        check_s57_preview(BOSTON, 10, value - 0.1)


def test_render_resolution_error_names_its_option():
    cell = s57.read_cell(BOSTON)
    from usvtool.chart.rendering import chart_frame

    with pytest.raises(UsvError, match=r"^--resolution 0.2 m: US5MA12M.000 would be \d+ x \d+ "
                       r"pixels \(limit 50 million\); use --resolution 2.7 or more$"):  # fmt: skip
        chart_frame(cell, 0.2)
