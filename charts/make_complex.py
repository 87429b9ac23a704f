"""Generate complex test maps as GeoJSON obstacle maps (seeded), beyond the bundled env1/env2.

Kinds (:data:`KINDS`), each a square sea area of ``size`` metres (default 500, like env1), local
metre frame (``"frame": "local"``, origin lower-left, a ``bbox``), in the format of the bundled
synthetic maps (``charts/make_synthetic.py``), so ``usvtool preprocess`` reads it:

* ``islands-sparse``, ``islands-medium``, ``islands-dense``: fields of 10, 20 and 50 star-shaped
  islands (make_synthetic's shapes) of decreasing radius, scattered about the start-goal line;
  overlapping islands merge into larger ones. Start and goal in opposite corners.
* ``walls``: four walls across the map, each with one or two gaps, the gaps of successive walls
  on alternating sides, so a route zig-zags; a few rocks between the walls.
* ``channel``: land everywhere but a winding channel of varying width (a meander of three to
  four bends about the diagonal) from the south-west corner to the north-east corner.
* ``harbour``: open sea in the south, a coast in the north with a basin cut into it, two
  breakwaters in front of the basin leaving an entrance, piers along the basin's shore; the
  start in the open sea, the goal at a berth between two piers; a few rocks off the coast.

Every map is drawn from ``numpy.random.default_rng(SeedSequence([seed, KIND_INDEX, draw]))``:
the same seed gives the same bytes. Each file carries its ``start`` and ``goal`` (map metres) and
its ``kind``, ``seed`` and ``draw``. :func:`connected_map` preprocesses a draw with usvtool and
keeps it only when both ends are on navigable cells and the exact any-angle planner joins them
(else it draws again, ``draw`` + 1): the geometry here needs only NumPy and shapely, the check
needs usvtool (imported there).

Run: ``python charts/make_complex.py OUTDIR [--seed 0] [--size 500] [--kinds walls,channel]
[--no-check]`` (writes ``OUTDIR/KIND.geojson``; generated on demand, not committed).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
from collections.abc import Callable
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon, box

_spec = importlib.util.spec_from_file_location(
    "make_synthetic", Path(__file__).with_name("make_synthetic.py")
)
_synthetic = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_synthetic)
island, feature_collection = _synthetic.island, _synthetic.feature_collection

#: preprocessing of the generated maps (as env1 and env2: 1 m cells, 3 m margin)
PREPROCESS = {"cell-size": 1, "margin": 3}
MAX_DRAWS = 20  # draws tried by connected_map before giving up
CLEAR = 25.0  # metres (at size 500) kept free of islands around the start and goal

Layout = tuple[list[Polygon], tuple[float, float], tuple[float, float]]


def _corners(size: float) -> tuple[tuple[float, float], tuple[float, float]]:
    d = 10.0 * size / 500
    return (d, d), (size - d, size - d)


def _field(rng: np.random.Generator, size: float, count: int, r_min: float, r_max: float,
           ends) -> list[Polygon]:  # fmt: skip
    """``count`` islands of radius ``r_min … r_max`` (at size 500), none within :data:`CLEAR` of
    the ends, centred about the line joining them (normal spread 0.2 of its length) so that
    they stand in the way."""
    scale = size / 500
    out: list[Polygon] = []
    ends = np.asarray(ends, float)
    a, b = ends[0], ends[1]
    normal = np.array([a[1] - b[1], b[0] - a[0]])
    while len(out) < count:
        r = rng.uniform(r_min, r_max) * scale
        c = a + rng.uniform(0.1, 0.9) * (b - a) + rng.normal(0, 0.2) * normal
        if not (0 < c[0] < size and 0 < c[1] < size):
            continue
        if np.min(np.hypot(*(ends - c).T)) > 1.3 * r + CLEAR * scale:
            out.append(island(c[0], c[1], r, rng))
    return out


def islands(count: int, r_min: float, r_max: float) -> Callable[..., Layout]:
    def make(rng: np.random.Generator, size: float) -> Layout:
        start, goal = _corners(size)
        return _field(rng, size, count, r_min, r_max, [start, goal]), start, goal

    return make


def walls(rng: np.random.Generator, size: float) -> Layout:
    """Four slightly tilted walls across the map with gaps on alternating sides, a few rocks."""
    s = size / 500
    start, goal = _corners(size)
    polygons: list[Polygon] = []
    levels = np.linspace(0, size, 6)[1:-1] + rng.uniform(-15, 15, 4) * s
    for i, y in enumerate(levels):
        tilt = rng.uniform(-25, 25) * s
        wall = LineString([(-10, y - tilt), (size + 10, y + tilt)]).buffer(
            rng.uniform(3, 6) * s, cap_style="flat"
        )
        side = (0.08, 0.42) if i % 2 == 0 else (0.58, 0.92)
        gaps = [rng.uniform(*side) * size]
        if rng.random() < 0.5:  # a second, narrower gap elsewhere
            gaps.append(rng.uniform(0.1, 0.9) * size)
        for j, x in enumerate(gaps):
            half = (rng.uniform(12, 18) if j == 0 else rng.uniform(8, 11)) * s
            wall = wall.difference(box(x - half, -10, x + half, size + 10))
        polygons.extend(shapely.get_parts(wall))
    for y0, y1 in zip([0, *levels], [*levels, size], strict=True):  # rocks between the walls
        for _ in range(2):
            x = rng.uniform(0.1, 0.9) * size
            y = rng.uniform(y0 + 0.3 * (y1 - y0), y1 - 0.3 * (y1 - y0))
            if min(np.hypot(x - start[0], y - start[1]), np.hypot(x - goal[0], y - goal[1])) > (
                CLEAR * s
            ):
                polygons.append(island(x, y, rng.uniform(4, 8) * s, rng, 24))
    return polygons, start, goal


def channel(rng: np.random.Generator, size: float) -> Layout:
    """The square less a winding channel: a meander about the diagonal of varying width."""
    s = size / 500
    start, goal = _corners(size)
    t = np.linspace(0, 1, 161)
    bends = rng.uniform(3.0, 4.0)
    lateral = (rng.uniform(0.13, 0.2) * size * np.sin(np.pi * bends * t) * np.sin(np.pi * t) ** 0.3
               + rng.uniform(0.02, 0.04) * size * np.sin(2 * np.pi * rng.uniform(5, 8) * t
                                                        + rng.uniform(0, 2 * np.pi)))  # fmt: skip
    along = np.column_stack([t, t]) * (np.subtract(goal, start)) + start
    normal = np.array([-1.0, 1.0]) / np.sqrt(2)
    centre = np.clip(along + lateral[:, None] * normal, 0.5 * CLEAR * s, size - 0.5 * CLEAR * s)
    centre[0], centre[-1] = start, goal
    width = rng.uniform(9, 15, t.size // 20 + 1) * s  # half-widths, varying along the channel
    pieces = [
        LineString(centre[i : i + 21]).buffer(width[i // 20]) for i in range(0, t.size - 1, 20)
    ]
    ends = [Point(start).buffer(CLEAR * s), Point(goal).buffer(CLEAR * s)]
    water = shapely.union_all(pieces + ends)
    land = box(0, 0, size, size).difference(water)
    return list(shapely.get_parts(land)), start, goal


def harbour(rng: np.random.Generator, size: float) -> Layout:
    """Sea in the south, a coast with a basin in the north, breakwaters and piers, rocks."""
    s = size / 500
    start = (10.0 * s, 10.0 * s)
    x = np.linspace(0, size, 41)
    coast_y = 0.62 * size + rng.uniform(-8, 8, x.size).cumsum() * s * 0.3
    land = Polygon([*zip(x, coast_y, strict=True), (size, size), (0, size)])
    b0, b1 = rng.uniform(0.28, 0.36) * size, rng.uniform(0.72, 0.8) * size
    b_top = rng.uniform(0.86, 0.9) * size
    land = land.difference(box(b0, 0.5 * size, b1, b_top))
    piers = int(rng.integers(3, 5))
    xs = np.linspace(b0, b1, piers + 2)[1:-1] + rng.uniform(-6, 6, piers) * s
    length = rng.uniform(0.1, 0.14) * size
    for px in xs:  # piers from the basin's north shore
        land = land.union(box(px - 3 * s, b_top - length, px + 3 * s, b_top + 1))
    y_coast = float(np.interp([b0, b1], x, coast_y).min())
    gap = rng.uniform(24, 30) * s  # between the arms, and at each end of the passage
    y_in, y_out = y_coast - 35 * s, y_coast - 35 * s - gap - 8 * s
    # the east arm shelters the basin's mouth; the west arm runs south of it, leaving a passage
    # between them entered from the east, then north past the east arm's west end
    east = LineString(
        [(b1 + 25 * s, y_coast + 5 * s), (b1 + 10 * s, y_in), (b0 + gap + 10 * s, y_in)]
    )
    west = LineString([(b0 - 25 * s, y_coast + 5 * s), (b0 - 10 * s, y_out), (b1 - gap, y_out)])
    land = land.union(west.buffer(4 * s)).union(east.buffer(4 * s))
    mouth = (b1 + 10 * s, y_out - 20 * s)
    berth = int(rng.integers(0, piers - 1))
    goal = (float((xs[berth] + xs[berth + 1]) / 2), float(b_top - 0.35 * length))
    rocks = _field(rng, size, 8, 5, 12, [start, mouth])
    rocks = [r for r in rocks if r.bounds[3] < y_out - 15 * s]
    return [*shapely.get_parts(land), *rocks], start, goal


KINDS: dict[str, Callable[..., Layout]] = {
    "islands-sparse": islands(10, 25, 50),
    "islands-medium": islands(20, 15, 35),
    "islands-dense": islands(50, 8, 20),
    "walls": walls,
    "channel": channel,
    "harbour": harbour,
}


def generate(kind: str, seed: int = 0, size: float = 500.0, draw: int = 0) -> dict:
    """The GeoJSON document of draw ``draw`` of map ``kind`` for ``seed`` (not yet checked)."""
    if kind not in KINDS:
        raise ValueError(f"unknown map kind {kind!r} (known: {', '.join(KINDS)})")
    index = list(KINDS).index(kind)
    rng = np.random.default_rng(np.random.SeedSequence([seed, index, draw]))
    polygons, start, goal = KINDS[kind](rng, float(size))
    bounds = box(0, 0, size, size)
    polygons = [p.intersection(bounds) for p in polygons]
    polygons = [p for p in polygons if not p.is_empty]
    start, goal = [round(float(v), 3) for v in start], [round(float(v), 3) for v in goal]
    return feature_collection(polygons, (0, 0, size, size), start=start, goal=goal, kind=kind,
                              seed=seed, draw=draw)  # fmt: skip


def connected_map(kind: str, seed: int = 0, size: float = 500.0, options: dict | None = None):
    """``(doc, grid)``: the first draw of ``kind`` whose grid (preprocessed with ``options``,
    default :data:`PREPROCESS`) has both ends on navigable cells joined by the any-angle planner.
    """
    import tempfile

    from usvtool.chart.preprocessing import PreprocessOptions, preprocess
    from usvtool.errors import UsvError
    from usvtool.plan.planner import PlanOptions, plan_route

    opts = {**PREPROCESS, **(options or {})}
    settings = PreprocessOptions(cell_size=float(opts["cell-size"]), margin=float(opts["margin"]))
    for draw in range(MAX_DRAWS):
        doc = generate(kind, seed, size, draw)
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / f"{kind}.geojson"
            path.write_text(json.dumps(doc), encoding="utf-8")
            grid = preprocess(path, settings).grid
        try:
            route = plan_route(grid, doc["start"], doc["goal"], PlanOptions("anyangle")).route
        except UsvError:
            continue
        if route.collision_free:
            return doc, grid
    raise RuntimeError(f"{kind}: no connected draw in {MAX_DRAWS} for seed {seed}")


def write_maps(outdir, kinds=None, seed: int = 0, size: float = 500.0, check: bool = True):
    """Write ``OUTDIR/KIND.geojson`` for every kind (checked with :func:`connected_map`);
    returns the paths."""
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for kind in kinds or KINDS:
        doc = connected_map(kind, seed, size)[0] if check else generate(kind, seed, size)
        paths.append(write_map(out / f"{kind}.geojson", doc))
    return paths


def write_map(path, doc: dict) -> Path:
    """Write one map document to ``path`` (a temporary file renamed into place)."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    tmp.replace(path)
    return path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("outdir")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--size", type=float, default=500.0)
    ap.add_argument("--kinds", default=",".join(KINDS))
    ap.add_argument("--no-check", dest="check", action="store_false")
    args = ap.parse_args()
    for path in write_maps(args.outdir, args.kinds.split(","), args.seed, args.size, args.check):
        print(path)


if __name__ == "__main__":
    main()
