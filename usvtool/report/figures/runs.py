"""Figures of runs against time: the own ship's x, y and heading (IWSO-DWA Figs. 12, 14, …, 26)
and the distance to the nearest ship per controller (UDWA Figs. 10, 13, 16); the tracks over
the wind field are the wind section's (:mod:`usvtool.report.figures.wind`)."""

from __future__ import annotations

import numpy as np

from usvtool.errors import UsvError
from usvtool.measures import target_distances
from usvtool.report.figures.canvas import (
    Plot,
    csv_text,
    figure,
    fixed,
    png,
)
from usvtool.report.figures.styles import ordered, style
from usvtool.trace import OWN, Trace


def unwrapped_heading(heading) -> np.ndarray:
    """Compass headings unwrapped into a continuous curve (no jump at 0/360), shifted by whole
    turns so that the first lies in [0, 360).

    >>> unwrapped_heading([350.0, 5.0, 20.0, 340.0]).tolist()
    [350.0, 365.0, 380.0, 340.0]
    """
    h = np.unwrap(np.asarray(heading, float), period=360.0)
    return h - 360.0 * np.floor(h[0] / 360.0)


def states_against_time(trace: Trace, title: str = "") -> Plot:
    """The own ship's x, y and heading against time, three panels sharing the time axis; the
    heading unwrapped (:func:`unwrapped_heading`), so a turn through north stays one curve.

    Data: ``t,x,y,heading_unwrapped`` (3 decimals), one row per step.
    """
    own = trace.ship(OWN)
    heading = unwrapped_heading(own[:, 2])
    columns = (own[:, 0], own[:, 1], heading)
    with figure(7.2, 5.6) as fig:
        axes = fig.subplots(3, 1, sharex=True)
        for ax, values, label in zip(axes, columns, ("x (m)", "y (m)", "heading (°, compass)"),
                                     strict=True):  # fmt: skip
            ax.plot(trace.t, values, color=style(OWN).color, linewidth=1.3)
            ax.set_ylabel(label)
        axes[-1].set_xlabel("t (s)")
        fig.suptitle(title or "own ship: position and heading")
        image = png(fig)
    rows = zip(fixed(trace.t, 3), *(fixed(c, 3) for c in columns), strict=True)
    return Plot(image, csv_text(("t", "x", "y", "heading_unwrapped"), rows))


def nearest_ship_distance(trace: Trace) -> np.ndarray:
    """``(n,)``: the centre distance from the own ship to the nearest other ship at each step."""
    if len(trace.ships) < 2:
        raise UsvError("nearest_distance: a trace has no ship but the own ship")
    j = trace.ships.index(OWN)
    others = [k for k in range(len(trace.ships)) if k != j]
    d = target_distances(trace.x[:, j], trace.y[:, j], trace.x[:, others], trace.y[:, others])
    return d.min(axis=1)


def nearest_distance(traces: dict[str, Trace], title: str, limit: float | None = None) -> Plot:
    """The distance to the nearest ship against time, one line per controller (in the registry's
    order, :func:`~usvtool.report.figures.styles.ordered`, each in its registered style), its
    minimum marked with the controller's marker and given in the legend, and a dotted line at
    ``limit`` metres when given (a domain, a safe distance: the caption says which).

    Data: ``controller,t,distance_m`` (3 decimals), one row per step of each trace.
    """
    if not traces:
        raise UsvError("nearest_distance: no trace")
    series = {name: nearest_ship_distance(traces[name]) for name in ordered(traces)}
    with figure(7.2, 3.9) as fig:
        ax = fig.add_subplot()
        for name, d in series.items():
            t, k = traces[name].t, int(np.argmin(d))
            look = style(name)
            ax.plot(t, d, linewidth=1.4, marker=look.marker, markevery=[k], markersize=5,
                    label=f"{look.label} (closest {d[k]:.2f} m at {t[k]:.1f} s)", **look.line())
        if limit is not None:
            ax.axhline(float(limit), color="black", linestyle=":", linewidth=1.0,
                       label=f"{float(limit):g} m")  # fmt: skip
        ax.set_ylim(bottom=0)
        ax.set_xlabel("t (s)")
        ax.set_ylabel("distance to the nearest ship (m)")
        ax.set_title(title)
        ax.legend(loc="best")
        image = png(fig)
    rows = [(name, tt, dd) for name, d in series.items()
            for tt, dd in zip(fixed(traces[name].t, 3), fixed(d, 3), strict=True)]  # fmt: skip
    return Plot(image, csv_text(("controller", "t", "distance_m"), rows))
