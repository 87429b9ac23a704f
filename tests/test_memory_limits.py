"""Memory under a process's limits (issue 29): refused before allocating, or one line, never
"internal error".

Each case runs ``python -m usvtool.cli`` in a subprocess, most under a lowered RLIMIT_AS (the
default budget is 3/4 of the room left under it: usvtool/budget.py), with inputs small enough to
take seconds. Before, the budget ignored RLIMIT_AS: these inputs were allowed and died of a
``MemoryError`` ("internal error"), a track file was not counted, the jobs of a pipeline were
listed before any check, and ``batch -j 50`` gave each of 2 jobs 1/50 of the budget.
"""

import json
import resource
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np
import rasterio
import yaml
from affine import Affine
from rasterio.windows import Window

HEAD_ON = Path(__file__).resolve().parent.parent / "charts/scenarios/emergency-head-on.yaml"


def run(*args, address_space: int | None = None, cwd=None) -> subprocess.CompletedProcess:
    """``usvtool ARGS`` in a subprocess, mapping at most ``address_space`` bytes (None: any)."""

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (address_space, address_space))

    return subprocess.run([sys.executable, "-m", "usvtool.cli", *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, timeout=300,
                          preexec_fn=limit if address_space else None)  # fmt: skip


def assert_one_line(r: subprocess.CompletedProcess, *words: str) -> str:
    """Exit 1, one line on stderr holding ``words``, no internal error or traceback, no
    summary."""
    assert r.returncode == 1, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert "internal error" not in r.stderr and "Traceback" not in r.stderr, r.stderr
    for word in words:
        assert word in lines[0], lines[0]
    assert r.stdout == ""
    return lines[0]


def chart_png(path: Path, side: int) -> Path:
    """A side x side RGB PNG, white with a square of land in the middle, written row by row."""
    white = b"\0" + b"\xff" * (3 * side)
    a, b = side // 3, 2 * side // 3
    land = b"\0" + b"\xff" * (3 * a) + bytes((201, 185, 122)) * (b - a) + b"\xff" * (3 * (side - b))
    z = zlib.compressobj(1)
    data = b"".join(z.compress(land if a <= y < b else white) for y in range(side)) + z.flush()

    def chunk(kind: bytes, body: bytes) -> bytes:
        crc = zlib.crc32(kind + body) & 0xFFFFFFFF
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", crc)

    ihdr = struct.pack(">IIBBBBB", side, side, 8, 2, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", data)
                     + chunk(b"IEND", b""))  # fmt: skip
    return path


def test_simulate_with_many_samples_under_an_address_space_limit(tmp_path):
    # 3001 x 3002 samples: 9.64 GiB estimated, within half the machine, not within 1.5 GiB
    r = run("simulate", HEAD_ON, "--param", "v_samples=3000", "--param", "omega_samples=3000",
            "-o", tmp_path / "t.csv", address_space=3 << 29)  # fmt: skip
    assert_one_line(r, "3001 x 3002 samples", "needs about 9.64 GiB", "v_samples", "--max-memory")
    assert not (tmp_path / "t.csv").exists()


def test_preprocess_of_a_large_png_under_an_address_space_limit(tmp_path):
    chart = chart_png(tmp_path / "chart.png", 8000)  # 64 M pixels: 1.50 GiB estimated
    args = ("preprocess", chart, "--resolution", 1, "-o", tmp_path / "g.tif")
    r = run(*args, address_space=5 << 28)
    assert_one_line(r, str(chart), "reading 8000 x 8000 pixels", "needs about 1.50 GiB",
                    "gdal_translate")  # fmt: skip
    # allowed by a --max-memory beyond what the process can map: the guard's line. Four times
    # the pixels, so that even the image's own bytes (768 MB) and the process's libraries
    # (about 540 MiB mapped after the imports) cannot fit, on any machine
    big = chart_png(tmp_path / "big.png", 16000)
    r = run("preprocess", big, "--resolution", 1, "-o", tmp_path / "g.tif", "--max-memory",
            "100G", address_space=5 << 28)  # fmt: skip
    assert_one_line(r, "out of memory while", f"16000 x 16000 pixels of {big}",
                    "GiB needed); give a smaller chart image")  # fmt: skip
    assert not (tmp_path / "g.tif").exists()


def test_plan_on_a_large_grid_under_an_address_space_limit(tmp_path):
    grid = tmp_path / "grid.tif"  # 6000 x 6000 cells, one tile written: 2.95 GiB estimated
    with rasterio.open(grid, "w", driver="GTiff", width=6000, height=6000, count=1, dtype="uint8",
                       crs="EPSG:32611", transform=Affine(1, 0, 500_000, 0, -1, 3_700_000),
                       tiled=True, blockxsize=1024, blockysize=1024, compress="deflate",
                       sparse_ok=True) as ds:  # fmt: skip
        ds.write(np.zeros((1, 1024, 1024), np.uint8), window=Window(0, 0, 1024, 1024))
    r = run("plan", grid, "--start", 500_010, 3_699_990, "--goal", 500_900, 3_699_100,
            "-o", tmp_path / "r.geojson", address_space=3 << 29)  # fmt: skip
    assert_one_line(r, str(grid), "6000 x 6000 cells", "--cell-size", "--max-memory")
    # allowed by a --max-memory beyond what the process can map: the planning's guard's line
    r = run("plan", grid, "--start", 500_010, 3_699_990, "--goal", 500_900, 3_699_100, "-o",
            tmp_path / "r.geojson", "--max-memory", "100G", address_space=3 << 29)  # fmt: skip
    assert_one_line(r, f"out of memory while planning on 6000 x 6000 cells of {grid}",
                    "(about 2.95 GiB needed); preprocess the chart with a larger --cell-size")
    assert not (tmp_path / "r.geojson").exists()


def test_simulate_counts_a_targets_track_file(tmp_path):
    t = np.arange(200_000, dtype=float)  # 200 000 rows: 460 B a row and 7 a byte, 120 MiB
    np.savetxt(tmp_path / "track.csv", np.column_stack([t, 260 + 0 * t, 350 - t / 1000]),
               fmt="%.3f", delimiter=",", header="t,x,y", comments="")  # fmt: skip
    data = yaml.safe_load(HEAD_ON.read_text())
    data["targets"] = [{"name": "replayed", "track": "track.csv", "speed": 0, "length": 3}]
    (tmp_path / "s.yaml").write_text(yaml.safe_dump(data))
    r = run("simulate", tmp_path / "s.yaml", "-o", tmp_path / "t.csv", "--max-memory", "300M")
    assert_one_line(r, "its targets' tracks: 200001 rows", "targets[].track", "--max-memory")
    assert not (tmp_path / "t.csv").exists()


def test_batch_refuses_ten_million_jobs_before_listing_them(tmp_path):
    pipeline = tmp_path / "p.yaml"
    pipeline.write_text(yaml.safe_dump({"functions": {
        "functions": ["F1"], "algorithms": ["pso"], "seeds": {"first": 0, "count": 10**7},
        "pop": 5, "iters": 5, "dim": 2}}))  # fmt: skip
    r = run("batch", pipeline, "-o", tmp_path / "out", address_space=3 << 29)
    assert_one_line(r, "listing 10000000 jobs (10000000 of them in functions)", "28.6 GiB",
                    "seeds, scenes or other lists of functions")  # fmt: skip
    assert not (tmp_path / "out").exists()


def test_batch_refuses_a_billion_seeds_before_listing_them(tmp_path):
    """{first, count} seeds are listed when the pipeline is read: 36 bytes a seed (a tuple's
    slot and an int), 33.5 GiB for 10^9, refused there rather than failing in the listing."""
    pipeline = tmp_path / "p.yaml"
    pipeline.write_text(yaml.safe_dump({"functions": {
        "functions": ["F1"], "algorithms": ["pso"], "seeds": {"first": 0, "count": 10**9},
        "pop": 5, "iters": 5, "dim": 2}}))  # fmt: skip
    r = run("batch", pipeline, "-o", tmp_path / "out", address_space=3 << 29)
    assert_one_line(r, f"{pipeline}: functions.seeds.count: listing 1000000000 seeds needs about "
                    "33.5 GiB", "give a smaller functions.seeds.count")  # fmt: skip
    assert not (tmp_path / "out").exists()


def test_batch_workers_and_their_memory_follow_the_jobs(tmp_path):
    pipeline = tmp_path / "p.yaml"  # 2 jobs: at -j 50, 1/50 of 1 GiB (21 MiB) refused both
    pipeline.write_text(yaml.safe_dump({"simulation": {
        "scenarios": [str(HEAD_ON)], "controllers": ["gdwa"], "seeds": [1, 2]}}))  # fmt: skip
    r = run("batch", pipeline, "-o", tmp_path / "out", "-j", 50, "--max-memory", "1G")
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout)
    assert summary["executor"] == "local, 2 workers"
    assert (summary["done"], summary["failed"]) == (2, 0)


def test_a_memory_error_past_the_guards_is_one_line(tmp_path, usv, monkeypatch, charts):
    def exhausted(*args):
        raise MemoryError("Unable to allocate 763. MiB")

    monkeypatch.setattr("usvtool.grid.read_grid", exhausted)
    r = usv("plan", charts / "env1.tif", "--start", 10, 10, "--goal", 90, 90, "-o",
            tmp_path / "r.geojson")  # fmt: skip
    assert r.exit_code == 1
    assert r.stderr == ("Error: out of memory while running usvtool plan; lower its inputs' "
                        "sizes or --max-memory\n")  # fmt: skip
