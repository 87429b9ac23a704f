"""Encounter snapshots (IWSO-DWA Figs. 11-26; UDWA Figs. 8-9, 11-12, 14-15): the ships at chosen
times with their tracks so far and their ship domains, and the choice of those times from the
events JSON.

Ship domain (docs/colregs.md, UDWA section 4.1): an ellipse centred on the ship, its full axes
7 L along her heading and 3 L across, drawn dashed at true scale for every ship with her own
length. The hull is drawn at her length, or at :data:`HULL_MIN` of the panel's side when that is
larger (at the charts' scales a 2.5 m hull would be a pixel or two), as the papers draw their
boats larger than life.
"""

from __future__ import annotations

import numpy as np

from usvtool.angles import compass_to_math, wrap360
from usvtool.encounter import DOMAIN_LENGTH_FACTOR, DOMAIN_WIDTH_FACTOR
from usvtool.errors import UsvError
from usvtool.grid import Grid
from usvtool.report.figures.canvas import Plot, csv_text, figure, finite_array, fixed, png
from usvtool.report.figures.maps import GOAL, START
from usvtool.report.figures.raster import draw_grid, map_axes, square_view
from usvtool.report.figures.runs import nearest_ship_distance
from usvtool.report.figures.styles import PRINT_WIDTH_IN, ship_styles
from usvtool.trace import OWN, Trace

#: The domain's full axes in ship lengths (:mod:`usvtool.encounter`, docs/colregs.md).
DOMAIN_LENGTHS = (DOMAIN_LENGTH_FACTOR, DOMAIN_WIDTH_FACTOR)
#: Target starts: open circles in each target's colour (IWSO-DWA: "the purple circle represents
#: the start point of the obstacle ship"; a purple of its own would be one more colour to tell
#: from the targets'). The ships' colours are
#: :func:`~usvtool.report.figures.styles.ship_styles`: the own ship blue, the obstacle ships
#: vermillion first, as in IWSO-DWA section 5.3 ("the blue boat indicates the USV and the red
#: boat indicates the obstacle ship").
TARGET_START = {"marker": "o", "markerfacecolor": "white", "markersize": 5.5,
                "markeredgewidth": 1.4, "linestyle": "none"}  # fmt: skip
#: The hull outline, bow toward +x, two units long (scaled to the hull's length).
HULL = np.array([(1.0, 0.0), (0.3, 0.32), (-1.0, 0.32), (-1.0, -0.32), (0.3, -0.32)])
#: The hull is drawn at least this fraction of a panel's side long, to be seen.
HULL_MIN = 1 / 45
#: The view is the square around every track and the goal, padded by the larger of this
#: fraction of its side and a domain's length.
VIEW_PAD = 0.08
#: Times are matched to the trace's steps to this tolerance (files hold them to 1 ms).
TIME_TOL = 5e-4


def snapshot_times(trace: Trace, events: dict) -> dict[str, float]:
    """The three states of IWSO-DWA Figs. 11-26 from a run's events JSON (``encounters``):

    - ``preparatory``: the earliest onset of an encounter (class other than ``none``);
    - ``meeting``: the CPA of the encounter with the smallest closest distance (its
      ``cpa_time_s``);
    - ``completion``: the end of the run (the trace's last step). Not the encounter's release:
      when the ships pass outside the clear distance (3.5 L) the release is the step after the
      CPA, the same picture as the meeting state.

    Without an encounter: the first step, the step closest to any target (the middle step
    without targets), and the last step.
    """
    encounters = events.get("encounters") if isinstance(events, dict) else None
    if not isinstance(encounters, list):
        raise UsvError("snapshot_times: the events hold no 'encounters' list (not the events "
                       "JSON of usvtool simulate)")  # fmt: skip
    latched = [e for e in encounters if isinstance(e, dict) and e.get("class") != "none"]
    t = trace.t
    try:
        if latched:
            onset = min(float(e["onset_s"]) for e in latched)
            closest = min(latched, key=lambda e: (float(e["closest_distance_m"]), e["cpa_time_s"]))
            meeting = float(closest["cpa_time_s"])
        else:
            onset = t[0]
            meeting = t[_closest_step(trace)]
    except (KeyError, TypeError, ValueError) as e:
        raise UsvError(f"snapshot_times: an encounter lacks a number ({e})") from None
    return {"preparatory": float(onset), "meeting": float(meeting), "completion": float(t[-1])}


def _closest_step(trace: Trace) -> int:
    if len(trace.ships) < 2:
        return trace.n_steps // 2
    return int(np.argmin(nearest_ship_distance(trace)))


def encounter_snapshots(trace: Trace, times: dict[str, float], lengths: dict[str, float],
                        grid: Grid | None = None, title: str = "", goal=None) -> Plot:
    """One panel per entry of ``times`` (state name: seconds, in order), each with every ship's
    track up to the last step at or before that time, the ship there as an oriented hull and
    her domain ellipse (``lengths``: metres per ship name), the own ship's start (triangle),
    the targets' (circles), the own ship's ``goal`` (star) when given, and ``grid`` behind.
    Every panel shows the same square around all the tracks (whole run) and the goal
    (:data:`VIEW_PAD`), within the grid when there is one.

    Data: ``state,t,ship,x,y,heading,domain_length_m,domain_width_m``: each ship as drawn in
    each panel (``t`` the step's time). The tracks are the trace's rows up to ``t``.
    """
    if not times:
        raise UsvError("encounter_snapshots: no snapshot time")
    missing = [s for s in trace.ships if s not in lengths]
    if missing:
        raise UsvError(f"encounter_snapshots: no length for ship {', '.join(map(repr, missing))}")
    size = {s: float(lengths[s]) for s in trace.ships}
    if not all(v > 0 for v in size.values()):
        raise UsvError("encounter_snapshots: ship lengths must be > 0")
    goal = None if goal is None else finite_array("encounter_snapshots: goal", goal, 1, 2)
    steps = {state: _step(trace, state, at) for state, at in times.items()}
    xs, ys = [trace.x.ravel()], [trace.y.ravel()]
    if goal is not None:
        xs.append(goal[:1])
        ys.append(goal[1:])
    view = square_view(np.concatenate(xs), np.concatenate(ys), VIEW_PAD,
                       DOMAIN_LENGTHS[0] * max(size.values()),
                       None if grid is None else grid.bounds)
    rows = []
    looks = ship_styles(trace.ships)
    columns = min(len(times), 3)
    panel_rows = -(-len(times) // columns)
    side = (PRINT_WIDTH_IN - 0.6) / columns
    with figure(PRINT_WIDTH_IN, panel_rows * (side + 0.25) + 0.9, "compressed") as fig:
        axes = fig.subplots(panel_rows, columns, squeeze=False).ravel()
        for ax in axes[len(times):]:
            ax.set_visible(False)
        for n, (ax, (state, i)) in enumerate(zip(axes, steps.items(), strict=False)):
            if grid is not None:
                draw_grid(ax, grid, view)
            for j, ship in enumerate(trace.ships):
                colour = looks[ship].color
                x, y, h = trace.x[: i + 1, j], trace.y[: i + 1, j], trace.heading[i, j]
                ax.plot(x, y, color=colour, linewidth=1.2, label=looks[ship].label, zorder=2)
                start = START if ship == OWN else {**TARGET_START, "markeredgecolor": colour}
                ax.plot(x[0], y[0], **start,
                        label=f"start of the {looks[ship].label}" if ship == OWN else None,
                        zorder=2.2)
                draw_ship(ax, x[-1], y[-1], h, size[ship], colour,
                          max(size[ship], HULL_MIN * (view[2] - view[0])))
                rows.append((state, *fixed([trace.t[i]], 3), ship,
                             *fixed([x[-1], y[-1], wrap360(h)], 3),
                             *fixed(np.array(DOMAIN_LENGTHS) * size[ship], 3)))  # fmt: skip
            if goal is not None:
                ax.plot(*goal, label="goal", **GOAL, zorder=5)
            ax.set_xlim(view[0], view[2])
            ax.set_ylim(view[1], view[3])
            map_axes(ax, view[2] - view[0], None if grid is None else grid.crs)
            ax.set_title(f"({chr(ord('a') + n)}) {state}, t = {trace.t[i]:.1f} s")
            ax.tick_params(axis="x", labelrotation=30)
        handles, labels = axes[0].get_legend_handles_labels()
        if len(trace.ships) > 1:
            handles.append(_target_start_handle())
            labels.append("start of the targets")
        fig.legend(handles, labels, loc="outside lower center", ncols=min(len(labels), 4))
        if title:
            fig.suptitle(title)
        image = png(fig)
    header = ("state", "t", "ship", "x", "y", "heading", "domain_length_m", "domain_width_m")
    return Plot(image, csv_text(header, rows))


def draw_ship(ax, x: float, y: float, heading: float, length: float, colour: str,
              hull_length: float) -> None:
    """The ship at (x, y) heading ``heading`` (compass degrees): her domain ellipse
    (:data:`DOMAIN_LENGTHS` x ``length``, tinted, its edge dashed) and a hull pointing along the
    heading, ``hull_length`` long, both in ``colour``."""
    from matplotlib.patches import Ellipse, Polygon

    angle = float(compass_to_math(heading))  # radians counter-clockwise from east
    major, minor = DOMAIN_LENGTHS[0] * length, DOMAIN_LENGTHS[1] * length
    for fill, z in ((True, 2.5), (False, 4)):
        ax.add_patch(Ellipse((x, y), major, minor, angle=float(np.degrees(angle)), fill=fill,
                             facecolor=colour, edgecolor=colour, alpha=0.25 if fill else 1.0,
                             linestyle="--", linewidth=0 if fill else 1.0, zorder=z))
    c, s = np.cos(angle), np.sin(angle)
    hull = HULL * (hull_length / 2) @ np.array([[c, s], [-s, c]]) + (x, y)
    ax.add_patch(Polygon(hull, closed=True, facecolor=colour, edgecolor="black", linewidth=0.5,
                         zorder=3))


def _target_start_handle():
    from matplotlib.lines import Line2D

    return Line2D([], [], markeredgecolor="0.3", **TARGET_START)


def _step(trace: Trace, state: str, at) -> int:
    """Index of the last step at or before ``at`` (refused outside the trace)."""
    try:
        at = float(at)
    except (TypeError, ValueError):
        raise UsvError(f"encounter_snapshots: time of {state!r} is not a number: {at!r}") from None
    t = trace.t
    if not t[0] - TIME_TOL <= at <= t[-1] + TIME_TOL:
        raise UsvError(f"encounter_snapshots: time of {state!r}, {at:g} s, is outside the trace "
                       f"({t[0]:g} to {t[-1]:g} s)")  # fmt: skip
    return max(0, int(np.searchsorted(t, at + TIME_TOL, side="right")) - 1)
