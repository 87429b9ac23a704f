"""Preview PNG: the chart with the navigation grid over it.

Obstacle cells are tinted red, margin cells orange; cell lines are drawn when cells are at least
8 preview pixels wide. Drawn with OpenCV (fast, no figure machinery needed for a raster overlay).
"""

from __future__ import annotations

import cv2
import numpy as np

from usvtool.atomic import atomic_path
from usvtool.grid import MARGIN, OBSTACLE, Grid

MAX_SIDE = 1200  # longest side of the preview in pixels
TINT = {OBSTACLE: (220, 40, 40), MARGIN: (245, 150, 40)}
WATER = (212, 234, 238)


def render_preview(grid: Grid, chart=None) -> np.ndarray:
    """RGB preview (H, W, 3) of ``grid`` over ``chart`` (a RasterChart) or a plain background."""
    left, bottom, right, top = grid.bounds
    scale = MAX_SIDE / max(grid.width, grid.height)
    w, h = max(1, round(grid.width * scale)), max(1, round(grid.height * scale))
    px = (right - left) / w  # metres per preview pixel
    xs = left + (np.arange(w) + 0.5) * px
    ys = top - (np.arange(h) + 0.5) * px
    gc, gr = grid.to_cell_coords(xs, ys)
    cells = grid.cells[np.clip(gr.astype(int), 0, grid.height - 1)][
        :, np.clip(gc.astype(int), 0, grid.width - 1)
    ]
    if chart is not None:
        t = chart.frame.transform
        cc = np.floor((xs - t.c) / t.a).astype(int)
        cr = np.floor((ys - t.f) / t.e).astype(int)
        inside = (cr[:, None] >= 0) & (cr[:, None] < chart.frame.height)
        inside = inside & (cc[None, :] >= 0) & (cc[None, :] < chart.frame.width)
        img = chart.rgb[np.clip(cr, 0, chart.frame.height - 1)][
            :, np.clip(cc, 0, chart.frame.width - 1)
        ].copy()
        img[~inside] = 255
    else:
        img = np.empty((h, w, 3), np.uint8)
        img[:] = WATER
    out = img.astype(np.float32)
    for code, colour in TINT.items():
        sel = cells == code
        out[sel] = 0.45 * out[sel] + 0.55 * np.array(colour, np.float32)
    out = out.astype(np.uint8)
    cell_px = grid.cell_size / px
    if cell_px >= 8:
        step = np.arange(0, max(w, h) + 1, cell_px)
        for x in step[step < w]:
            out[:, int(round(x))] = (out[:, int(round(x))] * 0.6).astype(np.uint8)
        for y in step[step < h]:
            out[int(round(y)), :] = (out[int(round(y)), :] * 0.6).astype(np.uint8)
    return out


def s57_background(path, resolution: float):
    """The S-52 drawing of an S-57 cell, as the preview's background."""
    from usvtool.chart.render import render_cell
    from usvtool.chart.s57 import read_cell
    from usvtool.chart.sources import RasterChart

    rgb, truth, frame = render_cell(read_cell(path), resolution, soundings=False)
    return RasterChart(np.ascontiguousarray(np.moveaxis(rgb, 0, -1)), truth != 255, frame, "s57")


def write_png(path, rgb: np.ndarray) -> None:
    """Write an RGB array as PNG, atomically."""
    ok, buf = cv2.imencode(".png", cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))
    if not ok:
        raise OSError(f"{path}: PNG encoding failed")
    with atomic_path(path) as tmp:
        tmp.write_bytes(buf.tobytes())
