"""``usvtool preprocess`` through click's CliRunner: outputs, summary, and every bad input."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import cv2
import numpy as np
import pytest
import rasterio

from usvtool.errors import UsvError
from usvtool.grid import read_grid

LANDA, DEPDW = (201, 185, 122), (212, 234, 238)


def write_png(path, rgb):
    cv2.imwrite(str(path), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))
    return path


def island_image(h=80, w=120):
    img = np.empty((h, w, 3), np.uint8)
    img[:] = DEPDW
    cv2.circle(img, (60, 40), 18, LANDA, -1)
    return img


def assert_one_line_error(result, code, *words):
    assert result.exit_code == code, result.output
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 if code == 1 else lines, result.stderr
    assert "Traceback" not in result.stderr
    for w in words:
        assert w in result.stderr
    assert result.stdout == ""


def test_plain_image_to_grid_with_preview_and_summary(tmp_path, usv):
    src = write_png(tmp_path / "chart.png", island_image())
    out, prev = tmp_path / "grid.tif", tmp_path / "grid.png"
    r = usv("preprocess", src, "-o", out, "--preview", prev, "--resolution", 2.5)
    assert r.exit_code == 0, r.stderr
    summary = json.loads(r.stdout)
    grid = read_grid(out)
    # 120 x 80 px of 2.5 m = 300 x 200 m; cells of 1.5 x 2.5 m = 3.75 m -> 80 x 54 cells
    assert (summary["width"], summary["height"]) == (grid.width, grid.height) == (80, 54)
    assert summary["cell_size_m"] == 3.75 and summary["crs"] is None
    assert grid.bounds[:2] == (0.0, 0.0)  # local frame: origin at the lower-left corner
    # the island: a disc of radius 18 px = 45 m, i.e. about 6362 m^2 over 60 000 m^2
    land = (grid.cells == 1).sum() * 3.75**2
    assert 6362 < land < 6362 * 1.35  # whole cells around the disc: a little more
    assert summary["obstacle_fraction"] == pytest.approx((grid.cells == 1).mean(), abs=1e-6)
    assert (grid.cells == 2).any() and cv2.imread(str(prev)) is not None
    for key in ("cell_size_m", "margin_fraction", "source_kind", "timings_s"):
        assert key in summary
    assert json.loads(grid.tags["margin_m"]) == 1.875  # the paper's 0.5 cell


def test_same_seed_same_bytes(tmp_path, usv):
    src = write_png(tmp_path / "chart.png", island_image())
    outs = [tmp_path / "a.tif", tmp_path / "b.tif"]
    for out in outs:
        assert usv("preprocess", src, "-o", out, "--resolution", 2, "--seed", 7).exit_code == 0
    assert outs[0].read_bytes() == outs[1].read_bytes()


def test_geojson_synthetic_map(charts, tmp_path, usv):
    out = tmp_path / "env1.tif"
    r = usv("preprocess", charts / "env1.geojson", "-o", out, "--cell-size", 1, "--margin", 3)
    assert r.exit_code == 0, r.stderr
    grid = read_grid(out)
    assert (grid.width, grid.height, grid.bounds) == (500, 500, (0.0, 0.0, 500.0, 500.0))
    # start (10, 10) and goal (490, 490) are navigable, the straight line between is not
    assert grid.cells[grid.cell_of(10, 10)] == 0 and grid.cells[grid.cell_of(490, 490)] == 0
    diag = [grid.cells[grid.cell_of(t, t)] for t in np.linspace(10, 490, 481)]
    assert max(diag) > 0


def test_bundled_grids_are_what_the_script_and_pipeline_make(charts, tmp_path, usv):
    import importlib.util

    spec = importlib.util.spec_from_file_location("mk", charts / "make_synthetic.py")
    mk = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mk)
    mk.main(str(tmp_path))
    for name in ("env1", "env2", "grid20", "grid50"):
        fresh = (tmp_path / f"{name}.geojson").read_text()
        assert fresh == (charts / f"{name}.geojson").read_text()
    out = tmp_path / "grid20.tif"
    r = usv("preprocess", tmp_path / "grid20.geojson", "-o", out, "--cell-size", 1,
            "--no-swell", "--occupancy", 0.5)
    assert r.exit_code == 0
    assert (read_grid(out).cells == read_grid(charts / "grid20.tif").cells).all()


# ---- bad input: one line naming the file or option, exit 1 (2 for usage), nothing written ----


def bad_inputs(tmp_path):
    good = island_image()
    cases = {}
    cases["missing"] = (tmp_path / "nope.png", [], 1, "no such file")
    (tmp_path / "empty.png").write_bytes(b"")
    cases["empty"] = (tmp_path / "empty.png", [], 1, "empty file")
    (tmp_path / "text.png").write_text("this is not an image\n" * 20)
    cases["text"] = (tmp_path / "text.png", [], 1, "not a readable chart image")
    full = write_png(tmp_path / "full.png", good).read_bytes()
    (tmp_path / "trunc.png").write_bytes(full[: len(full) // 2])
    cases["truncated"] = (tmp_path / "trunc.png", ["--resolution", 1], 1, "trunc.png")
    cases["tiny"] = (write_png(tmp_path / "tiny.png", good[:1, :1]), ["--resolution", 1], 1,
                     "too small")
    land = np.empty_like(good)
    land[:] = LANDA
    land[:40] = (244, 232, 193)
    cases["no water"] = (write_png(tmp_path / "land.png", land), ["--resolution", 1], 1,
                         "no navigable water")
    water = np.empty_like(good)
    water[:] = DEPDW
    water[:40] = (152, 197, 242)
    cases["no land"] = (write_png(tmp_path / "water.png", water), ["--resolution", 1], 1,
                        "no land")
    cases["no resolution"] = (write_png(tmp_path / "plain.png", good), [], 1, "--resolution")
    with rasterio.open(tmp_path / "plain.tif", "w", driver="GTiff", width=120, height=80,
                       count=3, dtype="uint8") as ds:
        ds.write(np.moveaxis(good, -1, 0))
    cases["tiff no georef"] = (tmp_path / "plain.tif", [], 1, "no georeference")
    src = tmp_path / "chart.png"
    write_png(src, good)
    for opt in ("--ship-length", "--cell-size", "--margin"):
        for value in ("0", "-3", "nan"):
            cases[f"{opt} {value}"] = (src, ["--resolution", 1, opt, value], 2, opt)
    cases["cell > chart"] = (src, ["--resolution", 1, "--cell-size", 500], 1, "--cell-size")
    return cases


@pytest.mark.parametrize(
    "case",
    ["missing", "empty", "text", "truncated", "tiny", "no water", "no land", "no resolution",
     "tiff no georef", "cell > chart"]
    + [f"{o} {v}" for o in ("--ship-length", "--cell-size", "--margin")
       for v in ("0", "-3", "nan")],
)
def test_bad_input(case, tmp_path, usv):
    path, extra, code, words = bad_inputs(tmp_path)[case]
    out = tmp_path / "out" / "grid.tif"
    out.parent.mkdir()
    r = usv("preprocess", path, "-o", out, *extra)
    assert_one_line_error(r, code, words)
    if code == 1:
        assert str(path.name) in r.stderr or words.startswith("--")
    assert list(out.parent.iterdir()) == []


def test_kap_without_georeference(kap, tmp_path, usv):
    # drop the header's REF (GCP) records: the chart is then an image without georeference
    data = kap.read_bytes()
    head_end = data.index(b"\x1a")
    header = data[:head_end].decode("latin-1").split("\r\n")
    kept = "\r\n".join(line for line in header if not line.startswith("REF/")).encode("latin-1")
    bad = tmp_path / "noref.kap"
    bad.write_bytes(kept + data[head_end:])
    out = tmp_path / "grid.tif"
    r = usv("preprocess", bad, "-o", out)
    assert_one_line_error(r, 1, "noref.kap")
    assert not out.exists()


def test_output_in_a_missing_directory(tmp_path, usv):
    src = write_png(tmp_path / "chart.png", island_image())
    r = usv("preprocess", src, "-o", tmp_path / "missing" / "g.tif", "--resolution", 1)
    assert_one_line_error(r, 1, "-o", "does not exist")
    r = usv("preprocess", src, "-o", tmp_path / "g.tif", "--resolution", 1,
            "--preview", tmp_path / "missing" / "p.png")
    assert_one_line_error(r, 1, "--preview")
    assert not (tmp_path / "g.tif").exists()


@pytest.mark.parametrize("kind", ["empty", "text", "raster-chart", "no-features"])
def test_bad_s57_cell(bad_cell, kind, tmp_path, usv):
    path, words = bad_cell(kind)
    out = tmp_path / "grid.tif"
    assert_one_line_error(usv("preprocess", path, "-o", out), 1, str(path), words)
    assert not out.exists()


# ---- all or nothing: grid and preview appear together, or neither changes (usvtool.atomic) ----


def one_line(stderr: str) -> str:
    lines = [line for line in stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in stderr, stderr
    return lines[0]


@pytest.fixture
def outputs(tmp_path):
    """An output directory holding an earlier grid (and no preview): (dir, grid, preview)."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "grid.tif").write_bytes(b"an earlier grid \x00\xff")
    return out, out / "grid.tif", out / "grid.png"


def assert_untouched(out: Path) -> None:
    assert sorted(p.name for p in out.iterdir()) == ["grid.tif"]  # no preview, no temporary
    assert (out / "grid.tif").read_bytes() == b"an earlier grid \x00\xff"


def test_grid_and_preview_written_with_no_temporary_left(tmp_path, usv, outputs):
    out, grid, prev = outputs
    src = write_png(tmp_path / "chart.png", island_image())
    r = usv("preprocess", src, "-o", grid, "--preview", prev, "--resolution", 2.5)
    assert r.exit_code == 0, r.stderr
    assert sorted(p.name for p in out.iterdir()) == ["grid.png", "grid.tif"]
    assert read_grid(grid).width == 80 and cv2.imread(str(prev)) is not None


@pytest.mark.parametrize("stage", ["render", "write"])
def test_a_failing_preview_leaves_the_grid_untouched(stage, tmp_path, usv, outputs, monkeypatch):
    import usvtool.chart.preview as preview

    out, grid, prev = outputs
    src = write_png(tmp_path / "chart.png", island_image())
    if stage == "render":  # as the preview's size limit fails, after the grid work

        def fail(*args, **kwargs):
            raise UsvError("--preview-resolution 0.001: the preview would be too large")

        monkeypatch.setattr(preview, "render_preview", fail)
    else:  # the disk fills while the preview is written, the grid's temporary being complete

        def fail(path, rgb):
            Path(path).write_bytes(b"\x89PNG half")
            raise OSError(28, "No space left on device")

        monkeypatch.setattr(preview, "write_png", fail)
    r = usv("preprocess", src, "-o", grid, "--preview", prev, "--resolution", 2.5)
    assert r.exit_code == 1
    assert ("too large" if stage == "render" else "No space left") in one_line(r.stderr)
    assert r.stdout == ""
    assert_untouched(out)


def test_sigterm_while_the_outputs_are_staged(tmp_path, usv, outputs, monkeypatch):
    import usvtool.chart.preview as preview

    out, grid, prev = outputs
    src = write_png(tmp_path / "chart.png", island_image())

    def write_then_signal(path, rgb):
        Path(path).write_bytes(b"\x89PNG half")
        os.kill(os.getpid(), signal.SIGTERM)

    monkeypatch.setattr(preview, "write_png", write_then_signal)
    r = usv("preprocess", src, "-o", grid, "--preview", prev, "--resolution", 2.5)
    assert r.exit_code == 143 and r.stdout == ""
    assert one_line(r.stderr) == "Error: interrupted by SIGTERM"
    assert_untouched(out)


def test_grid_and_preview_in_one_file_refused_before_the_work(tmp_path, usv, outputs):
    out, grid, _ = outputs
    src = write_png(tmp_path / "chart.png", island_image())
    r = usv("preprocess", src, "-o", grid, "--preview", out / ".." / "out" / "grid.tif",
            "--resolution", 2.5)
    assert_one_line_error(r, 1, "--preview", "same file as -o")
    assert_untouched(out)


def chart_is_open(pid: int, chart: Path) -> bool:
    """Whether process ``pid`` has ``chart`` open (Linux /proc)."""
    fds = Path(f"/proc/{pid}/fd")
    try:
        return any(os.readlink(fd) == str(chart) for fd in fds.iterdir())
    except OSError:  # an fd closed while looking, or the process gone
        return False


@pytest.mark.skipif(not Path("/proc/self/fd").is_dir(), reason="needs Linux /proc")
@pytest.mark.parametrize("signum, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_to_a_running_preprocess(charts, outputs, signum, status):
    out, grid, prev = outputs
    chart = (charts / "noaa" / "SanDiego_2.KAP").resolve()  # 29.5 Mpx: seconds of reading
    proc = subprocess.Popen(
        [sys.executable, "-m", "usvtool.cli", "preprocess", chart, "-o", grid, "--preview", prev],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),  # even if we ignore it
    )
    try:
        # the signal goes once the command is at work (reading the chart), not on a timer
        while proc.poll() is None and not chart_is_open(proc.pid, chart):
            time.sleep(0.005)
        assert proc.poll() is None, "preprocess ended before it was seen reading the chart"
        proc.send_signal(signum)
        stdout, stderr = proc.communicate(timeout=120)
    finally:
        proc.kill()
    assert proc.returncode == status, stderr
    assert one_line(stderr) == f"Error: interrupted by {signal.Signals(signum).name}"
    assert stdout == ""
    assert_untouched(out)
