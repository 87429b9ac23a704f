"""Preprocessing speed and quality on a real chart: prints the figures.

1. Renders the NOAA ENC cell US5MA12M (S-52 colours, soundings on) at ~4 megapixels.
2. Times ``preprocess`` end to end (read, segment, grid, swell, write) over several runs, and the
   CLI as a subprocess (with Python start-up and imports).
3. Land IoU against the cell's own vector truth, for the membership and chromatic channels.
4. The fuzzy C-means stage against scikit-fuzzy's ``cmeans`` over all pixels: speed-up and the
   difference of land IoU.
5. Each bundled NOAA chart with ink hazards, and US4MD81M at the cell size its size error
   suggests, end to end in a fresh process (read to grid written): time and peak memory, with the
   ink rule ``auto`` beside ``clutter`` (the first version's rule) for the raster charts.

Usage: python benchmarks/bench_preprocess.py [--resolution 9.4] [--runs 5]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from usvtool.chart.preprocessing import PreprocessOptions, preprocess
from usvtool.chart.rendering import RenderOptions, render
from usvtool.chart.segment import segment
from usvtool.chart.sources import read_raster
from usvtool.grid import write_grid

ROOT = Path(__file__).resolve().parent.parent
CELL = ROOT / "charts" / "noaa" / "US5MA12M.000"
#: (chart, options) run end to end in a fresh process by part 5
REAL = [
    ("12205_2.KAP", {}),
    ("SanDiego_2.KAP", {}),
    ("US4MD81M/US4MD81M.000", {"cell_size": 12.1}),
]
# peak memory is the process's own high-water mark (VmHWM, reset by exec; ru_maxrss of a child
# starts from its parent's at fork)
FRESH = """
import json, re, sys, time
from pathlib import Path
from usvtool.chart.preprocessing import PreprocessOptions, preprocess
from usvtool.grid import write_grid
t = time.perf_counter()
r = preprocess(sys.argv[1], PreprocessOptions(**json.loads(sys.argv[2])))
write_grid(sys.argv[3], r.grid)
s = time.perf_counter() - t
kb = int(re.search(r"VmHWM:\\s+(\\d+)", Path("/proc/self/status").read_text())[1])
print(json.dumps({"s": s, "mb": kb / 1024, "stages": r.summary()["timings_s"]}))
"""


def iou(a: np.ndarray, b: np.ndarray, within: np.ndarray) -> float:
    return float((a & b & within).sum() / ((a | b) & within).sum())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--resolution", type=float, default=9.4, help="metres per pixel")
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()

    tmp = Path(tempfile.mkdtemp())
    drawn = render(CELL, RenderOptions(resolution=args.resolution))
    chart_path, truth_path = tmp / "chart.tif", tmp / "truth.tif"
    drawn.write(chart_path, truth_path)
    truth, frame = drawn.truth, drawn.frame
    mp = frame.width * frame.height / 1e6
    print(f"rendering: {frame.width} x {frame.height} px = {mp:.2f} Mpx at {args.resolution} m")

    times, result = [], None
    for _ in range(args.runs):
        t = time.perf_counter()
        result = preprocess(chart_path, PreprocessOptions(cell_size=10.0))
        write_grid(tmp / "grid.tif", result.grid)
        times.append(time.perf_counter() - t)
    print(f"preprocess end to end (API, read..write): median {statistics.median(times):.3f} s, "
          f"min {min(times):.3f} s over {args.runs} runs (target <= 1.5 s)")
    stages = result.summary()["timings_s"]
    print("  stages: " + ", ".join(f"{k} {v:.3f}" for k, v in stages.items()))
    cli = []
    for _ in range(args.runs):
        t = time.perf_counter()
        subprocess.run(
            [sys.executable, "-m", "usvtool.cli", "-q", "preprocess", str(chart_path), "-o",
             str(tmp / "cli.tif"), "--cell-size", "10"],
            check=True, stdout=subprocess.DEVNULL,
        )
        cli.append(time.perf_counter() - t)
    print(f"preprocess via the CLI, cold process (start-up, imports, first calls): median "
          f"{statistics.median(cli):.3f} s over {args.runs} runs (target <= 1.5 s)")

    land_truth, covered = truth == 1, truth != 255
    chart = read_raster(chart_path)
    for channel in ("membership", "chromatic"):
        seg = segment(chart.rgb, chart.valid, channel=channel)
        print(f"land IoU vs the cell's truth, {channel} channel: "
              f"{iou(seg.land, land_truth, covered):.4f} (target >= 0.95)")

    t = time.perf_counter()
    ours = segment(chart.rgb, chart.valid)
    t_ours = ours.timings["colours"] + ours.timings["fcm"]
    t = time.perf_counter()
    full = segment(chart.rgb, chart.valid, sample=None)
    t_full = full.timings["colours"] + full.timings["fcm"]
    iou_ours = iou(ours.land, land_truth, covered)
    iou_full = iou(full.land, land_truth, covered)
    print(f"fuzzy C-means stage: subsample + per-colour prediction {t_ours:.3f} s, "
          f"cmeans over all {int(chart.valid.sum())} pixels {t_full:.2f} s: "
          f"{t_full / t_ours:.1f}x faster (target >= 10x)")
    print(f"  land IoU: ours {iou_ours:.4f}, all-pixel cmeans {iou_full:.4f}, "
          f"difference {abs(iou_ours - iou_full):.4f} (target <= 0.005)")

    print("real charts end to end, fresh process (peak memory includes ~120 MB of imports):")
    for name, options in REAL:
        inks = ["auto", "clutter"] if name.endswith(".KAP") else [None]
        for ink in inks:
            opts = dict(options, **({"ink": ink} if ink else {}))
            runs = [_fresh(ROOT / "charts" / "noaa" / name, opts, tmp) for _ in range(args.runs)]
            best = min(runs, key=lambda r: r["s"])
            label = f"{name} {json.dumps(opts)}"
            print(f"  {label}: median {statistics.median(r['s'] for r in runs):.2f} s, min "
                  f"{best['s']:.2f} s, peak {max(r['mb'] for r in runs):.0f} MB; stages of the "
                  f"fastest: " + ", ".join(f"{k} {v:.2f}" for k, v in best["stages"].items()))


def _fresh(chart: Path, options: dict, tmp: Path) -> dict:
    out = subprocess.run(
        [sys.executable, "-c", FRESH, str(chart), json.dumps(options), str(tmp / "real.tif")],
        check=True, capture_output=True, text=True,
    )
    return json.loads(out.stdout)


if __name__ == "__main__":
    main()
