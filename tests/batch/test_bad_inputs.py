"""A scenario or a chart that does not read fails its own jobs only: ``usvtool batch`` finishes,
the bad jobs fail with the reader's one line (in error.txt and the summary's failures), and the
others are done (issue 22: a scenario nesting brackets 20 000 deep aborted the whole batch
with ``internal error: RecursionError``; an alias bomb hung it before it made DIR)."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

from usvtool.results import read_results

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "tests" / "batch" / "scenarios" / "open-head-on.yaml"


def alias_bomb(levels: int = 9, width: int = 9) -> str:
    """``controller.sides``: 9 levels of 9 aliases (387 million values expanded)."""
    lines = [f"a0: &a0 [{', '.join(['x'] * width)}]"]
    for i in range(1, levels):
        lines.append(f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * width)}]")
    body = "\n  ".join(lines)
    return (f"name: bomb\nown: {{start: [100, 10], goal: [100, 190], speed: 4}}\n"
            f"controller:\n  name: dwa\n  {body}\n  sides: *a{levels - 1}\n")  # fmt: skip


def test_bad_scenarios_and_a_bad_chart_fail_alone(tmp_path):
    (tmp_path / "s").mkdir()
    (tmp_path / "s" / "good.yaml").write_text(SCENARIO.read_text())
    (tmp_path / "s" / "deep.yaml").write_text("name: deep\nown: " + "[" * 20000 + "]" * 20000)
    (tmp_path / "s" / "bomb.yaml").write_text(alias_bomb())
    shutil.copy(ROOT / "charts" / "grid20.geojson", tmp_path / "grid20.geojson")
    (tmp_path / "broken.tif").write_bytes(b"II*\0" + b"\xff" * 400)  # a TIFF header, no image
    pipeline = tmp_path / "p.yaml"
    pipeline.write_text(
        "root: .\ncharts:\n"
        "  good: {source: grid20.geojson, options: {cell-size: 1, no-swell: true}, "
        "start: [0.5, 0.5], goal: [19.5, 19.5]}\n"
        "  broken: {source: broken.tif, start: [0.5, 0.5], goal: [19.5, 19.5]}\n"
        "routes:\n  r: {charts: [good, broken], algorithms: [astar], seeds: [1]}\n"
        "simulation: {scenarios: [s/*.yaml], controllers: [dwa], seeds: [1]}\n")  # fmt: skip
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "usvtool.cli", "batch", str(pipeline), "-j", "1",
                        "-o", str(out)], capture_output=True, text=True, timeout=60)  # fmt: skip
    assert r.returncode == 1 and "Traceback" not in r.stderr, r.stderr
    assert r.stderr.splitlines()[-1] == "Error: 4 of 7 jobs failed"
    summary = json.loads(r.stdout)
    assert (summary["done"], summary["failed"]) == (3, 4)
    errors = {(f["kind"], f["case"]): f["error"] for f in summary["failures"]}
    assert errors[("runs", "deep")] == (f"Error: {tmp_path / 's' / 'deep.yaml'}: line 2: nested "
                                        "deeper than 64 levels")  # fmt: skip
    assert errors[("runs", "bomb")] == (f"Error: {tmp_path / 's' / 'bomb.yaml'}: line 1: more "
                                        "than 200000 values with its aliases expanded")  # fmt: skip
    assert errors[("grids", "broken")].startswith(f"Error: {tmp_path / 'broken.tif'}: ")
    assert errors[("routes", "broken")].startswith("its grid (grids broken preprocess, ")
    assert all(len(e) <= 200 for e in errors.values())
    for f in summary["failures"]:  # (the route on the broken grid never ran: no directory)
        if f["kind"] != "routes":
            assert (out / f["kind"] / f["key"] / "error.txt").read_text() == f["error"] + "\n"
    rows = read_results(out / "metrics.csv")
    assert {(row.kind, row.case) for row in rows} == {("routes", "good"), ("runs", "good")}
