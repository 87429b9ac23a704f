"""Figures of the runs in wind (UDWA paper 4.2, Figs. 19-20; docs/report-wind.md): the own-ship
tracks over the wind field, told apart by their cross-track offset; the speed made good toward
the goal against time over a family of wind fields; and the arrival-time differences between
controllers, scene by scene, with their 95 % interval.

Every controller is drawn in its one style (:func:`usvtool.report.figures.styles.style`).
The field is drawn in greys (its speed; arrows where it blows), so that the coloured tracks
stand out on it (each with a white halo).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from usvtool.errors import UsvError
from usvtool.report.figures.canvas import Plot, csv_text, figure, finite_array, fixed, png
from usvtool.report.figures.maps import GOAL, START
from usvtool.report.figures.outliers import limits, mark
from usvtool.report.figures.raster import MAX_SIDE, map_axes
from usvtool.report.figures.styles import style
from usvtool.trace import OWN, Trace

#: Quiver arrows along the longer side of the field.
ARROWS = 14
#: The speed made good is the distance to the goal lost over windows of this many seconds.
SMG_STEP = 2.0
#: A controller's median speed made good is drawn while at least this share of its runs is
#: under way (a median over a few runs left is not the family's).
UNDER_WAY = 0.5
#: Markers along a track: one every this many seconds, each controller's shifted.
MARK_EVERY_S = 20.0
#: The field's strongest wind is drawn this dark (0 white, 1 black): the tracks stay legible.
GREY_MAX = 0.45
#: Figure width, inches: the report's full text width.
WIDTH = 7.2


@dataclass(frozen=True)
class WindScene:
    """A scene drawn over its field: ``u``, ``v`` ``(h, w)`` (m/s toward east and north, row 0
    the northern edge) covering ``extent`` (left, right, bottom, top; map metres), the
    controllers' runs (``traces``), each one's arrival time (None: did not arrive), the goal."""

    name: str
    u: np.ndarray
    v: np.ndarray
    extent: tuple[float, float, float, float]
    traces: dict[str, Trace]
    arrivals: dict[str, float | None]
    goal: tuple[float, float]


@dataclass(frozen=True)
class Difference:
    """One comparison's arrival differences (method - reference, s): ``scenes`` those of the
    scenes where both arrived (by case), ``failed`` the pairs where one did not, and the
    estimate with its 95 % interval (None when not defined, ``note`` saying why)."""

    label: str
    method: str
    scenes: dict[str, float]
    failed: int
    estimate: float | None
    low: float | None
    high: float | None
    note: str = ""


def offsets(trace: Trace, goal) -> tuple[np.ndarray, np.ndarray]:
    """The own ship's along-track distance from her start toward ``goal`` and her offset across
    the start-goal line (m, positive to its left, i.e. to port going to the goal).

    >>> tr = Trace.from_states([0, 1], ["own"], [[[0, 0, 45, 1, 0]], [[0, 10, 45, 1, 0]]])
    >>> [a.round(3).tolist() for a in offsets(tr, (10, 10))]
    [[0.0, 7.071], [0.0, 7.071]]
    """
    own = trace.ship(OWN)
    p = own[:, :2] - own[0, :2]
    axis = np.asarray(goal, float) - own[0, :2]
    norm = float(np.hypot(*axis))
    if norm == 0:
        raise UsvError("offsets: the goal is the start")
    ux, uy = axis / norm
    return p[:, 0] * ux + p[:, 1] * uy, p[:, 1] * ux - p[:, 0] * uy


def made_good(trace: Trace, goal, step: float = SMG_STEP) -> tuple[np.ndarray, np.ndarray]:
    """The speed made good toward ``goal`` (m/s): the distance to it lost over each window of
    ``step`` s from the start, at the windows' middles (the distance linearly interpolated
    between the trace's steps); the windows that end within the run.

    >>> tr = Trace.from_states([0, 1, 2, 3, 4], ["own"],
    ...                        [[[0, y, 0, 1, 0]] for y in (0, 2, 4, 5, 6)])
    >>> [a.tolist() for a in made_good(tr, (0, 100), 2.0)]
    [[1.0, 3.0], [2.0, 1.0]]
    """
    own = trace.ship(OWN)
    distance = np.hypot(own[:, 0] - goal[0], own[:, 1] - goal[1])
    ends = np.arange(0.0, trace.t[-1] - trace.t[0] + 1e-9, step) + trace.t[0]
    d = np.interp(ends, trace.t, distance)
    return (ends[:-1] + step / 2), -np.diff(d) / step


def _field(ax, u, v, extent, vmax: float):
    """The field's speed in greys (white calm, :data:`GREY_MAX` at ``vmax``) and its arrows."""
    h, w = u.shape
    left, right, bottom, top = extent
    speed = np.hypot(u, v)
    shown = speed[:: math.ceil(h / MAX_SIDE), :: math.ceil(w / MAX_SIDE)]
    from matplotlib.colors import ListedColormap

    greys = ListedColormap(np.linspace(1.0, 1.0 - GREY_MAX, 256)[:, None].repeat(3, axis=1))
    image = ax.imshow(shown, extent=(left, right, bottom, top), origin="upper", cmap=greys,
                      vmin=0.0, vmax=vmax, interpolation="nearest", zorder=0)  # fmt: skip
    k = math.ceil(max(h, w) / ARROWS)
    rows, cols = np.arange(k // 2, h, k), np.arange(k // 2, w, k)
    xs = left + (cols + 0.5) * (right - left) / w
    ys = top - (rows + 0.5) * (top - bottom) / h
    ax.quiver(*np.meshgrid(xs, ys), u[np.ix_(rows, cols)], v[np.ix_(rows, cols)],
              color="0.35", pivot="middle", zorder=1, width=0.004)  # fmt: skip
    return image


def _ended(name: str, arrival: float | None) -> str:
    return f"{name}: did not arrive" if arrival is None else f"{name}: {arrival:.1f} s"


def wind_tracks(scenes: Sequence[WindScene]) -> Plot:
    """One column per scene: (top) the field beneath every controller's own-ship track, its
    start and goal; (bottom) each track's offset across the start-goal line against its
    progress along it, which tells tracks apart that lie on top of each other at map scale.
    The legends give each run's arrival time (or that it did not arrive).

    Data: ``scene,controller,t,x,y,along_m,across_m`` (3 decimals), every step of each track.
    """
    if not scenes:
        raise UsvError("wind_tracks: no scene")
    for s in scenes:
        for name, a in (("u", s.u), ("v", s.v)):
            finite_array(f"wind_tracks: {s.name}: {name}", a, ndim=2)
        if s.u.shape != s.v.shape or not s.traces:
            raise UsvError(f"wind_tracks: {s.name}: u and v differ in shape, or no track")
    from matplotlib import patheffects

    halo = [patheffects.withStroke(linewidth=3.0, foreground="white")]
    vmax = max(float(np.hypot(s.u, s.v).max()) for s in scenes) or 1.0
    rows = []
    n = len(scenes)
    with figure(WIDTH, 3.2 + 2.6 + 0.2 * max(len(s.traces) for s in scenes)) as fig:
        axes = fig.subplots(2, n, squeeze=False, height_ratios=(1.55, 1.0))
        for col, s in enumerate(scenes):
            top, bottom = axes[0][col], axes[1][col]
            image = _field(top, s.u, s.v, s.extent, vmax)
            for i, (name, tr) in enumerate(s.traces.items()):
                st = style(name)
                own = tr.ship(OWN)
                every = max(1, round(MARK_EVERY_S / max(float(np.median(np.diff(tr.t))), 1e-9)))
                marks = (round(every * i / max(len(s.traces), 1)), every)
                along, across = offsets(tr, s.goal)
                label = _ended(name, s.arrivals.get(name))
                marked = {"marker": st.marker, "markersize": 4, "markevery": marks}
                # the halo round the line only: round a marker it would blur its shape
                top.plot(own[:, 0], own[:, 1], **st.line(), linewidth=1.4, path_effects=halo,
                         zorder=3)  # fmt: skip
                top.plot(own[:, 0], own[:, 1], color=st.color, linestyle="none", zorder=3.5,
                         **marked)  # fmt: skip
                bottom.plot(along, across, **st.line(), linewidth=1.4, label=label, **marked)
                rows += [(s.name, name, *v) for v in zip(
                    *(fixed(c, 3) for c in (tr.t, own[:, 0], own[:, 1], along, across)),
                    strict=True)]  # fmt: skip
            first = next(iter(s.traces.values())).ship(OWN)[0]
            top.plot(first[0], first[1], **START, zorder=4)
            top.plot(*s.goal, **GOAL, zorder=4)
            left, right, low, high = s.extent
            top.set_xlim(left, right)
            top.set_ylim(low, high)
            map_axes(top, max(right - left, high - low))
            top.set_title(f"({chr(ord('a') + col)}) {s.name}")
            bottom.axhline(0.0, color="0.3", linewidth=0.8, linestyle=":")
            bottom.set_xlabel("along the start-goal line (m)")
            bottom.set_ylabel("off the line (m, + to port)")
            bottom.set_title(f"({chr(ord('a') + n + col)}) {s.name}: offset from the line")
            bottom.legend(loc="best", handlelength=3.0)
        fig.colorbar(image, ax=list(axes[0]), label="wind speed (m/s)", shrink=0.9)
        picture = png(fig)
    header = ("scene", "controller", "t", "x", "y", "along_m", "across_m")
    return Plot(picture, csv_text(header, rows))


def speed_made_good(runs: dict[str, list[tuple[Trace, tuple[float, float]]]],
                    title: str) -> Plot:  # fmt: skip
    """Each controller's speed made good toward the goal (:func:`made_good`) against time over
    its runs (each a trace and its goal): the median (line) and the quartiles (band) of the
    runs still under way, drawn while at least :data:`UNDER_WAY` of its runs are (a run ends
    when it arrives).

    Data: ``controller,t,under_way,median,q25,q75`` (m/s, 3 decimals), one row per window.
    """
    if not runs or not all(runs.values()):
        raise UsvError("speed_made_good: a controller without runs")
    rows = []
    with figure(WIDTH, 3.4) as fig:
        ax = fig.add_subplot()
        for name, pairs in runs.items():
            series = [made_good(tr, goal) for tr, goal in pairs]
            length = max(len(t) for t, _ in series)
            t = next(t for t, _ in series if len(t) == length)
            values = np.full((len(series), length), np.nan)
            for k, (_, smg) in enumerate(series):
                values[k, : smg.size] = smg
            under_way = np.isfinite(values).sum(axis=0)
            keep = under_way >= UNDER_WAY * len(series)
            if not keep.any():
                continue
            t, values, under_way = t[keep], values[:, keep], under_way[keep]
            q25, median, q75 = np.nanpercentile(values, [25, 50, 75], axis=0)
            st = style(name)
            ax.fill_between(t, q25, q75, color=st.color, alpha=0.18, linewidth=0)
            ax.plot(t, median, **st.line(), linewidth=1.5, marker=st.marker, markersize=4,
                    markevery=max(1, int(MARK_EVERY_S / SMG_STEP)),
                    label=f"{name} ({len(series)} runs)")  # fmt: skip
            rows += [(name, *v) for v in zip(fixed(t, 3), under_way.tolist(),
                                              *(fixed(a, 3) for a in (median, q25, q75)),
                                              strict=True)]  # fmt: skip
        ax.set_xlabel("t (s)")
        ax.ticklabel_format(axis="y", useOffset=False)
        ax.set_ylabel("speed made good to the goal (m/s)")
        ax.set_title(title)
        ax.legend(loc="lower left", handlelength=3.0)
        picture = png(fig)
    return Plot(picture, csv_text(("controller", "t", "under_way", "median", "q25", "q75"), rows))


def _clip(ax, differences: Sequence[Difference]) -> None:
    """Clip the time axis by :func:`~usvtool.report.figures.outliers.limits` over every scene's
    difference and every estimate and interval, the scenes beyond marked at the row's edge."""
    ends = [v for d in differences if d.estimate is not None
            for v in (d.estimate, d.low, d.high)]  # fmt: skip
    found = limits([v for d in differences for v in d.scenes.values()] + ends)
    if found is None or not found.clipped:
        return
    ax.set_xlim(found.low, found.high)
    for i, d in enumerate(differences):
        values = np.array(list(d.scenes.values()), float)
        if found.above is not None:
            mark(ax, i, values[values > found.above], "high", axis="x")
        if found.below is not None:
            mark(ax, i, values[values < found.below], "low", axis="x")


def arrival_differences(differences: Sequence[Difference], title: str) -> Plot:
    """One row per comparison: each scene's arrival difference (dots, where both arrived), the
    estimate with its 95 % interval (a bar), zero dotted, and beside it the estimate, the
    interval and the pairs where a run did not arrive (or why there is no estimate).

    The time axis leaves out the few scenes' differences that would squash the rest
    (:mod:`~usvtool.report.figures.outliers`): each is marked at the edge of its row with its
    value.

    Data: ``comparison,case,difference_s,low_s,high_s``: a row per scene drawn, then the
    estimate (case ``estimate``; empty when undefined), 3 decimals.
    """
    if not differences:
        raise UsvError("arrival_differences: no comparison")
    rows = []
    with figure(WIDTH, 0.9 + 0.7 * len(differences)) as fig:
        ax = fig.add_subplot()
        notes = []
        for i, d in enumerate(differences):
            st = style(d.method)
            values = np.array(list(d.scenes.values()), float)
            jitter = (np.arange(values.size) % 5 - 2) * 0.07
            ax.plot(values, i + jitter, linestyle="none", marker=st.marker, markersize=3.5,
                    color=st.color, alpha=0.7)  # fmt: skip
            rows += [(d.label, case, *fixed([v], 3), "", "") for case, v in d.scenes.items()]
            if d.estimate is not None:
                ax.plot([d.low, d.high], [i, i], color=st.color, linewidth=4, alpha=0.55,
                        solid_capstyle="butt")  # fmt: skip
                ax.plot(d.estimate, i, marker="D", color="black", markersize=5)
                rows.append((d.label, "estimate", *fixed([d.estimate, d.low, d.high], 3)))
                note = f"{d.estimate:+.1f} s [{d.low:+.1f}, {d.high:+.1f}]"
            else:
                rows.append((d.label, "estimate", "", "", ""))
                note = d.note
            total = len(d.scenes) + d.failed
            notes.append(note + (f"\n{d.failed} of {total} pairs failed" if d.failed else ""))
        _clip(ax, differences)
        ax.axvline(0.0, color="0.3", linewidth=0.8, linestyle=":")
        ax.set_yticks(range(len(differences)), [d.label for d in differences])
        ax.set_ylim(len(differences) - 0.5, -0.5)
        right = ax.secondary_yaxis("right")
        right.set_yticks(range(len(differences)), notes)
        right.tick_params(length=0)
        ax.set_xlabel("arrival time difference (s; < 0: earlier than the reference)")
        ax.set_title(title)
        picture = png(fig)
    header = ("comparison", "case", "difference_s", "low_s", "high_s")
    return Plot(picture, csv_text(header, rows))
