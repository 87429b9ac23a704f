"""S-57 update files on US4MD81M (edition 31, updates .001-.003): which update is applied, what
the summaries report, and the warning when the run of update files has a gap.

Each case copies the files it needs into a fresh directory (GDAL's S57 driver finds the updates
beside the ``.000``, and a fresh path keeps any cache of GDAL's out of the way).
"""

import json
import logging
import shutil
from pathlib import Path

import numpy as np
import pytest
import shapely

from usvtool.chart import s57
from usvtool.chart.preprocessing import PreprocessOptions, preprocess

SOURCE = Path(__file__).resolve().parents[2] / "charts" / "noaa" / "US4MD81M"
#: A wreck (VALSOU 11.9 m) that the updates add, lon/lat as charted.
NEW_WRECK = (-76.4231774, 38.8209314)
CELL_SIZE = 200.0  # metres: 246 x 369 cells, quick


def copy_cell(directory: Path, *suffixes: str) -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    for suffix in ("000", *suffixes):
        shutil.copy(SOURCE / f"US4MD81M.{suffix}", directory)
    return directory / "US4MD81M.000"


@pytest.fixture(scope="module")
def cells(tmp_path_factory):
    """The cell with its three updates beside it, and the base cell copied alone."""
    d = tmp_path_factory.mktemp("updates")
    return copy_cell(d / "all", "001", "002", "003"), copy_cell(d / "alone")


@pytest.fixture(scope="module")
def results(cells):
    return [preprocess(path, PreprocessOptions(cell_size=CELL_SIZE)) for path in cells]


def test_update_3_applied_with_the_files_beside_it(results):
    summary = results[0].summary()
    assert (summary["edition"], summary["update"]) == ("31", "3")
    assert summary["update_files"] == ["US4MD81M.001", "US4MD81M.002", "US4MD81M.003"]
    tags = results[0].grid.tags  # the grid GeoTIFF keeps them too
    assert tags["update"] == "3" and tags["update_files"] == summary["update_files"]


def test_update_0_when_the_cell_is_alone(results):
    summary = results[1].summary()
    assert (summary["edition"], summary["update"], summary["update_files"]) == ("31", "0", [])


def test_the_updates_change_the_cell_and_the_grid(cells, results):
    with_updates, alone = (s57.read_cell(p) for p in cells)
    wreck = shapely.Point(NEW_WRECK)
    found = [shapely.equals_exact(g, wreck, 1e-7) for g in with_updates.hazards]
    assert sum(found) == 1 and not any(shapely.equals_exact(g, wreck, 1e-7) for g in alone.hazards)
    assert with_updates.hazard_layers[np.argmax(found)] == "WRECKS"
    # the updates also redraw depth areas; at 200 m cells the grids differ (a shoal's edge)
    assert results[0].grid.cells.shape == results[1].grid.cells.shape
    assert (results[0].grid.cells != results[1].grid.cells).any()


def test_updates_ignored_report_update_0(cells):
    assert s57.read_cell(cells[0], updates=False).update == "0"


def test_a_gap_in_the_update_files_is_warned_about(tmp_path, caplog):
    path = copy_cell(tmp_path, "001", "003")
    with caplog.at_level(logging.WARNING, logger="usvtool.chart.s57"):
        status = s57.update_status(path)
    # GDAL applies .001 and stops at the missing .002
    assert status == {"edition": "31", "update": "1",
                      "update_files": ["US4MD81M.001", "US4MD81M.003"]}  # fmt: skip
    [record] = caplog.records
    assert record.getMessage() == (
        f"{path}: update files .001, .003 are not a contiguous run from .001 (missing .002): "
        "update 1 applied, the later files ignored"
    )


def test_no_warning_for_a_contiguous_run(tmp_path, caplog):
    path = copy_cell(tmp_path, "001", "002")
    with caplog.at_level(logging.WARNING, logger="usvtool.chart.s57"):
        assert s57.update_status(path)["update"] == "2"
    assert not caplog.records


def test_cli_warns_on_stderr_and_reports(tmp_path, usv):
    path = copy_cell(tmp_path, "002")  # .002 without .001: nothing applied
    r = usv("preprocess", path, "-o", tmp_path / "g.tif", "--cell-size", 400)
    assert r.exit_code == 0, r.stderr
    assert "not a contiguous run from .001 (missing .001)" in r.stderr
    summary = json.loads(r.stdout)
    assert (summary["update"], summary["update_files"]) == ("0", ["US4MD81M.002"])


def test_render_summary_reports_the_update(tmp_path, usv):
    r = usv("render", SOURCE / "US4MD81M.000", "-o", tmp_path / "c.tif", "--resolution", 400,
            "--no-soundings")  # fmt: skip
    assert r.exit_code == 0, r.stderr
    summary = json.loads(r.stdout)
    assert (summary["edition"], summary["update"]) == ("31", "3")
    assert summary["update_files"] == ["US4MD81M.001", "US4MD81M.002", "US4MD81M.003"]
