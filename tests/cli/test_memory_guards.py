"""The memory guards (issue 22 item 6): inputs whose job would exhaust the machine are refused
before allocating, in one line naming what needs the memory, how much, the budget and the option
that brings it down.

Each case runs ``python -m usvtool.cli`` in a subprocess limited to 2 GiB of address space: a
command that tried to allocate its arrays (10 GiB and more in every case) would die of a
MemoryError instead of answering with the guard's line. The 60 000 x 60 000 rasters are sparse
tiled GeoTIFFs of one written tile (tens of KB) and a PNG of a header and one row.
"""

import resource
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np
import pytest
import rasterio
import yaml
from affine import Affine
from rasterio.windows import Window

HUGE = 60_000
ADDRESS_SPACE = 2 << 30


def run_limited(*args) -> subprocess.CompletedProcess:
    """``usvtool ARGS`` in a subprocess that can map at most :data:`ADDRESS_SPACE` bytes."""

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, resource.RLIM_INFINITY))

    command = [sys.executable, "-m", "usvtool.cli", *map(str, args)]
    return subprocess.run(command, capture_output=True, text=True, timeout=120, preexec_fn=limit)


def assert_refused(r: subprocess.CompletedProcess, *words: str) -> None:
    assert r.returncode == 1, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert "MemoryError" not in r.stderr and "internal error" not in r.stderr, r.stderr
    for word in ("needs about", "GiB of memory", "more than the budget of", "--max-memory", *words):
        assert word in lines[0], lines[0]
    assert r.stdout == ""


def sparse_tiff(path: Path, count: int) -> Path:
    """A HUGE x HUGE uint8 GeoTIFF in UTM metres, tiled, with only its first tile written."""
    profile = dict(driver="GTiff", width=HUGE, height=HUGE, count=count, dtype="uint8",
                   crs="EPSG:32611", transform=Affine(1, 0, 500_000, 0, -1, 3_700_000),
                   tiled=True, blockxsize=1024, blockysize=1024, compress="deflate",
                   sparse_ok=True)  # fmt: skip
    with rasterio.open(path, "w", **profile) as ds:
        ds.write(np.full((count, 1024, 1024), 200, np.uint8), window=Window(0, 0, 1024, 1024))
    return path


def png_header(path: Path, width: int, height: int) -> Path:
    """A PNG declaring width x height RGB pixels: signature, IHDR, one row of IDAT, IEND."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        crc = zlib.crc32(kind + data) & 0xFFFFFFFF
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", crc)

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)  # 8-bit RGB, no interlace
    row = zlib.compress(b"\0" * (3 * width + 1))
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", row)
                     + chunk(b"IEND", b""))  # fmt: skip
    return path


def scenario(directory: Path, **changes) -> Path:
    """A head-on encounter on open water (as charts/scenarios/env1-head-on.yaml)."""
    data = {
        "name": "head-on",
        "sim": {"dt": 0.1, "duration": 150, "goal_tolerance": 5},
        "own": {"start": [260, 30], "goal": [260, 380], "heading": 0, "speed": 4,
                "vessel": "iwso-dwa-usv"},
        "targets": [{"name": "other", "start": [260, 350], "heading": 180, "speed": 3,
                     "length": 2.5}],
        "controller": {"name": "gdwa"},
    }  # fmt: skip
    for key, value in changes.items():
        data[key] = {**data[key], **value}
    path = directory / "s.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def test_a_huge_sparse_geotiff_chart(tmp_path):
    chart = sparse_tiff(tmp_path / "chart.tif", 3)
    assert chart.stat().st_size < 200_000
    r = run_limited("preprocess", chart, "-o", tmp_path / "grid.tif")
    assert_refused(r, str(chart), f"{HUGE} x {HUGE} pixels", "70.7 GiB", "gdal_translate")
    assert not (tmp_path / "grid.tif").exists()


def test_a_png_header_declaring_huge_pixels(tmp_path):
    chart = png_header(tmp_path / "chart.png", HUGE, HUGE)
    r = run_limited("preprocess", chart, "--resolution", 1, "-o", tmp_path / "grid.tif")
    assert_refused(r, str(chart), f"{HUGE} x {HUGE} pixels")


def test_plan_on_a_huge_grid(tmp_path):
    grid = sparse_tiff(tmp_path / "grid.tif", 1)
    r = run_limited("plan", grid, "--start", 500_010, 3_699_990, "--goal", 500_900, 3_699_100,
                    "-o", tmp_path / "route.geojson")  # fmt: skip
    # 272 MiB + 3.6e9 cells x 80 bytes = 268.5 GiB
    assert_refused(r, str(grid), f"{HUGE} x {HUGE} cells", "268 GiB", "--cell-size")


def test_simulate_with_huge_sample_grids(tmp_path):
    path = scenario(tmp_path)
    r = run_limited("simulate", path, "--param", "v_samples=5000", "--param",
                    "omega_samples=5000", "-o", tmp_path / "trace.csv")  # fmt: skip
    # 5001 x 5002 samples (the current speed and yaw rate, straight on) x 50 horizon steps
    assert_refused(r, "5001 x 5002 samples x 50 horizon steps", "v_samples", "--param")


def test_simulate_for_a_billion_seconds(tmp_path):
    path = scenario(tmp_path, sim={"duration": 1_000_000_000})
    r = run_limited("simulate", path, "-o", tmp_path / "trace.csv")
    assert_refused(r, "10000000000 steps x 2 ships", "sim.duration")


@pytest.mark.parametrize("size, budget", [("1G", "1.00 GiB"), ("300M", "0.29 GiB")])
def test_max_memory_sets_the_budget(tmp_path, usv, size, budget):
    path = scenario(tmp_path, sim={"duration": 5_000_000})  # 5e7 steps x 2 ships: 76.8 GiB
    r = usv("simulate", path, "-o", tmp_path / "trace.csv", "--max-memory", size)
    assert r.exit_code == 1 and f"more than the budget of {budget} (--max-memory)" in r.stderr
    # an ordinary run (1 500 steps, 22 x 23 samples): 133 MiB, within 300 MB
    short = scenario(tmp_path, sim={"duration": 150})
    r = usv("simulate", short, "-o", tmp_path / "trace.csv", "--max-memory", size)
    assert r.exit_code == 0, r.stderr


@pytest.mark.parametrize("command", ["preprocess", "plan", "simulate", "batch"])
def test_a_bad_max_memory_is_a_usage_error(tmp_path, usv, command):
    r = usv(command, tmp_path / "x", "--max-memory", "lots")
    assert r.exit_code == 2 and "--max-memory" in r.stderr and "is not a size" in r.stderr
