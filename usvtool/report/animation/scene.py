"""The scene an animation draws, read from a run's trace CSV, its events JSON and its map.

Everything the frames and the player show is here, computed once over the whole trace with
NumPy (no loop over steps): the ships' lengths (the events' ``run.ships``), the own ship's
domain (:func:`usvtool.encounter.domain_semi_axes` of her length), the route and goal, the map
(a navigation grid GeoTIFF; the chart's preview PNG beside it when there is one), each target's
COLREGs class at every step (:func:`usvtool.encounter.assess`, replaced by the latched class of
the events' encounters from onset to release), the verdict events for the timeline (onset, first
manoeuvre, release, Rule 2 departure, collision) and the distance to the nearest ship.

Input faults are one :class:`~usvtool.errors.UsvError` line naming the file (and the field).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from usvtool import encounter
from usvtool.errors import UsvError
from usvtool.grid import Grid
from usvtool.measures import target_distances
from usvtool.trace import Trace, read_events, read_trace

#: Where the events JSON of ``TRACE.csv`` is looked for, in this order: ``usvtool batch``'s and
#: ``usvtool simulate --events TRACE.events.json``'s name, then ``usvtool metrics``' other one.
EVENTS_SUFFIXES = (".events.json", ".json")
#: The kinds of verdict events on the timeline, in drawing order.
MARK_KINDS = ("onset", "manoeuvre", "release", "rule2", "collision")
#: Rule 2 departure records of one target closer than this many steps apart are one interval.
RULE2_GAP_STEPS = 2.5
#: The view is the box around the tracks, the route and the goal, padded by this fraction of
#: its larger side (and at least the own ship's domain).
VIEW_PAD = 0.05
#: Outside an encounter a target's class is shown while her CPA is ahead within this many
#: seconds (the events' ``thresholds.horizon_s``, the tracker's onset horizon, when given).
HORIZON_S = 120.0


@dataclass(frozen=True)
class Mark:
    """A verdict event: ``kind`` one of :data:`MARK_KINDS`, from ``t`` to ``end`` (s; ``end`` =
    ``t`` but for a Rule 2 departure's interval), ``ship`` the target's column in the trace
    (0 for none), ``text`` what the timeline says of it."""

    t: float
    end: float
    kind: str
    ship: int
    text: str


@dataclass(frozen=True)
class Scene:
    """A run ready to draw (module docstring). Arrays are per step ``(n,)`` or per step and ship
    ``(n, k)``, ship 0 the own ship."""

    trace: Trace
    lengths: np.ndarray  # (k,) metres
    title: str
    domain: tuple[float, float]  # the own ship's domain semi-axes (along, across), metres
    goal: tuple[float, float] | None
    goal_tolerance: float
    route: np.ndarray | None  # (m, 2) map metres
    grid: Grid | None
    chart: object | None  # usvtool.report.figures.raster.ChartImage: the map's preview
    classes: np.ndarray  # (n, k) int8 class codes (encounter.CLASS_NAMES); own column 0
    latched: np.ndarray  # (n, k) bool: inside an encounter of the events
    nearest: np.ndarray | None  # (n,) distance to the nearest ship (None: no target)
    marks: tuple[Mark, ...]
    view: tuple[float, float, float, float]  # left, bottom, right, top

    @property
    def ships(self) -> tuple[str, ...]:
        return self.trace.ships

    @property
    def duration(self) -> float:
        return float(self.trace.t[-1] - self.trace.t[0])


def events_path_for(trace_path: str | os.PathLike) -> Path:
    """The events JSON beside ``trace_path`` (:data:`EVENTS_SUFFIXES`); a :class:`UsvError`
    naming the trace and the names looked for when there is none."""
    p = Path(trace_path)
    candidates = [p.with_name(p.stem + s) for s in EVENTS_SUFFIXES]
    for c in candidates:
        if c.is_file():
            return c
    names = " or ".join(c.name for c in candidates)
    raise UsvError(f"{trace_path}: no events JSON beside it ({names}); give --events "
                   "(usvtool simulate --events writes it)")  # fmt: skip


def load_scene(trace_path, events_path=None, map_path=None) -> Scene:
    """The scene of the run ``trace_path`` (its events JSON ``events_path``, default beside it:
    :func:`events_path_for`) over ``map_path`` (default the run's ``map``, if any)."""
    trace = read_trace(trace_path)
    events_path = Path(events_path) if events_path is not None else events_path_for(trace_path)
    events = read_events(events_path)
    return scene_of(trace, events, events_path, map_path)


def scene_of(trace: Trace, events: dict, events_path, map_path=None) -> Scene:
    """:func:`load_scene` for a trace and events already read (``events_path`` names the events
    in errors and resolves their relative paths)."""
    where = str(events_path)
    run = events.get("run")
    if not isinstance(run, dict):
        raise UsvError(f"{where}: no 'run' object (not the events JSON of usvtool simulate, or "
                       "written before it had one: simulate the run again)")  # fmt: skip
    base = Path(events_path).resolve().parent
    lengths = _lengths(trace, run, where)
    title = " / ".join(str(run[k]) for k in ("scenario", "controller") if run.get(k))
    goal = _pair(run.get("goal"), f"{where}: run.goal")
    tolerance = _number(run.get("goal_tolerance", 0.0) or 0.0, f"{where}: run.goal_tolerance")
    route = None
    if run.get("route"):
        from usvtool.route import read_path_geojson

        route = read_path_geojson(_resolve(run["route"], base, f"{where}: run.route"))[0]
        if route.ndim != 2 or route.shape[1] != 2 or not np.isfinite(route).all():
            raise UsvError(f"{where}: run.route {run['route']}: not a route of (x, y) points")
    grid, chart = _map(trace, run, base, where, map_path)
    classes, latched, marks = _encounters(trace, events, where)
    nearest = None
    if len(trace.ships) > 1:
        nearest = target_distances(trace.x[:, 0], trace.y[:, 0], trace.x[:, 1:],
                                   trace.y[:, 1:]).min(axis=1)  # fmt: skip
    a, b = encounter.domain_semi_axes(float(lengths[0]))
    return Scene(trace, lengths, title, (float(a), float(b)), goal, tolerance, route, grid,
                 chart, classes, latched, nearest, marks,
                 _view(trace, route, goal, a, grid))  # fmt: skip


def _lengths(trace: Trace, run: dict, where: str) -> np.ndarray:
    ships = run.get("ships")
    try:
        names = [str(s["name"]) for s in ships]
        lengths = {str(s["name"]): float(s["length"]) for s in ships}
    except (KeyError, TypeError, ValueError):
        raise UsvError(f"{where}: run.ships must list each ship's name and length") from None
    if tuple(names) != trace.ships:
        raise UsvError(f"{where}: run.ships ({', '.join(names)}) are not the trace's ships "
                       f"({', '.join(trace.ships)}): not this trace's events")  # fmt: skip
    out = np.array([lengths[s] for s in trace.ships], float)
    if not (np.isfinite(out) & (out > 0)).all():
        raise UsvError(f"{where}: run.ships: every length must be a number > 0")
    return out


def _number(value, where: str) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise UsvError(f"{where} must be a number, not {value!r}") from None
    if not np.isfinite(x):
        raise UsvError(f"{where} must be finite")
    return x


def _pair(value, where: str) -> tuple[float, float] | None:
    if value is None:
        return None
    if not isinstance(value, list | tuple) or len(value) != 2:
        raise UsvError(f"{where} must be [x, y]")
    return _number(value[0], where), _number(value[1], where)


def _resolve(path, base: Path, where: str) -> Path:
    if not isinstance(path, str):
        raise UsvError(f"{where} must be a path, not {path!r}")
    p = Path(path)
    p = p if p.is_absolute() else base / p
    if not p.is_file():
        raise UsvError(f"{where} {path}: no such file")
    return p


def _map(trace: Trace, run: dict, base: Path, where: str, map_path):
    """The grid to draw and its preview (None, None without a map). A map given in another CRS
    than the run's, or that the trace does not lie on, is refused."""
    from usvtool.grid import read_grid

    run_map = _resolve(run["map"], base, f"{where}: run.map") if run.get("map") else None
    path = Path(map_path) if map_path is not None else run_map
    if path is None:
        return None, None
    label = f"--map {path}" if map_path is not None else f"{where}: run.map {path}"
    try:
        grid = read_grid(path)
    except UsvError as exc:
        raise UsvError(f"{label}: {exc}" if map_path is None else str(exc)) from None
    if map_path is not None and run_map is not None and Path(map_path).resolve() != run_map:
        import rasterio

        with rasterio.open(run_map) as ds:
            crs = ds.crs
        if (crs is None) != (grid.crs is None) or (crs is not None and crs != grid.crs):
            raise UsvError(f"{label}: its CRS ({_crs_name(grid.crs)}) is not the trace's, the "
                           f"run's map {run_map.name} ({_crs_name(crs)})")  # fmt: skip
    left, bottom, right, top = grid.bounds
    x, y = float(trace.x[0, 0]), float(trace.y[0, 0])
    if not (left <= x <= right and bottom <= y <= top):
        raise UsvError(f"{label}: the own ship starts at ({x:.0f}, {y:.0f}) m, outside the map "
                       f"(x {left:.0f}..{right:.0f}, y {bottom:.0f}..{top:.0f}): not the "
                       "trace's map or frame")  # fmt: skip
    for candidate in (path.with_name(path.stem + ".preview.png"), path.with_name("preview.png")):
        if candidate.is_file():  # the report's figures (and their imports) only then
            from usvtool.report.figures.raster import preview_chart

            chart = preview_chart(candidate, grid)
            if chart is not None:
                return grid, chart
    return grid, None


def _crs_name(crs) -> str:
    if crs is None:
        return "none: a local frame"
    epsg = crs.to_epsg()
    return f"EPSG:{epsg}" if epsg else crs.to_string()[:60]


def _encounters(trace: Trace, events: dict, where: str):
    """The class of every target at every step, whether it is latched, and the marks."""
    n, k = trace.x.shape
    classes = np.zeros((n, k), np.int8)
    latched = np.zeros((n, k), bool)
    if k > 1:
        s = encounter.assess(np.stack([trace.x[:, :1], trace.y[:, :1]], -1), trace.heading[:, :1],
                             trace.speed[:, :1], np.stack([trace.x[:, 1:], trace.y[:, 1:]], -1),
                             trace.heading[:, 1:], trace.speed[:, 1:])  # fmt: skip
        horizon = _number((events.get("thresholds") or {}).get("horizon_s", HORIZON_S),
                          f"{where}: thresholds.horizon_s")  # fmt: skip
        classes[:, 1:] = np.where((s.tcpa > 0) & (s.tcpa < horizon), s.cls, 0)
    t = trace.t
    marks: list[Mark] = []
    names = trace.ships
    try:
        for e in events.get("encounters") or []:
            cls = e["class"]
            if cls == "none":
                continue
            j = int(e["target"]) + 1
            if not 1 <= j < k:
                raise ValueError(f"target {e['target']} is not a target of the trace")
            code = encounter.CLASS_NAMES.index(cls)
            onset = float(e["onset_s"])
            released = None if e.get("released_s") is None else float(e["released_s"])
            steps = (t >= onset - 5e-4) & (t < (np.inf if released is None else released - 5e-4))
            classes[steps, j] = code
            latched[steps, j] = True
            marks.append(Mark(onset, onset, "onset", j, f"{names[j]}: {cls} encounter onset"))
            m = e.get("first_manoeuvre")
            if m:
                mt = float(m["t"])
                turn = (f"to {m['side']}" if m.get("side") else "of speed") + (
                    f", {float(m['course_change_deg']):+.0f} deg"
                    if m.get("course_change_deg") is not None else "")  # fmt: skip
                marks.append(Mark(mt, mt, "manoeuvre", j,
                                  f"own ship's first manoeuvre for {names[j]}: {turn}"))
            if released is not None:
                verdict = {True: "compliant", False: "not compliant", None: "not judged"}
                text = f"{names[j]}: released, {verdict.get(e.get('compliant'), 'not judged')}"
                failed = e.get("failed_rules") or []
                if failed:
                    text += f" ({', '.join(map(str, failed))})"
                marks.append(Mark(released, released, "release", j, text))
        dt = float(np.median(np.diff(t))) if n > 1 else 0.1
        rule2: dict[int, list[float]] = {}
        for s in events.get("steps") or []:
            if s.get("kind") == "rule2-departure":
                rule2.setdefault(int(s.get("target", -1)) + 1, []).append(float(s["t"]))
            elif s.get("kind") == "collision":
                who = s.get("with")
                marks.append(Mark(float(s["t"]), float(s["t"]), "collision",
                                  names.index(who) if who in names else 0,
                                  f"collision with {who}"))  # fmt: skip
        for j, times in sorted(rule2.items()):
            times = np.sort(np.asarray(times))
            breaks = np.flatnonzero(np.diff(times) > RULE2_GAP_STEPS * dt)
            starts = np.r_[times[:1], times[breaks + 1]]
            ends = np.r_[times[breaks], times[-1:]]
            who = names[j] if 1 <= j < k else "a target"
            for a, b in zip(starts.tolist(), ends.tolist(), strict=True):
                marks.append(Mark(a, b, "rule2", j if 1 <= j < k else 0,
                                  f"{who}: Rule 2 departure"))  # fmt: skip
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise UsvError(f"{where}: an encounter or step record is malformed ({exc})") from None
    marks.sort(key=lambda m: (m.t, MARK_KINDS.index(m.kind), m.ship))
    return classes, latched, tuple(marks)


def _view(trace: Trace, route, goal, domain_a: float, grid: Grid | None):
    xs, ys = [trace.x.ravel()], [trace.y.ravel()]
    if route is not None:
        xs.append(route[:, 0])
        ys.append(route[:, 1])
    if goal is not None:
        xs.append(np.array([goal[0]]))
        ys.append(np.array([goal[1]]))
    x, y = np.concatenate(xs), np.concatenate(ys)
    left, right, bottom, top = x.min(), x.max(), y.min(), y.max()
    pad = max(VIEW_PAD * max(right - left, top - bottom), domain_a, 1.0)
    view = [left - pad, bottom - pad, right + pad, top + pad]
    if grid is not None:  # not beyond the map
        g = grid.bounds
        view = [max(view[0], g[0]), max(view[1], g[1]), min(view[2], g[2]), min(view[3], g[3])]
    return tuple(float(v) for v in view)

