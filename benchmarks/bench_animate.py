"""``usvtool animate``'s time and output size per format (GIF, MP4, HTML), side by side, for a
bundled scenario and a 10-minute run of 35 ships.

Runs (written to a temporary folder):

- ``rudee-inlet-channel``: the bundled scenario on its chart with its route, run to its end
  (about 185 s of ship time, 2 ships);
- ``35 ships``: a generated trace of 35 ships over 600 s at 0.1 s (each on a slowly turning
  course with 0.3 degrees of heading noise a step, 2-8 m/s, over 3 km; the generator of
  tests/report/test_animate.py);
- with ``--ais``, the New York AIS scene 1 of the ``ais`` family (``under-way``, radius 5 km,
  600 s asked: 53 ships; it arrives after about 277 s).

Each animation is made by the facade in this process (``usvtool.report.animate``) with the
command's defaults (800x600, ``--speed 10``, ``--fps 10``, ``--wake 60``, ``--tolerance 0.5``)
after one warm-up call; ``read`` is reading the trace and events alone (the CSV reader,
:func:`usvtool.trace.read_trace`, part of every format's time). Best of ``--repeat``.

Usage: python benchmarks/bench_animate.py [--repeat 1] [--ais] [--formats gif,mp4,html]
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from usvtool.report import AnimateOptions, animate
from usvtool.report.animation.scene import load_scene
from usvtool.trace import Trace, write_events, write_trace

ROOT = Path(__file__).resolve().parent.parent


def synthetic(d: Path, ships: int = 35, seconds: float = 600.0, dt: float = 0.1) -> Path:
    """The 35-ship trace and its events (module docstring) in ``d``."""
    rng = np.random.default_rng(1)
    t = np.round(np.arange(0.0, seconds + dt / 2, dt), 3)
    n = t.size
    heading = (rng.uniform(0, 360, ships) + rng.uniform(0, 40, ships)
               * np.sin(2 * np.pi * t[:, None] / rng.uniform(120, 400, ships))
               + rng.normal(0, 0.3, (n, ships))) % 360  # fmt: skip
    speed = np.repeat(rng.uniform(2, 8, ships)[None], n, 0)
    a = np.radians(heading)
    x = rng.uniform(0, 3000, ships) + np.cumsum(speed * np.sin(a) * dt, axis=0)
    y = rng.uniform(0, 3000, ships) + np.cumsum(speed * np.cos(a) * dt, axis=0)
    names = ["own"] + [f"ship{j}" for j in range(1, ships)]
    write_trace(d / "ships35.csv", Trace(t, names, x, y, heading, speed, np.zeros((n, ships))))
    lengths = [15.0] + [float(v) for v in rng.uniform(10, 200, ships - 1)]
    write_events(d / "ships35.events.json", {
        "steps": [], "encounters": [],
        "run": {"scenario": "35 ships", "controller": "none", "goal": [1500.0, 1500.0],
                "goal_tolerance": 5.0, "map": None, "route": None,
                "ships": [{"name": s, "length": v} for s, v in zip(names, lengths, strict=True)]},
    })  # fmt: skip
    return d / "ships35.csv"


def simulate(d: Path, name: str, *args: str) -> Path:
    out = d / f"{name}.csv"
    usvtool = str(Path(sys.executable).parent / "usvtool")
    subprocess.run([usvtool, "-q", "simulate", *args, "-o", str(out),
                    "--events", str(d / f"{name}.events.json")], check=True,
                   stdout=subprocess.DEVNULL)  # fmt: skip
    return out


def best(fn, repeat: int) -> tuple[float, object]:
    times, value = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - start)
    return min(times), value


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--repeat", type=int, default=1)
    p.add_argument("--ais", action="store_true", help="also the New York AIS scene (53 ships)")
    p.add_argument("--formats", default="gif,mp4,html")
    args = p.parse_args(argv)
    formats = args.formats.split(",")
    if "mp4" in formats and shutil.which("ffmpeg") is None:
        print("ffmpeg is not installed: no MP4", file=sys.stderr)
        formats.remove("mp4")
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        runs = {"rudee-inlet-channel": simulate(
            d, "rudee", str(ROOT / "charts/scenarios/rudee-inlet-channel.yaml"))}
        runs["35 ships, 600 s"] = synthetic(d)
        if args.ais:
            (d / "ais").mkdir()
            runs["AIS New York scene 1"] = simulate(
                d, "ais", "--family", "ais", "--kind", "under-way", "--scene", "1",
                "--family-option", f"encounters={ROOT / 'charts/ais/nyharbor-encounters.csv'}",
                "--family-option", f"tracks={ROOT / 'charts/ais/nyharbor-tracks.parquet'}",
                "--family-option", "duration=600", "--family-option", "radius=5000",
                "--controller", "udwa", "--scenario-out", str(d / "ais" / "scene.yaml"))
        animate(AnimateOptions(str(runs["rudee-inlet-channel"]), "html"))  # warm-up
        header = f"{'run':24} {'ships':>5} {'run s':>6} {'read s':>7}"
        for f in formats:
            header += f" | {f + ' s':>7} {f + ' bytes':>11} {'frames':>6}"
        print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores at the start")
        print(header)
        for name, trace in runs.items():
            read, scene = best(lambda trace=trace: load_scene(trace), args.repeat)
            line = f"{name:24} {len(scene.ships):5d} {scene.duration:6.1f} {read:7.2f}"
            for f in formats:
                seconds, result = best(lambda f=f, trace=trace: animate(
                    AnimateOptions(str(trace), f)), args.repeat)  # fmt: skip
                frames = "" if result.frames is None else str(result.frames)
                line += f" | {seconds:7.2f} {len(result.content):11d} {frames:>6}"
            print(line, flush=True)
        print(f"load average {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
