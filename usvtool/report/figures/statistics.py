"""Figures over seeds: convergence curves (IWSO-DWA Figs. 8, 10) and box plots of the route
metrics (IWSO-DWA Table 2 and ISSA Table 3 as distributions)."""

from __future__ import annotations

import numpy as np

from usvtool.errors import UsvError
from usvtool.report.figures.canvas import (
    Plot,
    csv_text,
    figure,
    finite_array,
    fixed,
    panel_grid,
    png,
)
from usvtool.report.figures.outliers import limits, mark
from usvtool.report.figures.styles import ordered, style

#: Decimals of the costs and metric values in the data CSV.
DECIMALS = 6


def convergence_bands(where: str, runs: list[list[float]]) -> np.ndarray:
    """``(3, iterations)``: the median, first and third quartile over the seeds of the best
    cost after each iteration (NumPy's linear percentiles: seeds 1, 2, 3 give 2, 1.5, 2.5).

    >>> convergence_bands("x", [[3.0, 1.0], [1.0, 1.0], [2.0, 1.0]]).tolist()
    [[2.0, 1.0], [1.5, 1.0], [2.5, 1.0]]
    """
    lengths = {len(r) for r in runs}
    if not runs or 0 in lengths:
        raise UsvError(f"{where}: no convergence curve (the exact planners have none)")
    if len(lengths) > 1:
        raise UsvError(f"{where}: the seeds' curves have different lengths "
                       f"({', '.join(map(str, sorted(lengths)))} iterations)")  # fmt: skip
    a = finite_array(where, runs, ndim=2)
    return np.percentile(a, [50, 25, 75], axis=0)


def convergence(curves: dict[str, list[list[float]]], title: str) -> Plot:
    """Best cost against iteration (1, 2, …) per algorithm: the median over its seeds as a line
    and the interquartile range as a band (markers at ten iterations, staggered between the
    algorithms so that they do not hide one another), family by family
    (:func:`~usvtool.report.figures.styles.ordered`), each in its registered style
    (:func:`~usvtool.report.figures.styles.style`: its family's line and marker).

    Data: ``algorithm,iteration,median,q1,q3`` in that order, costs to 6 decimals.
    """
    bands = {name: convergence_bands(f"convergence: {name!r}", curves[name])
             for name in ordered(curves)}  # fmt: skip
    with figure(7.2, 4.4) as fig:
        ax = fig.add_subplot()
        for k, (name, (median, q1, q3)) in enumerate(bands.items()):
            it = np.arange(1, median.size + 1)
            look = style(name)
            n = len(curves[name])
            ax.plot(it, median, linewidth=1.3, marker=look.marker, markersize=3.5,
                    markevery=_marks(median.size, k, len(bands)),
                    label=f"{look.label} ({n} seed{'s' * (n != 1)})", **look.line())
            ax.fill_between(it, q1, q3, color=look.color, alpha=0.15, linewidth=0)
        ax.set_xlabel("iteration")
        ax.set_ylabel("best cost (m)")
        ax.set_title(title)
        fig.legend(loc="outside right upper")
        image = png(fig)
    rows = [(name, i + 1, *fixed(b[:, i], DECIMALS)) for name, b in bands.items()
            for i in range(b.shape[1])]  # fmt: skip
    return Plot(image, csv_text(("algorithm", "iteration", "median", "q1", "q3"), rows))


def _clip(ax, boxes: list[np.ndarray]) -> None:
    """Clip the panel's value axis by :func:`~usvtool.report.figures.outliers.limits` over every
    box's values, each box's values beyond marked at the edge above or below it."""
    found = limits(np.concatenate([np.ravel(b) for b in boxes])) if boxes else None
    if found is None or not found.clipped:
        return
    ax.set_ylim(found.low, found.high)
    for i, b in enumerate(boxes, start=1):
        if found.above is not None:
            mark(ax, i, b[b > found.above], "high")
        if found.below is not None:
            mark(ax, i, b[b < found.below], "low")


def _marks(n: int, k: int, of: int) -> tuple[int, int]:
    """``markevery`` of the ``k``-th of ``of`` curves of ``n`` points: every ``n // 10`` points
    from an offset of ``k / of`` of that step.

    >>> _marks(300, 0, 3), _marks(300, 2, 3), _marks(5, 1, 2)
    ((0, 30), (20, 30), (0, 1))
    """
    step = max(1, n // 10)
    return k * step // of, step


def boxplots(values: dict[str, dict[str, list[float]]], title: str,
             labels: dict[str, str] | None = None) -> Plot:  # fmt: skip
    """One panel per metric (the outer keys, in order; two panels a row), one box per algorithm
    (family by family, :func:`~usvtool.report.figures.styles.ordered`) over its seeds: the median,
    the quartile box, whiskers to the furthest value within 1.5 IQR, the values beyond as points. An
    algorithm without values in a metric keeps its place, empty. Each algorithm's box in its
    registered colour, its edge in its family's line style, under its name or its ``labels``
    entry. A panel's axis leaves out the values a few far ones would squash
    (:mod:`~usvtool.report.figures.outliers`): those are marked at its edge with their value.

    Data: ``metric,algorithm,seed_index,value``, one row per value (6 decimals).
    """
    if not values:
        raise UsvError("boxplots: no metric")
    data = {metric: {name: finite_array(f"boxplots: {metric!r}, {name!r}", per[name], ndim=1)
                     for name in ordered(per)} for metric, per in values.items()}  # fmt: skip
    rows, cols = panel_grid(len(data), 2)
    with figure(7.2, 2.9 * rows + 0.4) as fig:
        axes = fig.subplots(rows, cols, squeeze=False).ravel()
        for ax, (metric, per) in zip(axes, data.items(), strict=False):
            ticks = [(labels or {}).get(name, name) for name in per]
            box = ax.boxplot(list(per.values()), tick_labels=ticks, patch_artist=True,
                             widths=0.6, medianprops={"color": "black"},
                             flierprops={"markersize": 3})  # fmt: skip
            for patch, name in zip(box["boxes"], per, strict=True):
                look = style(name)
                patch.set_facecolor(look.color)
                patch.set_alpha(0.6)
                patch.set_linestyle(look.linestyle)
            _clip(ax, list(per.values()))
            ax.set_title(metric)
            ax.tick_params(axis="x", labelrotation=60)
        for ax in axes[len(data):]:
            ax.set_visible(False)
        fig.suptitle(title)
        image = png(fig)
    table = [(metric, name, i, v) for metric, per in data.items() for name, a in per.items()
             for i, v in enumerate(fixed(a, DECIMALS))]  # fmt: skip
    return Plot(image, csv_text(("metric", "algorithm", "seed_index", "value"), table))
