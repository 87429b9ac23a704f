"""Figures on the chart: every algorithm's route over the chart or its grid (IWSO-DWA Figs. 7, 9),
and a chart's preprocessing (the chart beside its navigation grid, ISSA section 3)."""

from __future__ import annotations

import numpy as np

from usvtool.errors import UsvError
from usvtool.grid import Grid
from usvtool.report.figures.canvas import Plot, csv_text, figure, finite_array, fixed, png
from usvtool.report.figures.raster import (
    CLASS_NAMES,
    ChartImage,
    chart_handles,
    chart_window,
    class_handles,
    draw_chart,
    draw_grid,
    draw_outside,
    fit_view,
    map_axes,
    outside_handle,
    share,
)
from usvtool.report.figures.styles import PRINT_WIDTH_IN, ordered, style

#: The papers' markers: "the dark blue triangle represents the start point and the red star
#: represents the target point" (IWSO-DWA Figs. 7, 9, 11-26).
START = {"marker": "^", "color": "#00008b", "markersize": 9, "linestyle": "none",
         "markeredgecolor": "white", "markeredgewidth": 0.8}  # fmt: skip
GOAL = {"marker": "*", "color": "#e00000", "markersize": 13, "linestyle": "none",
        "markeredgecolor": "white", "markeredgewidth": 0.8}  # fmt: skip
#: Padding of the routes' view on each side, a fraction of the routes' longer extent.
VIEW_PAD = 0.08
#: The routes' view is widened to a width / height in this range (a map strip along a long
#: route would leave no room to see the chart around it; a tall one would not fit the page).
ASPECT = (0.6, 4.0)
#: Views at least this much wider than high put the legend under the map, others beside it.
WIDE = 1.6
#: The tallest map (inches): a taller view is drawn narrower.
MAX_MAP_HEIGHT = 6.0
#: The widest map beside its legend (inches): two square maps with their captions fit an A4
#: page (2 x (3.5 + the margins' 0.9 + about 0.7 of caption) = 10.2 of its 10.4 in).
SIDE_MAP_WIDTH = 3.5
#: A map's margins (inches: left for the northings, right, top for the title, bottom for the
#: eastings), the legend's column beside a tall map, the height of a legend entry, and the
#: columns of the legend under a wide map.
MARGINS = (0.85, 0.15, 0.35, 0.55)
LEGEND_WIDTH = 2.3
ENTRY_HEIGHT = 0.17
LEGEND_COLUMNS = 5
#: Markers along a route: each optimizer's waypoints, at most about this many on a route.
MARKS = 12
#: A route that hugs the grid's edges (usvtool.report.edges) is drawn over a wide dotted band
#: (no method's line is that wide or dotted so), also in the legend.
EDGE_BAND = {"color": "#000000", "linewidth": 6.5, "linestyle": (0, (0.6, 0.9)), "alpha": 0.45,
             "solid_capstyle": "butt", "dash_capstyle": "butt"}  # fmt: skip
EDGE_LABEL = "hugs the grid's edges"


def routes_on_grid(grid: Grid, routes: dict[str, np.ndarray], start, goal, title: str,
                   chart: ChartImage | None = None, hugging=()) -> Plot:
    """Every route ``(m, 2)`` (map metres) in its registered style
    (:func:`~usvtool.report.figures.styles.style`: colour, and its family's line and marker,
    whatever the order of ``routes``; drawn and listed family by family,
    :func:`~usvtool.report.figures.styles.ordered`), marked at its vertices (at most about
    :data:`MARKS`), the start and the goal marked, over ``chart`` (the chart as its preview draws
    it: obstacles tinted, outside the chart hatched, each in the legend, outside the chart when the
    view shows some) or else the grid (obstacles dark, margin grey). The view is the box around the
    routes padded by :data:`VIEW_PAD`, widened to an aspect within :data:`ASPECT` and kept within
    the grid: the whole of env1, the harbour reach of a large chart, never the empty rest of its
    frame. The figure is as wide as the page's text and as high as the view needs. The routes
    named in ``hugging`` (those that hug the grid's edges, :mod:`usvtool.report.edges`) are
    drawn over :data:`EDGE_BAND`, labelled ``NAME (edges)``, with a legend entry of the band.

    Data: ``kind,algorithm,vertex,x,y``, one row per route vertex (``kind`` ``route``, or
    ``route-edges`` for a route in ``hugging``; the routes in the legend's order), then
    the start and the goal (``kind`` ``start``, ``goal``; ``algorithm`` empty); metres to 3
    decimals. The grid itself is the grid file's.
    """
    from matplotlib import patheffects

    points = {name: finite_array(f"routes_on_grid: route {name!r}", routes[name], ndim=2,
                                 columns=2) for name in ordered(routes)}  # fmt: skip
    start = finite_array("routes_on_grid: start", start, ndim=1, columns=2)
    goal = finite_array("routes_on_grid: goal", goal, ndim=1, columns=2)
    every = np.vstack([start, goal, *points.values()])
    left, bottom, right, top = view = fit_view(every[:, 0], every[:, 1], VIEW_PAD, ASPECT,
                                               grid.bounds)  # fmt: skip
    if chart is None:
        background = class_handles()[1:]
    else:
        rows, cols, _ = chart_window(chart, view)
        background = chart_handles(bool(chart.outside[rows, cols].any()))[1:]
    hugging = set(hugging)
    unknown = sorted(hugging - set(points))
    if unknown:
        raise UsvError(f"routes_on_grid: hugging names no route: {', '.join(unknown)}")
    entries = len(points) + 2 + len(background) + bool(hugging)
    size, box, wide = map_layout((right - left) / (top - bottom), entries)
    halo = [patheffects.withStroke(linewidth=2.8, foreground="white", alpha=0.75)]
    with figure(*size, layout=None) as fig:
        ax = fig.add_axes(box)
        if chart is None:
            draw_grid(ax, grid, view)
        else:
            draw_chart(ax, chart, view)
        for name, p in points.items():
            look = style(name)
            if name in hugging:
                ax.plot(p[:, 0], p[:, 1], zorder=1.9, **EDGE_BAND)
            label = f"{look.label} (edges)" if name in hugging else look.label
            ax.plot(p[:, 0], p[:, 1], linewidth=1.5, marker=look.marker, markersize=3.5,
                    markevery=max(1, len(p) // MARKS), label=label, path_effects=halo,
                    **look.line())  # fmt: skip
        ax.plot(*start, label="start", **START, zorder=5)
        ax.plot(*goal, label="goal", **GOAL, zorder=5)
        ax.set_xlim(left, right)
        ax.set_ylim(bottom, top)
        map_axes(ax, max(right - left, top - bottom), grid.crs)
        ax.set_title(title)
        handles = ax.get_legend_handles_labels()[0] + background
        if hugging:
            from matplotlib.lines import Line2D

            handles.append(Line2D([], [], label=EDGE_LABEL, **EDGE_BAND))
        if wide:
            fig.legend(handles=handles, loc="lower center", ncols=LEGEND_COLUMNS,
                       bbox_to_anchor=(0.5, 0.0))  # fmt: skip
        else:
            ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.03, 1.0),
                      borderaxespad=0.0)  # fmt: skip
        image = png(fig)
    rows = [("route-edges" if name in hugging else "route", name, i, *fixed(xy, 3))
            for name, p in points.items() for i, xy in enumerate(p)]  # fmt: skip
    rows += [("start", "", 0, *fixed(start, 3)), ("goal", "", 0, *fixed(goal, 3))]
    return Plot(image, csv_text(("kind", "algorithm", "vertex", "x", "y"), rows))


def map_layout(aspect: float, entries: int):
    """((width, height) inches, axes box in figure fractions, legend below) of a map of
    width / height ``aspect`` with a legend of ``entries``: the page's text width; a view at
    least :data:`WIDE` wide has the legend under it in :data:`LEGEND_COLUMNS` columns, any other
    beside it, at most :data:`SIDE_MAP_WIDTH` wide and :data:`MAX_MAP_HEIGHT` high. The axes is
    placed by hand, at
    exactly the map's aspect (Matplotlib's constrained layout can leave the labels of an
    equal-aspect axes outside the figure).

    >>> map_layout(1.0, 10)  # 3.5 in square (of 7.165 - 0.85 - 0.15 - 2.3); 0.35 + 0.55 more
    ((7.165, 4.4), (0.119, 0.125, 0.488, 0.795), False)
    """
    left, right, top, bottom = MARGINS
    wide = aspect >= WIDE
    if wide:
        map_w = PRINT_WIDTH_IN - left - right
        map_h = map_w / aspect
        legend = ENTRY_HEIGHT * -(-entries // LEGEND_COLUMNS) + 0.15
        height = top + map_h + bottom + legend
        y0 = bottom + legend
    else:
        map_w = min(PRINT_WIDTH_IN - left - right - LEGEND_WIDTH, SIDE_MAP_WIDTH)
        map_h = min(map_w / aspect, MAX_MAP_HEIGHT)
        map_w = map_h * aspect
        height = top + max(map_h, ENTRY_HEIGHT * entries + 0.1) + bottom
        y0 = height - top - map_h
    box = (left / PRINT_WIDTH_IN, y0 / height, map_w / PRINT_WIDTH_IN, map_h / height)
    return (round(PRINT_WIDTH_IN, 3), round(height, 3)), tuple(round(v, 3) for v in box), wide


def preprocessing(chart: ChartImage | None, grid: Grid, title: str) -> Plot:
    """The chart (its preview's map, :func:`~usvtool.report.figures.raster.preview_chart`)
    beside the navigation grid, both over the grid's bounds in map metres, the grid's cells
    outside the chart hatched as the preview hatches them, with the legend of the classes and
    their shares; the grid alone when ``chart`` is None.

    Data: ``class,value,cells,percent``, one row per class of the grid (the legend's figures;
    the cells outside the chart are obstacle cells).
    """
    left, bottom, right, top = grid.bounds
    panels = 1 if chart is None else 2
    side = (PRINT_WIDTH_IN - 0.5) / panels
    aspect = (right - left) / (top - bottom)
    with figure(PRINT_WIDTH_IN, min(side / aspect, MAX_MAP_HEIGHT) + 1.1, "compressed") as fig:
        axes = fig.subplots(1, panels, squeeze=False, sharex=True, sharey=True)[0]
        if chart is not None:
            draw_chart(axes[0], chart, grid.bounds)
            axes[0].set_title("chart (preview: obstacle red, margin yellow)")
        ax = axes[-1]
        draw_grid(ax, grid)
        if chart is not None:
            draw_outside(ax, chart)
        for a in axes:
            a.set_xlim(left, right)
            a.set_ylim(bottom, top)
            map_axes(a, max(right - left, top - bottom), grid.crs)
        ax.set_title(f"grid, {grid.width} x {grid.height} cells of {grid.cell_size:g} m")
        fig.suptitle(title)
        handles = class_handles(grid.cells)
        if chart is not None and chart.outside.any():
            handles.append(outside_handle(100.0 * float(chart.outside.mean())))
        fig.legend(handles=handles, loc="outside lower center", ncols=min(len(handles), 3))
        image = png(fig)
    rows = [(name, value, int(np.count_nonzero(grid.cells == value)),
             fixed([share(grid.cells, value)], 3)[0]) for value, name in CLASS_NAMES.items()]
    return Plot(image, csv_text(("class", "value", "cells", "percent"), rows))
