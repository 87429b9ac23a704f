"""Draw an S-57 cell as a georeferenced chart image in the S-52 day colours, with its land truth.

The image is in the UTM zone of the cell's centre and covers the bounds of its coverage
(``M_COVR`` with ``CATCOV=1``). Drawing order, each step over the previous one:

1. no-data grey (NODTA) everywhere;
2. depth areas (DEPARE, then DRGARE), shaded by ``DRVAL1`` against the shallow, safety and deep
   contours (DEPIT, DEPVS, DEPMS, DEPMD, DEPDW);
3. land polygons (LANDA);
4. depth contours (DEPCNT), one pixel wide, grey (DEPCN);
5. soundings, black digits, shallowest first, each skipped if it would overlap one already drawn
   or leave the coverage;
6. coastline (COALNE), one pixel wide (CSTLN);
7. NODTA again on every pixel whose centre is outside the coverage.

Areas are rasterised on pixel centres and nothing is antialiased, so the LANDA pixels are exactly
the land truth minus the pixels covered by the lines and digits drawn over them.

The stage API (``usvtool render``): :func:`render` reads a cell and draws it as
:class:`RenderOptions` say; its :class:`RenderResult` writes the chart and the truth together
(:meth:`RenderResult.write`) and gives the command's summary (:meth:`RenderResult.summary`).
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from usvtool.atomic import atomic_path, staged
from usvtool.chart.georef import Frame, frame_for_bounds
from usvtool.chart.s57 import Cell, read_cell, update_status
from usvtool.errors import UsvError
from usvtool.geodesy import WGS84, reproject_geometries

#: S-52 day colour table entries, in palette index order.
COLOURS = {
    "NODTA": (163, 180, 183),
    "DEPIT": (131, 178, 149),
    "DEPVS": (115, 182, 239),
    "DEPMS": (152, 197, 242),
    "DEPMD": (186, 213, 225),
    "DEPDW": (212, 234, 238),
    "LANDA": (201, 185, 122),
    "DEPCN": (125, 137, 140),
    "SNDG2": (7, 7, 7),
    "CSTLN": (82, 90, 92),
}
INDEX = {name: i for i, name in enumerate(COLOURS)}
PALETTE = np.array(list(COLOURS.values()), dtype=np.uint8)
DEPTH_SHADES = ("DEPIT", "DEPVS", "DEPMS", "DEPMD", "DEPDW")

TRUTH_WATER, TRUTH_LAND, TRUTH_NODATA = 0, 1, 255
#: Largest image drawn, in pixels (about 0.5 GB of working memory at the limit).
MAX_PIXELS = 50_000_000
#: Sounding digits are this high on the chart at its compilation scale (2 mm at 1:25 000 = 50 m),
#: but never fewer pixels than MIN_TEXT_PX, so that they stay legible at fine resolutions.
TEXT_MM = 2.0
MIN_TEXT_PX = 8


def chart_frame(cell: Cell, resolution: float, option: str = "--resolution") -> Frame:
    """The UTM frame covering the cell's coverage at ``resolution`` metres per pixel.

    An image over :data:`MAX_PIXELS` is refused with the resolution that fits, named by
    ``option`` (the command-line option that sets ``resolution``).
    """
    if not math.isfinite(resolution) or resolution <= 0:
        raise UsvError(f"{option} {resolution}: must be a finite number > 0")
    crs = cell.utm
    bounds = reproject_geometries([cell.coverage], WGS84, crs)[0].bounds
    return limited_frame(bounds, resolution, crs, cell.name, option)


def limited_frame(bounds, resolution: float, crs, what: str, option: str) -> Frame:
    """The frame over ``bounds`` at ``resolution``, refusing more than :data:`MAX_PIXELS`.

    The error names ``option`` and the finest resolution, to 0.1 m, whose frame fits: the
    estimate from the area, checked on the frame itself (whole pixels cover the edges) and
    raised by 0.1 m until it fits.
    """
    frame = frame_for_bounds(bounds, resolution, crs)
    if frame.width * frame.height <= MAX_PIXELS:
        return frame
    left, bottom, right, top = bounds
    fits = math.ceil(math.sqrt((right - left) * (top - bottom) / MAX_PIXELS) * 10) / 10
    while fits <= resolution or _pixels(bounds, fits) > MAX_PIXELS:
        fits = (round(fits * 10) + 1) / 10
    raise UsvError(
        f"{option} {resolution:g} m: {what} would be {frame.width} x {frame.height} pixels"
        f" (limit {MAX_PIXELS // 1_000_000} million); use {option} {fits:g} or more"
    )


def _pixels(bounds, resolution: float) -> int:
    frame = frame_for_bounds(bounds, resolution)
    return frame.width * frame.height


def render_cell(
    cell: Cell,
    resolution: float,
    shallow: float = 2.0,
    safety: float = 10.0,
    deep: float = 30.0,
    soundings: bool = True,
) -> tuple[np.ndarray, np.ndarray, Frame]:
    """Draw ``cell``: RGB uint8 (3, H, W), land truth uint8 (H, W) and the frame.

    Truth: 1 = land, 0 = water inside the coverage, 255 = outside the coverage.
    """
    if not shallow <= safety <= deep:
        raise UsvError(
            f"contours shallow {shallow} <= safety {safety} <= deep {deep}: not in order"
        )
    frame = chart_frame(cell, resolution)
    crs = cell.utm

    def project(geoms):
        return reproject_geometries(geoms, WGS84, crs)

    coverage = _burn(frame, project([cell.coverage])).astype(bool)
    land = project(cell.land)
    shade = np.digitize(cell.drval1, [0.0, shallow, safety, deep])
    depth_index = np.array([INDEX[s] for s in DEPTH_SHADES], dtype=np.uint8)[shade]
    shapes = [*zip(project(cell.depth_areas), depth_index.tolist(), strict=True)]
    shapes += [(g, INDEX["LANDA"]) for g in land]
    index = _burn(frame, shapes, fill=INDEX["NODTA"])
    _burn(frame, project(cell.contours), out=index, value=INDEX["DEPCN"])
    if soundings and len(cell.soundings):
        points = project(cell.soundings)
        _draw_soundings(index, ~coverage, frame, points, cell.sounding_depths, cell.scale)
    _burn(frame, project(cell.coastline), out=index, value=INDEX["CSTLN"])
    index[~coverage] = INDEX["NODTA"]

    truth = _burn(frame, land, fill=TRUTH_WATER, value=TRUTH_LAND)
    truth[~coverage] = TRUTH_NODATA
    return np.moveaxis(PALETTE[index], -1, 0), truth, frame


@dataclass
class RenderOptions:
    """Everything :func:`render` can be told (the ``usvtool render`` options)."""

    resolution: float = 10.0  # metres per pixel
    shallow: float = 2.0  # contours, metres: shallow <= safety <= deep
    safety: float = 10.0
    deep: float = 30.0
    soundings: bool = True  # draw the soundings


@dataclass
class RenderResult:
    """A drawn cell: the RGB chart ``(3, H, W)``, its land truth ``(H, W)``, frame and tags."""

    cell: str  # the cell's name (DSID)
    status: dict  # edition, update and update files (usvtool.chart.s57.update_status)
    rgb: np.ndarray
    truth: np.ndarray
    frame: Frame
    tags: dict  # the GeoTIFF tags of both files
    options: RenderOptions
    timings: dict[str, float] = field(default_factory=dict)  # seconds: read, render[, write]
    output: str | None = None  # where write() put the chart
    truth_output: str | None = None  # and the truth (None: not written)

    @property
    def land_fraction(self) -> float:
        """Share of land among the pixels inside the coverage."""
        covered = self.truth != TRUTH_NODATA
        return float((self.truth[covered] == TRUTH_LAND).mean()) if covered.any() else 0.0

    def write(self, output: str | os.PathLike, truth: str | os.PathLike | None = None) -> None:
        """Write the chart to ``output`` and the truth to ``truth`` (if given), all or nothing
        (:class:`usvtool.atomic.staged`); records the paths and the time taken."""
        start = time.perf_counter()
        with staged(output, truth) as (chart_tmp, truth_tmp):  # renamed together at the end
            write_chart(chart_tmp, self.rgb, self.frame, self.tags)
            if truth_tmp:
                write_truth(truth_tmp, self.truth, self.frame, self.tags)
        self.timings["write"] = time.perf_counter() - start
        self.output = os.fspath(output)
        self.truth_output = os.fspath(truth) if truth is not None else None

    def summary(self) -> dict:
        """The ``usvtool render`` summary (``timings_s`` has ``write`` once written)."""
        seconds = {**self.timings, "total": sum(self.timings.values())}
        return {
            "cell": self.cell,
            **self.status,
            "output": self.output,
            "truth": self.truth_output,
            "width": self.frame.width,
            "height": self.frame.height,
            "resolution_m": self.options.resolution,
            "crs": self.frame.crs.to_string(),
            "land_fraction": round(self.land_fraction, 6),
            "soundings": self.options.soundings,
            "timings_s": {k: round(v, 3) for k, v in seconds.items()},
        }


def render(path: str | os.PathLike, options: RenderOptions | None = None) -> RenderResult:
    """Read the S-57 cell at ``path`` (its update files applied) and draw it (:func:`render_cell`).

    Raises :class:`UsvError` for an unreadable cell, contours out of order or an image over
    :data:`MAX_PIXELS`.
    """
    opts = options or RenderOptions()
    start = time.perf_counter()
    status = update_status(path)
    cell = read_cell(path)
    read_s = time.perf_counter() - start
    rgb, truth, frame = render_cell(
        cell, opts.resolution, opts.shallow, opts.safety, opts.deep, opts.soundings
    )
    render_s = time.perf_counter() - start - read_s
    tags = {
        "source": Path(path).name,
        "edition": cell.edition,
        "update": cell.update,
        "resolution_m": opts.resolution,
        "shallow_m": opts.shallow,
        "safety_m": opts.safety,
        "deep_m": opts.deep,
    }
    return RenderResult(
        cell.name, status, rgb, truth, frame, tags, opts, {"read": read_s, "render": render_s}
    )


def write_chart(path, rgb: np.ndarray, frame: Frame, tags: dict | None = None) -> None:
    """Write the RGB chart as a 3-band uint8 GeoTIFF (photometric RGB), atomically."""
    _write(path, rgb, frame, tags, photometric="RGB")


def write_truth(path, truth: np.ndarray, frame: Frame, tags: dict | None = None) -> None:
    """Write the land truth as a 1-band uint8 GeoTIFF with nodata 255, atomically."""
    _write(path, truth[np.newaxis], frame, tags, nodata=TRUTH_NODATA)


def sounding_text(depth: float) -> str:
    """A sounding as charted: decimetres below 31 m unless zero, whole metres from 31 m.

    >>> sounding_text(2.4), sounding_text(12.0), sounding_text(36.6)
    ('2.4', '12', '37')
    """
    if depth < 31 and round(depth * 10) % 10:
        return f"{depth:.1f}"
    return f"{depth:.0f}"


def _draw_soundings(index, taken, frame: Frame, points, depths, scale: int) -> None:
    """Draw depth digits centred on the points, shallowest first, wholly off ``taken`` pixels.

    ``taken`` (the outside of the coverage) is updated with the boxes of the digits drawn.
    """
    import cv2
    import shapely

    font = cv2.FONT_HERSHEY_PLAIN
    height_px = max(MIN_TEXT_PX, round(TEXT_MM / 1000 * (scale or 25_000) / frame.resolution))
    font_scale = height_px / cv2.getTextSize("0", font, 1.0, 1)[0][1]
    xy = shapely.get_coordinates(points)
    cols, rows = ~frame.transform @ (xy[:, 0], xy[:, 1])
    ink = np.zeros(index.shape, dtype=np.uint8)  # OpenCV 5 antialiases text whatever lineType
    for i in np.argsort(depths, kind="stable"):
        text = sounding_text(float(depths[i]))
        (w, h), _ = cv2.getTextSize(text, font, font_scale, 1)
        x0, y0 = round(cols[i] - w / 2), round(rows[i] + h / 2)  # text origin: bottom left
        if x0 < 1 or y0 < h + 1 or x0 + w + 1 > frame.width or y0 + 2 > frame.height:
            continue
        box = (slice(y0 - h - 1, y0 + 2), slice(x0 - 1, x0 + w + 1))
        if taken[box].any():
            continue
        taken[box] = True
        cv2.putText(ink, text, (x0, y0), font, font_scale, 255, 1, cv2.LINE_8)
    index[ink >= 128] = INDEX["SNDG2"]


def _burn(frame: Frame, shapes, fill: int = 0, value: int = 1, out=None) -> np.ndarray:
    """Rasterise shapes (no all_touched) into ``out`` or a new uint8 array filled with ``fill``.

    ``shapes`` are geometries (burnt with ``value``) or (geometry, value) pairs; later ones
    are drawn over earlier ones.
    """
    from rasterio.features import rasterize

    if out is None:
        out = np.full((frame.height, frame.width), fill, dtype=np.uint8)
    shapes = list(shapes)
    if shapes:
        rasterize(shapes, out=out, transform=frame.transform, default_value=value)
    return out


def _write(path, bands: np.ndarray, frame: Frame, tags: dict | None, **profile) -> None:
    import rasterio

    profile.update(
        driver="GTiff",
        width=frame.width,
        height=frame.height,
        count=bands.shape[0],
        dtype="uint8",
        crs=frame.crs,
        transform=frame.transform,
        compress="deflate",
        tiled=True,
    )
    with atomic_path(path) as tmp:
        with rasterio.open(tmp, "w", **profile) as ds:
            ds.write(bands)
            if tags:
                ds.update_tags(**{k: str(v) for k, v in tags.items()})
