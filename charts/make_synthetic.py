"""Write the bundled synthetic charts as GeoJSON obstacle maps (deterministic).

* ``env1``, ``env2``: 500 m x 500 m sea areas with islands, in the spirit of the IWSO-DWA
  paper's two environments (its Figure 6 is not in the text we have): start (10, 10), goal
  (490, 490), the straight line blocked and several channels competing. ``env2`` is denser.
* ``grid20``: a 20 x 20 grid environment in the spirit of the ISSA paper's 20 x 20 experiment
  (its Figure 10 is not in the text): start cell (1, 1), goal cell (20, 20), 1 m cells.
* ``grid50``: a 50 x 50 ENC-like river grid (the ISSA paper's Zhenjiang-Yangzhou channel,
  Figure 11): a winding river with islands from cell (2, 2) to cell (50, 50).

Islands are star-shaped polygons whose radius varies with a few harmonics drawn from a fixed
seed. Files carry ``"frame": "local"`` (local metre frame, origin lower-left) and a ``bbox``.

Run: ``python charts/make_synthetic.py [OUTDIR]`` (default: this directory).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon, box, mapping

# (x, y, mean radius) of the islands; the shapes' wobble comes from the seed
ENV1 = [
    (95, 90, 38), (240, 250, 70), (170, 380, 45), (380, 130, 50), (360, 370, 42),
    (90, 260, 30), (260, 90, 28), (450, 300, 25), (300, 450, 25),
]
ENV2 = [
    (80, 70, 30), (180, 150, 45), (300, 110, 40), (420, 200, 45), (120, 290, 40),
    (250, 260, 48), (370, 330, 40), (200, 420, 45), (320, 460, 22), (450, 420, 28),
    (60, 430, 35), (430, 60, 30), (280, 370, 20), (150, 220, 18),
]

# rows from north (y = 20) to south (y = 1); '#' is an obstacle cell
GRID20 = """\
....................
....................
..###.......####....
..###.......####....
..###.........###...
..............###...
.........####.......
.........####...###.
..####...####...###.
..####...####.......
..####..............
.............####...
....###......####...
....###......####...
....###.............
..........###.......
..###.....###...###.
..###.....###...###.
..###...........###.
....................
"""


def island(x: float, y: float, r: float, rng: np.random.Generator, n: int = 48) -> Polygon:
    """A star-shaped island: radius r(theta) = r (1 + sum_k a_k cos(k theta + phi_k))."""
    theta = np.linspace(0, 2 * np.pi, n, endpoint=False)
    k = np.arange(2, 5)
    amp = rng.uniform(0.04, 0.14, k.size)
    phase = rng.uniform(0, 2 * np.pi, k.size)
    radius = r * (1 + (amp[:, None] * np.cos(k[:, None] * theta + phase[:, None])).sum(0))
    return Polygon(np.column_stack([x + radius * np.cos(theta), y + radius * np.sin(theta)]))


def islands(spec, seed: int) -> list[Polygon]:
    rng = np.random.default_rng(seed)
    return [island(x, y, r, rng) for x, y, r in spec]


def grid_cells(art: str) -> list[Polygon]:
    """Unit squares of the '#' cells of an ASCII grid (first line = northern row)."""
    rows = art.strip("\n").splitlines()
    top = len(rows)
    return [
        box(c, top - r - 1, c + 1, top - r)
        for r, line in enumerate(rows)
        for c, ch in enumerate(line)
        if ch == "#"
    ]


def river(size: int = 50, seed: int = 50) -> list[Polygon]:
    """Land of a 50 x 50 river map: the square less a winding channel, with two islands."""
    bends = [(0, 0), (6, 14), (18, 16), (27, 27), (22, 38), (36, 42), (50, 50)]
    line = LineString(bends)
    channel = line.buffer(4.0).union(line.buffer(6.5).intersection(box(12, 10, 40, 46)))
    land = box(0, 0, size, size).difference(channel)
    rng = np.random.default_rng(seed)
    isles = [island(18.0, 16.0, 1.8, rng, 24), island(29.0, 41.0, 1.8, rng, 24)]
    return list(shapely.get_parts(land)) + isles


def feature_collection(polygons, bbox, **meta) -> dict:
    merged = shapely.get_parts(shapely.union_all(polygons))
    return {
        "type": "FeatureCollection",
        "frame": "local",
        "bbox": list(bbox),
        **meta,
        "features": [
            {"type": "Feature", "properties": {}, "geometry": mapping(g)}
            for g in shapely.set_precision(merged, 1e-3)
        ],
    }


def charts() -> dict[str, dict]:
    return {
        "env1": feature_collection(
            islands(ENV1, 1), (0, 0, 500, 500), start=[10, 10], goal=[490, 490]
        ),
        "env2": feature_collection(
            islands(ENV2, 2), (0, 0, 500, 500), start=[10, 10], goal=[490, 490]
        ),
        "grid20": feature_collection(
            grid_cells(GRID20), (0, 0, 20, 20), start=[0.5, 0.5], goal=[19.5, 19.5]
        ),
        "grid50": feature_collection(river(), (0, 0, 50, 50), start=[1.5, 1.5], goal=[49.5, 49.5]),
    }


def main(outdir: str | None = None) -> None:
    out = Path(outdir) if outdir else Path(__file__).parent
    for name, doc in charts().items():
        (out / f"{name}.geojson").write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main(*sys.argv[1:])
