"""Preview PNG: the chart with the navigation grid over it, for a person to read.

The map, north up: the chart image (for an S-57 cell its S-52 drawing; a plain water colour for
vector inputs without one) with obstacle cells tinted red and margin cells yellow. Obstacle
pixels outside the chart (outside a raster's valid area or its image, outside an S-57 cell's
coverage; the grid makes them obstacles) are hatched grey instead: no data. Cell lines are drawn
when cells are at least 8 preview pixels wide. Under the map, a white strip: the title line
(source file, cell size, margin), the legend of the four classes, a scale bar of a round length
and a north arrow.

Drawn with OpenCV (fast, no figure machinery needed for a raster overlay), in blocks of rows so
that a large map needs little more memory than the image itself; the same grid and chart give
the same bytes.
"""

from __future__ import annotations

import math
from pathlib import Path

import cv2
import numpy as np

from usvtool.atomic import atomic_path
from usvtool.grid import MARGIN, NAVIGABLE, OBSTACLE, Grid

MAX_SIDE = 1200  # longest side of the map in pixels, unless a resolution is given
#: Tint colour and opacity of the blocked classes over the chart.
TINT = {OBSTACLE: ((200, 30, 30), 0.6), MARGIN: ((250, 200, 0), 0.6)}
WATER = (212, 234, 238)  # background without a chart image (S-52 DEPDW)
OUTSIDE = -1  # legend key of "outside the chart" (not a grid code)
HATCH = ((160, 160, 160), (90, 90, 90))  # outside the chart: grey with darker diagonals
HATCH_STEP = 6  # pixels between hatch lines
LEGEND = (
    (NAVIGABLE, "navigable"),
    (OBSTACLE, "obstacle"),
    (MARGIN, "margin"),
    (OUTSIDE, "outside the chart"),
)
FONT, FONT_SCALE = cv2.FONT_HERSHEY_SIMPLEX, 0.45
ROW, PAD = 24, 8  # strip row height and padding, pixels
SWATCH = (20, 12)  # legend swatch width, height
MIN_WIDTH = 240  # narrowest strip: scale bar, its label and the north arrow
BLOCK = 512  # map rows drawn at a time


def render_preview(grid: Grid, chart=None, resolution: float | None = None) -> np.ndarray:
    """RGB preview (H, W, 3): the map of ``grid`` over ``chart`` (a RasterChart) and the strip.

    ``resolution`` is metres per map pixel (default: the longest side :data:`MAX_SIDE` pixels);
    a map over the size limit is refused, naming ``--preview-resolution``.
    """
    left, bottom, right, top = grid.bounds
    if resolution is None:
        scale = MAX_SIDE / max(grid.width, grid.height)
        w, h = max(1, round(grid.width * scale)), max(1, round(grid.height * scale))
        px = (right - left) / w
    else:
        frame = preview_frame(grid.bounds, resolution, f"the preview of {_source(grid)}")
        w, h, px = frame.width, frame.height, resolution
    title = title_line(grid)
    width = max(w, MIN_WIDTH, _text_width(title) + 2 * PAD, _legend_width() + 2 * PAD)
    canvas = np.full((h + 3 * ROW + PAD, width, 3), 255, np.uint8)
    xs = left + (np.arange(w) + 0.5) * px
    cols = np.clip(((xs - left) / grid.cell_size).astype(int), 0, grid.width - 1)
    for r0 in range(0, h, BLOCK):
        ys = top - (np.arange(r0, min(r0 + BLOCK, h)) + 0.5) * px
        rows = np.clip(((top - ys) / grid.cell_size).astype(int), 0, grid.height - 1)
        cells = grid.cells[rows][:, cols]
        if chart is None:
            img = np.empty((*cells.shape, 3), np.uint8)
            img[:] = WATER
            outside = np.zeros(cells.shape, bool)
        else:
            img, valid = _sample(chart, xs, ys)
            outside = ~valid & (cells == OBSTACLE)
        block = tint(img, cells)
        _hatch(block, outside, r0)
        canvas[r0 : r0 + len(ys), :w] = block
    _cell_lines(canvas[:h, :w], grid.cell_size / px)
    _strip(canvas, h, w, px, title)
    return canvas


def preview_frame(bounds, resolution: float, what: str):
    """The map's frame at ``resolution`` over ``bounds``, refused over the pixel limit with the
    ``--preview-resolution`` that fits."""
    from usvtool.chart.rendering import limited_frame

    return limited_frame(bounds, resolution, None, what, "--preview-resolution")


def background_resolution(bounds, cell_size: float) -> float:
    """Metres per pixel of an S-57 cell's background by default: half a cell, or the map's own
    pixel (the longest side :data:`MAX_SIDE` pixels) when that is coarser, since the map is
    sampled at that pixel anyway. A default preview therefore never exceeds the size limit.

    >>> background_resolution((0, 0, 1200, 600), 10.0)
    5.0
    >>> background_resolution((0, 0, 60000, 100), 10.0)  # 60 km over 1200 pixels
    50.0
    """
    left, bottom, right, top = bounds
    return max(cell_size / 2, max(right - left, top - bottom) / MAX_SIDE)


def check_s57_preview(path, cell_size: float, resolution: float | None) -> None:
    """Refuse an S-57 preview at ``resolution`` over the size limit from the cell's coverage
    alone, before the grid is made (the default resolution always fits).

    The check uses the grid's bounds (the coverage grown to whole cells), which hold both the
    background's and the map's, so the value suggested works for both.
    """
    if resolution is None:
        return
    from usvtool.chart import gridding, s57
    from usvtool.geodesy import WGS84, reproject_geometries

    coverage = s57.read_coverage(path)
    crs = s57.coverage_utm(coverage)
    bounds = reproject_geometries([coverage], WGS84, crs)[0].bounds
    grid_bounds = gridding.grid_frame(bounds, cell_size, crs).bounds
    preview_frame(grid_bounds, resolution, f"the preview of {Path(path).name}")


def s57_background(path, resolution: float):
    """The S-52 drawing of an S-57 cell, as the preview's background."""
    from usvtool.chart.rendering import render_cell
    from usvtool.chart.s57 import read_cell
    from usvtool.chart.sources import RasterChart

    rgb, truth, frame = render_cell(read_cell(path), resolution, soundings=False)
    return RasterChart.from_rgb(np.moveaxis(rgb, 0, -1), truth != 255, frame, "s57")


def tint(img: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """``img`` (RGB uint8) with the obstacle and margin cells' tints blended in."""
    out = img.copy()
    for code, lut in _TINT_LUTS.items():  # one look-up per channel: the blend of every value
        cv2.copyTo(cv2.LUT(img, lut), (cells == code).view(np.uint8), out)
    return out


def _tint_lut(colour, alpha: float) -> np.ndarray:
    values = np.arange(256, dtype=float)[:, None]
    blend = np.rint((1 - alpha) * values + alpha * np.array(colour, float))
    return blend.astype(np.uint8).reshape(256, 1, 3)


_TINT_LUTS = {code: _tint_lut(colour, alpha) for code, (colour, alpha) in TINT.items()}


def scale_length(metres: float) -> float:
    """The longest round length (1, 2 or 5 times a power of ten) not over ``metres``.

    >>> scale_length(1234.0), scale_length(480.0), scale_length(5.0), scale_length(0.3)
    (1000.0, 200.0, 5.0, 0.2)
    """
    power = 10.0 ** math.floor(math.log10(metres))
    return max(k for k in (1.0, 2.0, 5.0, 10.0) if k * power <= metres * (1 + 1e-9)) * power


def _sample(chart, xs: np.ndarray, ys: np.ndarray):
    """Chart colours and validity at the map pixels' centres (outside its image: invalid)."""
    t = chart.frame.transform
    cc = np.floor((xs - t.c) / t.a).astype(int)
    cr = np.floor((ys - t.f) / t.e).astype(int)
    inside = (cr[:, None] >= 0) & (cr[:, None] < chart.frame.height)
    inside = inside & (cc[None, :] >= 0) & (cc[None, :] < chart.frame.width)
    rows = np.clip(cr, 0, chart.frame.height - 1)
    cols = np.clip(cc, 0, chart.frame.width - 1)
    img = chart.palette[chart.index.take(rows, axis=0).take(cols, axis=1)]
    img[~inside] = 255
    return img, chart.valid.take(rows, axis=0).take(cols, axis=1) & inside


def _hatch(block: np.ndarray, mask: np.ndarray, row0: int) -> None:
    """Hatch the ``mask`` pixels of ``block`` (whose first row is map row ``row0``)."""
    if not mask.any():
        return
    h, w = mask.shape
    period = np.add.outer(np.arange(HATCH_STEP), np.arange(w)) % HATCH_STEP == 0
    pattern = np.where(period[..., None], np.uint8(HATCH[1]), np.uint8(HATCH[0]))
    rows = pattern.take(np.arange(row0, row0 + h) % HATCH_STEP, axis=0)
    cv2.copyTo(rows, mask.view(np.uint8), block)


def _cell_lines(out: np.ndarray, cell_px: float) -> None:
    """Darken the cell boundaries when cells are at least 8 pixels wide."""
    if cell_px < 8:
        return
    h, w = out.shape[:2]
    step = np.arange(0, max(w, h) + 1, cell_px)
    for x in step[step < w]:
        out[:, int(round(x))] = (out[:, int(round(x))] * 0.6).astype(np.uint8)
    for y in step[step < h]:
        out[int(round(y)), :] = (out[int(round(y)), :] * 0.6).astype(np.uint8)


def _strip(canvas: np.ndarray, h: int, w: int, px: float, title: str) -> None:
    """Title, legend, scale bar and north arrow in the rows below the map (``h`` rows high)."""
    _text(canvas, title, (PAD, h + ROW - 8))
    x, y = PAD, h + ROW
    sw, sh = SWATCH
    for key, label in LEGEND:
        top = y + (ROW - sh) // 2
        swatch = tint(np.full((sh, sw, 3), WATER, np.uint8), np.full((sh, sw), key))
        _hatch(swatch, np.full((sh, sw), key == OUTSIDE), 0)
        canvas[top : top + sh, x : x + sw] = swatch
        cv2.rectangle(canvas, (x, top), (x + sw - 1, top + sh - 1), (0, 0, 0), 1)
        x += sw + 6
        _text(canvas, label, (x, y + ROW - 8))
        x += _text_width(label) + 16
    y += ROW
    length = scale_length(px * w / 4)
    bar = max(1, round(length / px))
    cv2.rectangle(canvas, (PAD, y + 10), (PAD + bar - 1, y + 14), (0, 0, 0), -1)
    label = f"{length / 1000:g} km" if length >= 1000 else f"{length:g} m"
    _text(canvas, label, (PAD + bar + 6, y + 16))
    ax = canvas.shape[1] - PAD - 4
    cv2.arrowedLine(canvas, (ax, y + ROW - 2), (ax, y + 2), (0, 0, 0), 2, cv2.LINE_AA,
                    tipLength=0.4)  # fmt: skip
    _text(canvas, "N", (ax - 18, y + ROW - 6))


def _text(canvas: np.ndarray, text: str, origin: tuple[int, int]) -> None:
    cv2.putText(canvas, text, origin, FONT, FONT_SCALE, (0, 0, 0), 1, cv2.LINE_AA)


def _text_width(text: str) -> int:
    return cv2.getTextSize(text, FONT, FONT_SCALE, 1)[0][0]


def _legend_width() -> int:
    return sum(SWATCH[0] + 6 + _text_width(label) + 16 for _, label in LEGEND)


def _source(grid: Grid) -> str:
    return Path(str(grid.tags.get("source", ""))).name or "the grid"


def title_line(grid: Grid) -> str:
    """Source file name, cell size and margin (from the grid's tags)."""
    parts = [_source(grid), f"cell {grid.cell_size:g} m"]
    if "margin_m" in grid.tags:
        parts.append(f"margin {float(grid.tags['margin_m']):g} m")
    return "   ".join(parts)


def write_png(path, rgb: np.ndarray) -> None:
    """Write an RGB array as PNG, atomically."""
    ok, buf = cv2.imencode(".png", cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))
    if not ok:
        raise OSError(f"{path}: PNG encoding failed")
    with atomic_path(path) as tmp:
        tmp.write_bytes(buf.tobytes())
