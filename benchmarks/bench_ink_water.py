"""How much navigable water the ink rule removes on the bundled raster charts, and whether it
splits a water body.

For each chart of charts/noaa (11361_4, 12205_2, SanDiego_2), preprocessed with the default
options under ``--ink auto`` and ``--ink clutter``: the navigable cells of each and the
difference (cells and %), the water bodies of 300 cells or more (8-connected components of the
navigable cells; also of the non-obstacle cells, margin counted as water), and every
``clutter`` body that falls into two or more ``auto`` pieces of 300 cells or more. The times are
those of ``preprocess`` in this process (the first chart's include the imports' first calls).

Usage: python benchmarks/bench_ink_water.py [--charts 12205_2,SanDiego_2] [--modes auto,clutter]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import cv2
import numpy as np

from usvtool.chart.preprocessing import PreprocessOptions, preprocess
from usvtool.grid import NAVIGABLE, OBSTACLE

ROOT = Path(__file__).resolve().parent.parent
CHARTS = ("11361_4", "12205_2", "SanDiego_2")
BODY = 300  # cells: a water body


def bodies(water: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(labels, sizes) of the 8-connected components of ``water``."""
    n, labels = cv2.connectedComponents(water.astype(np.uint8), connectivity=8)
    return labels, np.bincount(labels.ravel(), minlength=n)


def splits(reference: np.ndarray, water: np.ndarray) -> list[list[int]]:
    """The sizes of the pieces of ``water`` of BODY cells or more into which a body of
    ``reference`` of BODY cells or more falls, where there are two or more."""
    ref_labels, ref_sizes = bodies(reference)
    labels, _ = bodies(water)
    out = []
    for k in range(1, ref_sizes.size):
        if ref_sizes[k] < BODY:
            continue
        inside = labels[(ref_labels == k) & water]
        pieces = np.bincount(inside)[1:]
        big = sorted((int(p) for p in pieces if p >= BODY), reverse=True)
        if len(big) > 1:
            out.append([int(ref_sizes[k]), *big])
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--charts", default=",".join(CHARTS))
    ap.add_argument("--modes", default="auto,clutter", help="the first is compared with the last")
    args = ap.parse_args()
    modes = args.modes.split(",")
    print("| chart | water | " + " | ".join(f"`{m}` cells, bodies" for m in modes)
          + " | removed | split bodies (cells: pieces) | " + " | ".join(f"`{m}` s" for m in modes)
          + " |")  # fmt: skip
    for name in args.charts.split(","):
        cells, seconds = {}, {}
        for mode in modes:
            t = time.perf_counter()
            cells[mode] = preprocess(ROOT / "charts" / "noaa" / f"{name}.KAP",
                                     PreprocessOptions(ink=mode)).grid.cells  # fmt: skip
            seconds[mode] = time.perf_counter() - t
        first, last = modes[0], modes[-1]
        for what, water_of in (("navigable", lambda c: c == NAVIGABLE),
                               ("not obstacle", lambda c: c != OBSTACLE)):  # fmt: skip
            water = {m: water_of(cells[m]) for m in modes}
            counts = {m: int(water[m].sum()) for m in modes}
            n_bodies = {m: int((bodies(water[m])[1][1:] >= BODY).sum()) for m in modes}
            removed = counts[last] - counts[first]
            split = splits(water[last], water[first])
            print(f"| {name} | {what} | "
                  + " | ".join(f"{counts[m]}, {n_bodies[m]}" for m in modes)
                  + f" | {removed} ({100 * removed / counts[last]:.2f} %) | "
                  + ("; ".join(f"{s[0]}: {', '.join(map(str, s[1:]))}" for s in split) or "none")
                  + " | " + " | ".join(f"{seconds[m]:.2f}" for m in modes) + " |")  # fmt: skip


if __name__ == "__main__":
    main()
