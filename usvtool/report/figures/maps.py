"""Figures on the chart: every algorithm's route on the grid (IWSO-DWA Figs. 7, 9), and a chart's
preprocessing (the chart beside its navigation grid, ISSA section 3)."""

from __future__ import annotations

import numpy as np

from usvtool.errors import UsvError
from usvtool.grid import Grid
from usvtool.report.figures.canvas import (
    Plot,
    csv_text,
    figure,
    finite_array,
    fixed,
    png,
    series_style,
)
from usvtool.report.figures.raster import (
    CLASS_NAMES,
    MAX_SIDE,
    class_handles,
    draw_grid,
    map_axes,
    share,
    square_view,
)

#: The papers' markers: "the dark blue triangle represents the start point and the red star
#: represents the target point" (IWSO-DWA Figs. 7, 9, 11-26).
START = {"marker": "^", "color": "#00008b", "markersize": 10, "linestyle": "none"}
GOAL = {"marker": "*", "color": "#e00000", "markersize": 14, "linestyle": "none"}
#: Padding of the routes' view, a fraction of its side.
VIEW_PAD = 0.12


def routes_on_grid(grid: Grid, routes: dict[str, np.ndarray], start, goal, title: str) -> Plot:
    """Every route ``(m, 2)`` (map metres) on the grid, each in its own colour and line style
    (:func:`~usvtool.report.figures.canvas.series_style`, in the order of ``routes``), the start
    and the goal marked, the legend outside the axes. The view is the square around the routes
    padded by :data:`VIEW_PAD` of its side, within the grid: the whole of env1, the harbour
    reach of a large chart.

    Data: ``kind,algorithm,vertex,x,y``, one row per route vertex (``kind`` ``route``), then
    the start and the goal (``kind`` ``start``, ``goal``; ``algorithm`` empty); metres to 3
    decimals. The grid itself is the grid file's.
    """
    points = {name: finite_array(f"routes_on_grid: route {name!r}", p, ndim=2, columns=2)
              for name, p in routes.items()}  # fmt: skip
    start = finite_array("routes_on_grid: start", start, ndim=1, columns=2)
    goal = finite_array("routes_on_grid: goal", goal, ndim=1, columns=2)
    every = np.vstack([start, goal, *points.values()])
    left, bottom, right, top = view = square_view(every[:, 0], every[:, 1], VIEW_PAD,
                                                  bounds=grid.bounds)
    with figure(9.6, 6.4) as fig:
        ax = fig.add_subplot()
        draw_grid(ax, grid, view)
        for i, (name, p) in enumerate(points.items()):
            ax.plot(p[:, 0], p[:, 1], linewidth=1.6, label=name, **series_style(i))
        ax.plot(*start, label="start", **START)
        ax.plot(*goal, label="goal", **GOAL)
        ax.set_xlim(left, right)
        ax.set_ylim(bottom, top)
        map_axes(ax, max(right - left, top - bottom), grid.crs)
        ax.set_title(title)
        handles = ax.get_legend_handles_labels()[0] + class_handles()[1:]
        fig.legend(handles=handles, loc="outside right upper")
        image = png(fig)
    rows = [("route", name, i, *fixed(xy, 3)) for name, p in points.items()
            for i, xy in enumerate(p)]  # fmt: skip
    rows += [("start", "", 0, *fixed(start, 3)), ("goal", "", 0, *fixed(goal, 3))]
    return Plot(image, csv_text(("kind", "algorithm", "vertex", "x", "y"), rows))


def preprocessing(chart_rgb: np.ndarray | None, grid: Grid, title: str) -> Plot:
    """The chart image (e.g. the ``usvtool preprocess --preview`` PNG, read by the caller as RGB)
    beside the navigation grid, with the legend of the classes and their shares; the grid alone
    when ``chart_rgb`` is None. An image longer than 1500 pixels is reduced for display
    (OpenCV area averaging).

    Data: ``class,value,cells,percent``, one row per class of the grid (the legend's figures).
    """
    if chart_rgb is not None:
        chart_rgb = np.asarray(chart_rgb)
        if chart_rgb.dtype != np.uint8 or chart_rgb.ndim != 3 or chart_rgb.shape[2] != 3:
            raise UsvError(f"preprocessing: chart_rgb must be a (h, w, 3) uint8 array, not "
                           f"{chart_rgb.dtype} of shape {chart_rgb.shape}")  # fmt: skip
        chart_rgb = _reduced(chart_rgb)
    left, bottom, right, top = grid.bounds
    with figure(11.0, 5.6) as fig:
        axes = fig.subplots(1, 1 if chart_rgb is None else 2, squeeze=False)[0]
        if chart_rgb is not None:
            axes[0].imshow(chart_rgb, interpolation="antialiased")
            axes[0].set_axis_off()
            axes[0].set_title("chart")
        ax = axes[-1]
        draw_grid(ax, grid)
        ax.set_xlim(left, right)
        ax.set_ylim(bottom, top)
        map_axes(ax, max(right - left, top - bottom), grid.crs)
        ax.set_title(f"navigation grid, {grid.width} x {grid.height} cells of "
                     f"{grid.cell_size:g} m")  # fmt: skip
        fig.suptitle(title)
        fig.legend(handles=class_handles(grid.cells), loc="outside lower center", ncols=3)
        image = png(fig)
    rows = [(name, value, int(np.count_nonzero(grid.cells == value)),
             fixed([share(grid.cells, value)], 3)[0]) for value, name in CLASS_NAMES.items()]
    return Plot(image, csv_text(("class", "value", "cells", "percent"), rows))


def _reduced(rgb: np.ndarray) -> np.ndarray:
    import cv2

    h, w = rgb.shape[:2]
    f = max(h, w) / MAX_SIDE
    if f <= 1:
        return rgb
    size = (max(1, round(w / f)), max(1, round(h / f)))
    return cv2.resize(rgb, size, interpolation=cv2.INTER_AREA)
