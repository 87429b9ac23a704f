"""``usvtool render`` through click's CliRunner."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from usvtool.cli import cli

CHARTS = Path(__file__).resolve().parents[2] / "charts" / "noaa"
CELL = CHARTS / "US5MA12M.000"


def run(*args):
    return CliRunner().invoke(cli, ["render", *map(str, args)])


def test_render_writes_chart_and_truth(tmp_path):
    import rasterio

    chart, truth = tmp_path / "chart.tif", tmp_path / "truth.tif"
    result = run(CELL, "-o", chart, "--truth", truth, "--resolution", 40, "--no-soundings")
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert (summary["width"], summary["height"]) == (692, 315)
    assert summary["resolution_m"] == 40.0 and summary["crs"] == "EPSG:32619"
    assert 0.15 < summary["land_fraction"] < 0.3
    assert summary["cell"] == "US5MA12M.000" and summary["edition"] == "32"
    assert set(summary["timings"]) == {"read_s", "render_s", "write_s", "total_s"}
    with rasterio.open(chart) as c, rasterio.open(truth) as t:
        assert (c.count, t.count, t.nodata) == (3, 1, 255)
        assert c.tags()["safety_m"] == "10.0"
        land = (t.read(1) == 1).sum() / (t.read(1) != 255).sum()
        assert land == pytest.approx(summary["land_fraction"], abs=1e-6)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["chart.tif", "truth.tif"]


def bad_cell(kind: str, directory: Path) -> Path:
    path = directory / f"{kind}.000"
    if kind == "empty":
        path.write_bytes(b"")
    elif kind == "text":
        path.write_text("not a chart\n")
    elif kind == "raster-chart":
        shutil.copy(CHARTS / "11361_4.KAP", path)
    elif kind == "no-features":
        write_dsid_only_cell(path)
    return path


def write_dsid_only_cell(path: Path) -> None:
    """An S-57 file with only its DSID record: GDAL's S57 driver writes the DSID on creation,
    then refuses to create the M_COVR layer."""
    import contextlib

    import numpy as np
    import shapely
    from pyogrio.raw import write

    wkb = np.array([shapely.to_wkb(shapely.box(-71, 42, -70.9, 42.1))], dtype=object)
    with contextlib.suppress(Exception):
        write(path, wkb, [np.array([1], dtype=np.int32)], fields=["CATCOV"], layer="M_COVR",
              driver="S57", geometry_type="Polygon", crs="EPSG:4326")  # fmt: skip
    if not path.is_file() or not path.stat().st_size:
        pytest.skip("this GDAL does not write S-57 files")


@pytest.mark.parametrize("kind", ["missing", "empty", "text", "raster-chart", "no-features"])
def test_bad_cell_one_line_exit_1_nothing_written(tmp_path, kind):
    path = bad_cell(kind, tmp_path)
    result = run(path, "-o", tmp_path / "chart.tif", "--truth", tmp_path / "truth.tif")
    assert result.exit_code == 1
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and str(path) in lines[0]
    assert not (tmp_path / "chart.tif").exists() and not (tmp_path / "truth.tif").exists()


@pytest.mark.parametrize(
    "args, code, message",
    [
        (["--resolution", "0"], 2, "--resolution"),
        (["--resolution", "inf"], 2, "--resolution"),
        (["--shallow", "20"], 2, "shallow <= safety <= deep"),
        (["--deep", "5"], 2, "shallow <= safety <= deep"),
        (["--resolution", "0.2"], 1, "m or coarser"),
        (["--truth", "nowhere/truth.tif"], 1, "--truth nowhere/truth.tif"),
    ],
)
def test_bad_options(tmp_path, args, code, message):
    result = run(CELL, "-o", tmp_path / "chart.tif", *args)
    assert result.exit_code == code
    assert message in result.stderr
    assert not list(tmp_path.iterdir())


def test_output_directory_must_exist(tmp_path):
    result = run(CELL, "-o", tmp_path / "no" / "chart.tif")
    assert result.exit_code == 1 and "does not exist" in result.stderr
