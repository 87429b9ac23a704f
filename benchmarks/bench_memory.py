"""The memory guards' estimates against measured peaks (issue 22 item 6; docs/preprocess.md,
docs/planning.md, docs/simulate.md).

Each case runs one ``usvtool`` command in a subprocess and reads its peak resident size
(``VmHWM``, :func:`measure`), beside the estimate the guard makes of it
(:mod:`usvtool.chart.memory`, :mod:`usvtool.plan.memory`, :mod:`usvtool.sim.memory`). The inputs
are made in a temporary directory: the S-57 cell US5MA12M rendered at 10, 5 and 2.7 m (RGB
GeoTIFFs of 3.5-48 megapixels), its 5 m rendering as a plain PNG and as a 16-bit RGBA GeoTIFF,
the bundled KAPs; env1's grid scaled 2-12 times (1-36 M cells); the UDWA emergency crossing with
denser sample grids, and runs that last their whole duration (20 000 and 100 000 steps of 1, 3
and 7 ships).

Usage: python benchmarks/bench_memory.py [--full]
(--full adds the largest cases: a 191-megapixel chart, a 36 M-cell grid, 100 000-step runs;
about 5 minutes on 2 cores, the default about 2)
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np
import rasterio
import yaml
from affine import Affine

from usvtool.chart import memory as chart_memory
from usvtool.grid import Grid, read_grid, write_grid
from usvtool.plan import memory as plan_memory
from usvtool.sim import memory as sim_memory
from usvtool.sim.controllers import make_controller

ROOT = Path(__file__).resolve().parent.parent
CHARTS = ROOT / "charts"
MiB = 1 << 20


#: Runs ``usvtool`` and, at exit, writes its peak resident kilobytes (``VmHWM``: this process's
#: own, not the parent's copy it was forked from, which ``wait4``'s ``ru_maxrss`` would include)
#: to the file ``$USVTOOL_PEAK_FILE``.
_CHILD = """
import atexit, os, sys
def report():
    with open("/proc/self/status") as status:
        peak = next(line.split()[1] for line in status if line.startswith("VmHWM:"))
    with open(os.environ["USVTOOL_PEAK_FILE"], "w") as out:
        out.write(peak)
atexit.register(report)
from usvtool.cli import main
sys.argv[0] = "usvtool"
main()
"""


def measure(*args) -> tuple[int, dict]:
    """(peak resident bytes, summary JSON) of ``usvtool ARGS`` in a subprocess, which must
    succeed."""
    with tempfile.TemporaryDirectory() as tmp:
        peak = Path(tmp) / "peak"
        env = {**os.environ, "USVTOOL_PEAK_FILE": str(peak)}
        r = subprocess.run([sys.executable, "-c", _CHILD, "-q", *map(str, args)], env=env,
                           capture_output=True, text=True)  # fmt: skip
        if r.returncode != 0:
            raise RuntimeError(f"usvtool {' '.join(map(str, args))}: {r.stderr.strip()}")
        return int(peak.read_text()) * 1024, json.loads(r.stdout)


def row(case: str, sizes: str, need: int, used: int) -> None:
    print(f"| {case} | {sizes} | {need / MiB:.0f} | {used / MiB:.0f} | {need / used:.2f} |")


def inputs(d: Path, full: bool) -> dict[str, Path]:
    """The charts of the preprocess cases, made in ``d``."""
    charts = {k: CHARTS / "noaa" / f"{k}.KAP" for k in ("11361_4", "12205_2", "SanDiego_2")}
    for res in ("10", "5", "2.7"):
        charts[f"boston {res} m"] = d / f"boston_{res}.tif"
        measure("render", CHARTS / "noaa" / "US5MA12M.000", "-o", d / f"boston_{res}.tif",
                "--resolution", res)  # fmt: skip
    with rasterio.open(d / "boston_5.tif") as ds:
        rgb, profile = ds.read(), ds.profile
    import cv2

    cv2.imwrite(str(d / "boston_5.png"), cv2.cvtColor(np.moveaxis(rgb, 0, -1), cv2.COLOR_RGB2BGR))
    charts["boston 5 m PNG"] = d / "boston_5.png"
    alpha = np.full(rgb.shape[1:], 65535, np.uint16)
    alpha[:50] = 0
    with rasterio.open(d / "rgba16.tif", "w", **{**profile, "count": 4, "dtype": "uint16"}) as ds:
        ds.write(np.concatenate([rgb.astype(np.uint16) * 257, alpha[None]]))
    charts["boston 5 m RGBA16"] = d / "rgba16.tif"
    if full:
        with rasterio.open(d / "boston_2.7.tif") as ds:
            big, profile, t = ds.read(), ds.profile, ds.transform
        up = big.repeat(2, axis=1).repeat(2, axis=2)
        with rasterio.open(d / "up2.tif", "w", **{**profile, "width": up.shape[2],
                           "height": up.shape[1], "transform": t @ Affine.scale(0.5),
                           "tiled": True, "compress": "deflate"}) as ds:  # fmt: skip
            ds.write(up)
        charts["boston 1.35 m"] = d / "up2.tif"
    return charts


def preprocess_cases(d: Path, full: bool) -> None:
    print("\npreprocess (estimate: the larger of reading and gridding)\n")
    print("| chart | pixels, cells | estimate MiB | peak MiB | ratio |\n|---|---|---|---|---|")
    for name, chart in inputs(d, full).items():
        extra = ["--resolution", 5] if chart.suffix == ".png" else []
        for cell in ([], ["--cell-size", 50]):
            if name == "boston 1.35 m" and not cell:
                continue  # over the 25 M-cell limit at 3.75 m
            used, s = measure("preprocess", chart, "-o", d / "g.tif", *extra, *cell)
            with warnings.catch_warnings():  # a PNG has no georeference
                warnings.simplefilter("ignore")
                with rasterio.open(chart) as ds:
                    w, h, bands = ds.width, ds.height, ds.count
                    size = np.dtype(ds.dtypes[0]).itemsize
            (pw, ph), (gw, gh) = s["image_size"], (s["width"], s["height"])
            need = max(chart_memory.pixels_need(w, h, bands, size),
                       chart_memory.cells_need(gw, gh, pw * ph, False))  # fmt: skip
            row(f"{name} {' '.join(map(str, cell))}", f"{pw * ph / 1e6:.1f} M, "
                f"{gw * gh / 1e6:.2f} M", need, used)  # fmt: skip
    cell, env1 = CHARTS / "noaa" / "US5MA12M.000", CHARTS / "env1.geojson"
    vector = [(cell, []), (cell, ["--cell-size", 10]), (cell, ["--occupancy", 0.5]),
              (cell, ["--cell-size", 10, "--occupancy", 0.5]), (env1, ["--cell-size", 0.1]),
              (env1, ["--cell-size", 0.1, "--occupancy", 0.5])]  # fmt: skip
    for source, opts in vector:
        used, s = measure("preprocess", source, "-o", d / "g.tif", *opts)
        need = chart_memory.cells_need(s["width"], s["height"], 0, "--occupancy" in opts)
        row(f"{source.name} {' '.join(map(str, opts))}", f"{s['width'] * s['height'] / 1e6:.2f} M",
            need, used)  # fmt: skip


def plan_cases(d: Path, full: bool) -> None:
    print("\nplan (env1 scaled; start (10, 10), goal (490, 490))\n")
    print("| grid, algorithm | cells | estimate MiB | peak MiB | ratio |\n|---|---|---|---|---|")
    env1 = read_grid(CHARTS / "env1.tif")
    for k in (1, 2, 4, 8, 12) if full else (1, 2, 4, 8):
        path = d / f"env1_x{k}.tif"
        cells = env1.cells.repeat(k, 0).repeat(k, 1)
        write_grid(path, Grid(cells, env1.transform @ Affine.scale(1 / k), env1.crs))
        for algo in ("astar", "anyangle", "iwso", "iwso+g"):
            iters = ["--iters", 20] if algo.startswith("iwso") else []
            used, _ = measure("plan", path, "--start", 10, 10, "--goal", 490, 490, "--algo", algo,
                              *iters, "--allow-collision", "-o", d / "r.geojson")  # fmt: skip
            h, w = cells.shape
            row(f"env1 x{k} {algo}", f"{w * h / 1e6:.2f} M", plan_memory.grid_need(w, h), used)


def scenario(d: Path, data: dict, name: str) -> Path:
    path = d / f"{name}.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def simulate_cases(d: Path, full: bool) -> None:
    print("\nsimulate (estimate: a run of the whole duration)\n")
    print("| run | sizes | estimate MiB | peak MiB | ratio |\n|---|---|---|---|---|")
    crossing = yaml.safe_load((CHARTS / "scenarios" / "emergency-crossing.yaml").read_text())
    crossing["sim"]["duration"] = 3
    path = scenario(d, crossing, "crossing")
    runs = [(c, n, {}) for c in ("dwa", "udwa", "udwa+") for n in (101, 201, 401)]
    runs += [("udwa", 201, {"horizon": 20}), ("udwa", 401, {"step": 0.5}),
             ("udwa", 401, {"step": 0.5, "horizon": 20})]  # fmt: skip
    for controller, n, extra in runs:
        params = {"v_samples": n, "omega_samples": n, **extra}
        args = [a for k, v in params.items() for a in ("--param", f"{k}={v}")]
        used, _ = measure("simulate", path, "--controller", controller, *args, "-o", d / "t.csv")
        c = make_controller(controller, **params)
        need = sim_memory.run_need(sim_memory.run_parts(c, 30, 3))
        row(f"crossing {controller} {extra or ''}", f"{n}^2 samples x {c.times.size}", need, used)
    for k in (0, 2, 6):
        for duration in (2000, 10000) if full else (2000,):
            data = {"name": "long", "sim": {"dt": 0.1, "duration": duration, "goal_tolerance": 5},
                    "own": {"start": [0, 0], "goal": [0, 1e7], "heading": 0, "speed": 4,
                            "vessel": "iwso-dwa-usv"},
                    "targets": [{"name": f"t{i}", "start": [200 + 100 * i, 0], "heading": 0,
                                 "speed": 3, "length": 5} for i in range(k)],
                    "controller": {"name": "dwa", "v_samples": 2, "omega_samples": 2,
                                   "horizon": 0.4}}  # fmt: skip
            used, _ = measure("simulate", scenario(d, data, "long"), "-o", d / "t.csv")
            c = make_controller("dwa", v_samples=2, omega_samples=2, horizon=0.4)
            steps = duration * 10
            need = sim_memory.run_need(sim_memory.run_parts(c, steps, k + 1))
            row(f"open water, {k} targets", f"{steps} steps", need, used)
    static = yaml.safe_load((CHARTS / "scenarios" / "env1-static.yaml").read_text())
    static["sim"]["duration"] = 3
    static.pop("route")
    env1 = read_grid(CHARTS / "env1.tif")
    for k in (4, 8, 12) if full else (4, 8):
        grid = d / f"map_x{k}.tif"
        cells = env1.cells.repeat(k, 0).repeat(k, 1)
        write_grid(grid, Grid(cells, env1.transform @ Affine.scale(1 / k), env1.crs))
        used, _ = measure("simulate", scenario(d, {**static, "map": grid.name}, "map"), "-o",
                          d / "t.csv")  # fmt: skip
        c = make_controller("gdwa")
        h, w = cells.shape
        need = sim_memory.run_need(sim_memory.run_parts(c, 30, 1, (w, h)))
        row(f"env1-static, map x{k}", f"{w * h / 1e6:.0f} M cells", need, used)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--full", action="store_true", help="add the largest cases")
    full = parser.parse_args().full
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        preprocess_cases(d, full)
        plan_cases(d, full)
        simulate_cases(d, full)


if __name__ == "__main__":
    main()
