"""``preprocess``: any chart input to a swelled navigation grid (ISSA paper section 3).

Image inputs go through segmentation (:mod:`usvtool.chart.segment`), vector inputs are
rasterised straight onto the grid; both then share gridding and swelling
(:mod:`usvtool.chart.gridding`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from usvtool.chart import gridding, memory, sources
from usvtool.chart.segment import Segmentation, segment
from usvtool.errors import UsvError
from usvtool.grid import MARGIN, OBSTACLE, Grid

#: The ISSA paper's test vessel YL-2500 is 2.5 m long (its Table 4).
DEFAULT_SHIP_LENGTH = 2.5
#: The paper's cell: 1.5 x ship length.
CELL_PER_SHIP_LENGTH = 1.5


@dataclass
class PreprocessOptions:
    """Everything ``preprocess`` can be told; ``None`` means the documented default."""

    ship_length: float = DEFAULT_SHIP_LENGTH
    cell_size: float | None = None  # default 1.5 x ship_length
    margin: float | None = None  # metres; default 0.5 cell (the paper's rule)
    swell: bool = True  # False: grid used as drawn (already swelled, or a grid environment)
    resolution: float | None = None  # metres per pixel of a plain image
    cutline: str | None = None  # GeoJSON polygon: pixels of a raster chart outside it are outside
    bounds: tuple[float, float, float, float] | None = None  # GeoJSON extent
    clusters: int = 8
    land_colours: list[tuple[int, int, int]] = field(default_factory=list)
    channel: str = "membership"
    threshold: float | None = None  # fixed 0..255 threshold instead of Otsu (paper: 100)
    min_area: int = 16  # pixels: smaller land specks and water holes are clutter
    ink: str = "auto"  # ink in water: auto (by stroke shape), clutter or obstacle (chart.ink)
    occupancy: float = 0.0  # obstacle share above which a cell blocks (0: any pixel)
    min_depth: float | None = None  # S-57: default s57.DEFAULT_MIN_DEPTH
    hazard_radius: float | None = None  # S-57: default s57.DEFAULT_HAZARD_RADIUS
    seed: int = 0
    max_memory: int | None = None  # bytes (chart.memory); None: usvtool.budget's default

    @property
    def cell(self) -> float:
        return self.cell_size if self.cell_size is not None else (
            CELL_PER_SHIP_LENGTH * self.ship_length
        )

    @property
    def margin_m(self) -> float:
        if not self.swell:
            return 0.0
        return self.margin if self.margin is not None else 0.5 * self.cell


@dataclass
class PreprocessResult:
    """A navigation grid, what it came from, and the figures of the run."""

    grid: Grid
    details: dict  # the grid's parameters, sizes, fractions and stage timings (summary())
    chart: sources.RasterChart | None  # the chart image, for previews
    segmentation: Segmentation | None

    def summary(self) -> dict:
        """The ``usvtool preprocess`` summary (the CLI adds ``output`` and ``preview``)."""
        return dict(self.details)


def preprocess(path, options: PreprocessOptions | None = None) -> PreprocessResult:
    """Turn the chart at ``path`` into a navigation grid."""
    opts = options or PreprocessOptions()
    timings: dict[str, float] = {}
    t = time.perf_counter()
    kind = sources.chart_kind(path)
    chart = seg = None
    extra: dict = {}
    if kind in ("raster", "kap"):
        chart = sources.read_raster(path, opts.resolution, opts.cutline, opts.max_memory)
        timings["read"] = time.perf_counter() - t
        with memory.segmenting(path, chart.index.shape[1], chart.index.shape[0]):
            seg = _named(path, segment)(
                (chart.index, chart.palette),
                chart.valid,
                clusters=opts.clusters,
                land_colours=opts.land_colours,
                channel=opts.channel,
                threshold=opts.threshold,
                min_area=opts.min_area,
                ink=opts.ink,
                seed=opts.seed,
            )
        timings.update({f"segment_{k}": v for k, v in seg.timings.items()})
        t = time.perf_counter()
        frame = gridding.grid_frame(chart.frame.bounds, opts.cell, chart.frame.crs)
        with memory.check_cells(path, frame.width, frame.height, chart.index.size, False,
                                opts.max_memory):  # fmt: skip
            fraction = gridding.occupancy_fraction(seg.blocked, chart.frame, frame)
            obstacle = gridding.obstacles_from_fraction(fraction, opts.occupancy)
        crs = chart.frame.crs
        extra = {
            "threshold": seg.threshold,
            "clusters": seg.clusters,
            "image_size": [int(chart.index.shape[1]), int(chart.index.shape[0])],
            "image_resolution_m": chart.frame.resolution,
            "ink_hazard_fraction": round(float(seg.hazard.sum() / seg.hazard.size), 6),
        }
    else:
        for option, value, use in (
            ("--resolution", opts.resolution, "plain images"),
            ("--cutline", opts.cutline, "raster charts"),
        ):
            if value is not None:
                raise UsvError(f"{path}: {option} is for {use}; this is a {kind} source")
        if kind == "s57":
            from usvtool.chart import s57

            min_depth = opts.min_depth if opts.min_depth is not None else s57.DEFAULT_MIN_DEPTH
            radius = (
                opts.hazard_radius if opts.hazard_radius is not None else s57.DEFAULT_HAZARD_RADIUS
            )
            vec = sources.read_s57(path, min_depth, radius)
            extra = {"min_depth_m": min_depth, "hazard_radius_m": radius, **s57.update_status(path)}
        else:
            vec = sources.read_geojson(path, opts.bounds)
        timings["read"] = time.perf_counter() - t
        t = time.perf_counter()
        frame = gridding.grid_frame(vec.extent.bounds, opts.cell, vec.crs)
        with memory.check_cells(path, frame.width, frame.height, 0, opts.occupancy > 0,
                                opts.max_memory):  # fmt: skip
            obstacle = _rasterise(vec, frame, opts.occupancy)
        crs = vec.crs
    timings["grid"] = time.perf_counter() - t

    t = time.perf_counter()
    cells = gridding.swell(obstacle, opts.cell, opts.margin_m)
    timings["swell"] = time.perf_counter() - t
    if (cells == OBSTACLE).all():
        raise UsvError(f"{path}: no navigable water on the grid")
    if (cells != 0).all():
        raise UsvError(
            f"{path}: the safety margin leaves no navigable cell; reduce --margin "
            f"({opts.margin_m:g} m)"
        )

    params = {
        "source": str(path),
        "source_kind": chart.kind if chart else kind,
        "cell_size_m": opts.cell,
        "ship_length_m": opts.ship_length,
        "margin_m": opts.margin_m,
        "occupancy": opts.occupancy,
    }
    if chart is not None:
        params.update(
            clusters=opts.clusters,
            channel=opts.channel,
            threshold=seg.threshold,
            threshold_rule="fixed" if opts.threshold is not None else "otsu",
            min_area_px=opts.min_area,
            ink=opts.ink,
            land_colours=[list(c) for c in opts.land_colours],
            seed=opts.seed,
        )
        if opts.cutline is not None:
            params["cutline"] = str(opts.cutline)
    else:
        params.update(extra)
    grid = Grid(cells, frame.transform, crs, params)
    n = cells.size
    summary = {
        **params,
        "width": grid.width,
        "height": grid.height,
        "bounds": list(grid.bounds),
        "crs": crs.to_string() if crs is not None else None,
        "obstacle_fraction": round(float((cells == OBSTACLE).sum() / n), 6),
        "margin_fraction": round(float((cells == MARGIN).sum() / n), 6),
        "navigable_fraction": round(float((cells == 0).sum() / n), 6),
        **extra,
        "timings_s": {k: round(v, 4) for k, v in timings.items()},
    }
    return PreprocessResult(grid, summary, chart, seg)


def _named(path, func):
    """``func`` with its :class:`UsvError` messages prefixed by the chart's path."""

    def call(*args, **kwargs):
        try:
            return func(*args, **kwargs)
        except UsvError as exc:
            raise UsvError(f"{path}: {exc}") from None

    return call


def _rasterise(vec: sources.VectorChart, frame, occupancy: float) -> np.ndarray:
    """Obstacle cells of a vector chart; cells outside its extent are obstacles too.

    With ``occupancy == 0`` every cell an obstacle touches blocks (rasterio ``all_touched``);
    otherwise the covered share is measured on an 8x finer raster.
    """
    from rasterio import features

    shape = (frame.height, frame.width)
    outside = features.geometry_mask([vec.extent], shape, frame.transform, all_touched=False)
    if vec.obstacles.size == 0:
        return outside
    if occupancy <= 0:
        hit = features.rasterize(
            ((g, 1) for g in vec.obstacles), shape, transform=frame.transform,
            all_touched=True, dtype="uint8",
        )
        return (hit > 0) | outside
    k = 8
    fine = features.rasterize(
        ((g, 1) for g in vec.obstacles), (shape[0] * k, shape[1] * k),
        transform=frame.transform @ frame.transform.scale(1 / k), dtype="uint8",
    )
    share = fine.reshape(shape[0], k, shape[1], k).mean(axis=(1, 3))
    return gridding.obstacles_from_fraction(share, occupancy) | outside
