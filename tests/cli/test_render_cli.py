"""``usvtool render`` through click's CliRunner."""

from __future__ import annotations

import json
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
    assert set(summary["timings_s"]) == {"read", "render", "write", "total"}
    with rasterio.open(chart) as c, rasterio.open(truth) as t:
        assert (c.count, t.count, t.nodata) == (3, 1, 255)
        assert c.tags()["safety_m"] == "10.0"
        land = (t.read(1) == 1).sum() / (t.read(1) != 255).sum()
        assert land == pytest.approx(summary["land_fraction"], abs=1e-6)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["chart.tif", "truth.tif"]


@pytest.mark.parametrize("kind", ["missing", "empty", "text", "raster-chart", "no-features"])
def test_bad_cell_one_line_exit_1_nothing_written(tmp_path, bad_cell, kind):
    path, _ = bad_cell(kind)
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
        (["--resolution", "0.2"], 1, "use --resolution 2.7 or more"),
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
