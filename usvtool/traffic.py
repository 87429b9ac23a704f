"""Real traffic: the encounters file of ``usvtool ais encounters``, an encounter's window of
recorded tracks as a scenario, and what the real vessel did in it. The contract between the AIS
stage (:mod:`usvtool.ais`: it writes the encounters file, and ``ais scenario`` writes a
scenario), the simulation's ``ais`` scene family (a pipeline's runs over an encounters file and
its tracks: docs/families.md) and the report's traffic section, which read the same files
(docs/ais.md). It imports no stage.

**Local frame.** Positions are compared in a local east/north frame on the mean Earth sphere:
``x = R cos φ Δλ``, ``y = R Δφ`` (R = :data:`EARTH_RADIUS`); a track's velocity is that of its
segment (from one fix to the next); a vessel slower than :data:`STILL` keeps her reported
heading (else her COG, else 0) as her course.

**The encounters CSV** (:data:`COLUMNS`, one row per encounter, ranked by ``cpa_m``): written
by :func:`encounters_csv`, read by :func:`read_encounters`. An encounter is picked as a scene
of a kind (:data:`KINDS`, :func:`pick_encounter`): ``any``, scene n the encounter of rank n;
``under-way``, scene n the n-th closest encounter whose two vessels both make ``min_speed``
kn at first detection.

**The scenario** (:func:`traffic_scenario`, docs/scenario.md): the own ship is one vessel's
track (the USV under test, a vessel preset, takes her place): she starts at her position at the
window's start, on her course over ground and at her speed over ground there (m/s), bound for
her position at the window's end; her recorded track is the scenario's ``route`` (a path
GeoJSON; gdwa follows it). The window is cut to her track. Every other track that comes within
``radius`` metres of her recorded track during the window (both interpolated every
:data:`SAMPLE` seconds) is a target replaying its track (a track CSV of its fixes in the
window, with its positions at the window's ends interpolated; ``t`` from the window's start),
with its length (:data:`DEFAULT_LENGTH` when it has none: counted in the figures). On a map (a
grid GeoTIFF with a CRS) every point is ``{lon, lat}`` and every track ``t,lon,lat``, and the
own ship's start and goal must be navigable cells of it; without one the scenario is in a local
metre frame: the WGS84 / UTM zone of the own ship's track, less an origin (her start, to the
metre), stated in its comments and figures.

**The recorded manoeuvre** (:func:`manoeuvre`): the own vessel's course and speed over ground
at an encounter's start and end, her net course change, her largest turn from the first course
and her slowest and fastest speed over the segments in the window.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from dataclasses import dataclass

import numpy as np

from usvtool.angles import wrap180, wrap360
from usvtool.errors import UsvError, check_input_file
from usvtool.tracks import NS, Tracks, format_time, spreadsheet_safe, spreadsheet_text

EARTH_RADIUS = 6_371_008.8  # m, IUGG mean radius
KNOT = 1852.0 / 3600.0  # m/s
#: Below this speed (m/s) a vessel's course is her reported heading (else COG, else 0).
STILL = 0.05
#: Seconds between the samples that test a scenario's radius.
SAMPLE = 5.0
#: A target's length (m) when her AIS static data give none.
DEFAULT_LENGTH = 20.0
#: The own ship's recorded track, in a scenario's files.
ROUTE = "route.geojson"

COLUMNS = ("rank", "mmsi_a", "mmsi_b", "track_a", "track_b", "name_a", "name_b", "length_a",
           "length_b", "start", "end", "cpa_time", "cpa_m", "tcpa_s", "range_m", "class_a",
           "class_b", "sog_a", "sog_b", "cog_a", "cog_b", "lon", "lat", "censored")  # fmt: skip
#: The encounters CSV's real columns and their decimals.
DECIMALS = {"length_a": 1, "length_b": 1, "cpa_m": 1, "tcpa_s": 1, "range_m": 1, "sog_a": 2,
            "sog_b": 2, "cog_a": 1, "cog_b": 1, "lon": 6, "lat": 6}  # fmt: skip
_INTEGERS = ("rank", "mmsi_a", "mmsi_b", "track_a", "track_b")
_NAMES = ("name_a", "name_b")
#: How an encounter is picked as a scene (:func:`pick_encounter`).
KINDS = ("any", "under-way")


# --- the encounters CSV ----------------------------------------------------------------------


def _text(column: str, value) -> str:
    if column in DECIMALS:
        if value is None or (isinstance(value, float) and math.isnan(value)):
            return ""
        text = f"{value:.{DECIMALS[column]}f}"
        return text[1:] if text.startswith("-") and float(text) == 0 else text
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def encounters_csv(rows: list[dict]) -> str:
    """The encounters CSV of ``rows`` (dicts of :data:`COLUMNS`); the vessels' names
    spreadsheet-safe (:func:`usvtool.tracks.spreadsheet_safe`; :func:`read_encounters` gives
    them back as they were)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(COLUMNS)
    names = {c: spreadsheet_safe([r[c] for r in rows]) for c in _NAMES} if rows else {}
    for i, r in enumerate(rows):
        writer.writerow([_text(c, names[c][i] if c in names else r[c]) for c in COLUMNS])
    return out.getvalue()


def read_encounters(path: str | os.PathLike) -> list[dict]:
    """The rows of an encounters CSV: numbers as floats (empty: NaN), MMSIs, tracks and ranks
    as ints, ``censored`` a bool; one line naming the line and column at fault."""
    check_input_file(path)
    with open(path, encoding="utf-8-sig", newline="") as f:  # a spreadsheet's BOM too
        reader = csv.reader(f)
        header = next(reader, [])
        if tuple(header) != COLUMNS:
            raise UsvError(f"{path}: line 1: the header must be {','.join(COLUMNS)!r} (usvtool "
                           "ais encounters)")  # fmt: skip
        rows = []
        for fields in reader:
            if len(fields) != len(COLUMNS):
                raise UsvError(f"{path}: line {reader.line_num}: {len(fields)} fields, expected "
                               f"{len(COLUMNS)}")  # fmt: skip
            row = dict(zip(COLUMNS, fields, strict=True))
            for c in COLUMNS:
                try:
                    if c in _INTEGERS:
                        row[c] = int(row[c])
                    elif c in DECIMALS:
                        row[c] = float(row[c]) if row[c] else math.nan
                    elif c == "censored":
                        row[c] = {"true": True, "false": False}[row[c]]
                except (ValueError, KeyError):
                    raise UsvError(f"{path}: line {reader.line_num}, column {c}: {row[c]!r} is "
                                   "not of its kind") from None  # fmt: skip
            rows.append(row)
    for c in _NAMES if rows else ():
        for row, name in zip(rows, spreadsheet_text([r[c] for r in rows]), strict=True):
            row[c] = name
    return rows


def under_way(row: dict, min_speed: float) -> bool:
    """Whether both vessels of an encounter make ``min_speed`` kn at first detection."""
    return row["sog_a"] >= min_speed and row["sog_b"] >= min_speed


def pick_encounter(rows: list[dict], kind: str, number: int, min_speed: float, path,
                   where: str) -> dict:  # fmt: skip
    """Encounter ``number`` of ``kind`` (:data:`KINDS`) of the rows of the encounters file
    ``path``; one line starting with ``where`` (``--encounter``) when there is none."""
    if kind == "any":
        row = next((r for r in rows if r["rank"] == number), None)
        if row is None:
            raise UsvError(f"{where} {number}: no such rank in {path} (1 … {len(rows)})")
        return row
    if kind != "under-way":
        raise UsvError(f"{where}: no kind {kind!r} of encounter (kinds: {', '.join(KINDS)})")
    moving = [r for r in rows if under_way(r, min_speed)]
    if not 1 <= number <= len(moving):
        raise UsvError(f"{where} {number}: {path} holds {len(moving)} encounters with both "
                       f"vessels making {min_speed:g} kn at first detection (1 … "
                       f"{len(moving)})")  # fmt: skip
    return moving[number - 1]


def _encounter_times(row: dict, path) -> tuple[int, int]:
    """The encounter's ``start`` and ``end`` (ns since the epoch)."""
    import pyarrow as pa

    from usvtool.csvtable import time_ns

    ends = time_ns(path, pa.array([row["start"], row["end"]]), "start", 1)
    return int(ends[0]), int(ends[1])


def _vessel_track(tracks: Tracks, row: dict, vessel: str, path) -> int:
    """The ordinal (in :meth:`Tracks.track_bounds`) of the track of the encounter's ``vessel``
    (``"a"`` or ``"b"``); one line when the tracks file does not hold it."""
    first, _ = tracks.track_bounds()
    mmsi, track = row[f"mmsi_{vessel}"], row[f"track_{vessel}"]
    ordinal = np.flatnonzero(tracks.track[first] == track)
    if ordinal.size == 0 or tracks.mmsi[first[ordinal[0]]] != mmsi:
        raise UsvError(f"{path}: encounter {row['rank']}: track {track} of {mmsi} is not in the "
                       "tracks file (made from other tracks?)")  # fmt: skip
    return int(ordinal[0])


@dataclass(frozen=True)
class SceneEncounter:
    """An encounter as a scene: its row, the own vessel's track (an ordinal of
    :meth:`Tracks.track_bounds`), the other vessel's MMSI, the encounter's start and end and
    the scenario's window (ns): those widened by the pad on each side, cut to the own track."""

    row: dict
    own: int
    other: int
    times: tuple[int, int]
    window: tuple[int, int]


def scene_encounter(tracks: Tracks, row: dict, own: str, pad: float, path) -> SceneEncounter:
    """The encounter ``row`` of the encounters file ``path`` with its vessel ``own`` (``"a"``
    or ``"b"``) as the own ship, the window ``pad`` s wider on each side."""
    ordinal = _vessel_track(tracks, row, own, path)
    t0, t1 = _encounter_times(row, path)
    widen = round(pad * NS)
    window = cut_window(tracks, ordinal, (t0 - widen, t1 + widen))
    return SceneEncounter(row, ordinal, row["mmsi_b" if own == "a" else "mmsi_a"], (t0, t1),
                          window)  # fmt: skip


def cut_window(tracks: Tracks, own: int, window: tuple[int, int]) -> tuple[int, int]:
    """``window`` (ns) cut to the track ``own``; one line when they do not overlap."""
    first, stop = tracks.track_bounds()
    t0 = max(window[0], int(tracks.time[first[own]]))
    t1 = min(window[1], int(tracks.time[stop[own] - 1]))
    if t1 <= t0:
        raise UsvError(f"MMSI {tracks.mmsi[first[own]]}: her track {tracks.track[first[own]]} "
                       f"holds no time of the window {' … '.join(format_time(list(window)))}")
    return t0, t1


# --- tracks in the local frame ---------------------------------------------------------------


def times_in(fix_times: np.ndarray, t0: int, t1: int) -> np.ndarray:
    """The window's ends and the fix times strictly inside it."""
    inner = fix_times[(fix_times > t0) & (fix_times < t1)]
    return np.r_[t0, inner, t1].astype(np.int64)


def positions_at(tracks: Tracks, rows: slice, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lon/lat of a track at ``times`` (within its span), interpolated linearly (lon across
    the antimeridian unwrapped)."""
    t = tracks.time[rows]
    lon = tracks.lon[rows]
    unwrapped = lon[0] + np.r_[0.0, np.cumsum(wrap180(np.diff(lon)))]
    x = (times - t[0]) / NS
    tx = (t - t[0]) / NS
    return wrap180(np.interp(x, tx, unwrapped)), np.interp(x, tx, tracks.lat[rows])


def distance(lon1, lat1, lon2, lat2) -> np.ndarray:
    """Distances (m) in the local east/north frame."""
    scale = EARTH_RADIUS * np.radians(1.0)
    mid = np.radians(0.5 * (np.asarray(lat1) + np.asarray(lat2)))
    return np.hypot(scale * np.cos(mid) * wrap180(np.asarray(lon2) - lon1),
                    scale * (np.asarray(lat2) - lat1))  # fmt: skip


def _segments(tracks: Tracks, rows: slice, j: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Course (compass deg) and speed (m/s) over ground of a track's segments ``j`` (from fix
    ``j`` to ``j + 1``); a segment slower than :data:`STILL` has the reported heading (else
    COG, else 0) as its course."""
    t, lon, lat = tracks.time[rows], tracks.lon[rows], tracks.lat[rows]
    scale = EARTH_RADIUS * np.radians(1.0)
    dt = (t[j + 1] - t[j]) / NS
    ve = scale * np.cos(np.radians(lat[j])) * wrap180(lon[j + 1] - lon[j]) / dt
    vn = scale * (lat[j + 1] - lat[j]) / dt
    speed = np.hypot(ve, vn)
    heading, cog = tracks.heading[rows][j], tracks.cog[rows][j]
    reported = np.nan_to_num(np.where(np.isnan(heading), cog, heading))
    course = np.where(speed < STILL, reported, wrap360(np.degrees(np.arctan2(ve, vn))))
    return course, speed


def _segment(t: np.ndarray, time: int, side: str) -> int:
    """The segment holding ``time``: the one starting at or before it (``side="right"``) or
    the one ending at or after it (``"left"``), within the track's segments."""
    return int(np.clip(np.searchsorted(t, time, side=side) - 1, 0, t.size - 2))


def course_speed(tracks: Tracks, rows: slice, time: int,
                 side: str = "right") -> tuple[float, float]:  # fmt: skip
    """Course over ground (compass deg) and speed (m/s) of the track's segment at ``time``."""
    j = np.array([_segment(tracks.time[rows], time, side)])
    course, speed = _segments(tracks, rows, j)
    return float(course[0]), float(speed[0])


@dataclass(frozen=True)
class Manoeuvre:
    """What a vessel did over a window: course over ground (compass deg) at its start and end,
    the net change (``end - start`` in (-180, 180]: > 0 to starboard), the largest turn from
    the first course (signed), and speed over ground (kn) at the start and end, slowest and
    fastest, over the segments of her track in the window."""

    course_start: float
    course_end: float
    course_change: float
    largest_turn: float
    speed_start: float
    speed_end: float
    speed_min: float
    speed_max: float


def summarise(course: np.ndarray, speed: np.ndarray, start: tuple[float, float],
              end: tuple[float, float]) -> Manoeuvre:  # fmt: skip
    """The :class:`Manoeuvre` of course (compass deg) and speed (m/s) samples over a window,
    ``start`` and ``end`` its (course, speed) at its ends; the largest turn over the samples
    of at least :data:`STILL`."""
    course, speed = np.asarray(course, float), np.asarray(speed, float)
    turns = wrap180(course[speed >= STILL] - start[0])
    largest = float(turns[np.argmax(np.abs(turns))]) if turns.size else 0.0
    return Manoeuvre(float(start[0]), float(end[0]), float(wrap180(end[0] - start[0])), largest,
                     start[1] / KNOT, end[1] / KNOT, float(speed.min()) / KNOT,
                     float(speed.max()) / KNOT)  # fmt: skip


def manoeuvre(tracks: Tracks, ordinal: int, t0: int, t1: int) -> Manoeuvre:
    """The manoeuvre of track ``ordinal`` over ``t0`` … ``t1`` (ns; within her track): her
    segments there, her course and speed at ``t0`` (the segment from it) and at ``t1`` (the
    segment to it)."""
    first, stop = tracks.track_bounds()
    rows = slice(first[ordinal], stop[ordinal])
    t = tracks.time[rows]
    j = np.arange(_segment(t, t0, "right"), _segment(t, t1, "left") + 1)
    course, speed = _segments(tracks, rows, j)
    return summarise(course, speed, course_speed(tracks, rows, t0, "right"),
                     course_speed(tracks, rows, t1, "left"))  # fmt: skip


# --- the scenario ----------------------------------------------------------------------------


@dataclass
class TrafficScenario:
    """A scenario mapping (docs/scenario.md; its targets' ``track`` and its ``route`` name the
    files of ``files``), the texts of those files (name: text), its figures and the comments
    that head its YAML (:func:`scenario_yaml`)."""

    scenario: dict
    files: dict[str, str]
    figures: dict
    comments: list[str]


def traffic_scenario(tracks: Tracks, own: int, window: tuple[int, int], *, radius: float,
                     vessel: str, controller: str, duration: float | None = None,
                     map_path: str | os.PathLike | None = None,
                     directory: str | os.PathLike = ".", what: str = "a window",
                     ) -> TrafficScenario:  # fmt: skip
    """The scenario of track ``own`` (an ordinal of :meth:`Tracks.track_bounds`) over
    ``window`` (ns, cut to her track) with the targets within ``radius`` m (module docstring);
    ``duration`` s (None: twice the window); on the grid ``map_path`` (named relative to the
    scenario's ``directory``) or in the local UTM frame; ``what`` the window is, for the
    comments."""
    first, stop = tracks.track_bounds()
    mmsi = int(tracks.mmsi[first[own]])
    t0, t1 = cut_window(tracks, own, window)
    own_rows = slice(first[own], stop[own])
    own_lon, own_lat = positions_at(tracks, own_rows, times_in(tracks.time[own_rows], t0, t1))
    frame = _Frame(tracks.lon[first[own]], tracks.lat[first[own]], own_lon[0], own_lat[0],
                   map_path)  # fmt: skip
    grid_t = np.arange(t0, t1 + 1, round(SAMPLE * NS), dtype=np.int64)
    own_glon, own_glat = positions_at(tracks, own_rows, grid_t)
    targets, files, assumed = [], {}, 0
    names: set[str] = set()
    for i in range(first.size):
        rows = slice(first[i], stop[i])
        if tracks.mmsi[first[i]] == mmsi:
            continue
        lo, hi = max(t0, tracks.time[first[i]]), min(t1, tracks.time[stop[i] - 1])
        if hi <= lo:
            continue
        inside = (grid_t >= lo) & (grid_t <= hi)
        if not inside.any():
            continue
        lon, lat = positions_at(tracks, rows, grid_t[inside])
        if distance(own_glon[inside], own_glat[inside], lon, lat).min() > radius:
            continue
        times = times_in(tracks.time[rows], lo, hi)
        lon, lat = positions_at(tracks, rows, times)
        name = f"ais-{tracks.mmsi[first[i]]}"
        name = name if name not in names else f"{name}-{tracks.track[first[i]]}"
        names.add(name)
        length = float(tracks.length[first[i]])
        if not length > 0:
            length, assumed = DEFAULT_LENGTH, assumed + 1
        files[f"{name}.csv"] = frame.track_csv((times - t0) / NS, lon, lat)
        targets.append({"name": name, "track": f"{name}.csv", "speed": 0,
                        "length": round(length, 2)})  # fmt: skip
    course, speed = course_speed(tracks, own_rows, t0)
    duration = duration if duration is not None else 2 * (t1 - t0) / NS
    stamp = format_time([t0])[0].replace("-", "").replace(":", "").rstrip("Z")
    scenario = {
        "name": f"ais-{mmsi}-{stamp}",
        **({"map": os.path.relpath(os.path.abspath(map_path), os.path.abspath(directory))}
           if map_path else {}),
        "route": ROUTE,
        "sim": {"dt": 0.1, "duration": round(duration, 1)},
        "own": {"start": frame.point(own_lon[0], own_lat[0]),
                "goal": frame.point(own_lon[-1], own_lat[-1]),
                "heading": round(course, 1), "speed": round(speed, 3), "vessel": vessel},
        "targets": targets,
        "controller": {"name": controller},
    }  # fmt: skip
    figures = {
        "scenario": scenario["name"], "own": mmsi, "own_name": tracks.name[first[own]],
        "own_track": int(tracks.track[first[own]]), "window": format_time([t0, t1]),
        "targets": len(targets), "target_mmsis": [int(t["name"].split("-")[1]) for t in targets],
        "lengths_assumed": assumed, "frame": frame.describe(),
        "own_recorded_length_m": round(float(distance(own_lon[:-1], own_lat[:-1], own_lon[1:],
                                                      own_lat[1:]).sum()), 1),
    }  # fmt: skip
    files[ROUTE] = frame.route(own_lon, own_lat, mmsi)
    comments = [
        f"Real traffic: {what}, {figures['window'][0]} … {figures['window'][1]}.",
        f"Own ship: MMSI {mmsi} {figures['own_name'] or ''}".rstrip() + "'s start, goal and "
        "recorded track (the route); the USV under test in her place.",
        f"Targets: the {len(targets)} other tracks within {radius:g} m, replayed.",
        f"Frame: {figures['frame']}.",
    ]  # fmt: skip
    return TrafficScenario(scenario, files, figures, comments)


def scenario_yaml(data: dict, comments: list[str]) -> str:
    """A scenario mapping's YAML headed by ``comments`` (``# `` lines, each one line whatever
    text from an input it holds: :func:`usvtool.yamlfile.comment`)."""
    import yaml

    from usvtool.yamlfile import comment

    body = yaml.safe_dump(data, sort_keys=False, default_flow_style=None, width=100,
                          allow_unicode=True)  # fmt: skip
    return "".join(f"{comment(c)}\n" for c in comments) + body


class _Frame:
    """Lon/lat on a map with a CRS, else the local UTM metre frame (module docstring)."""

    def __init__(self, lon0: float, lat0: float, start_lon: float, start_lat: float, map_path):
        from usvtool.geodesy import lonlat_to_map, utm_crs

        self.grid = None
        if map_path is not None:
            from usvtool.grid import read_grid

            self.grid = read_grid(map_path)
            if self.grid.crs is None:
                raise UsvError(f"--map {map_path}: the grid has no CRS; AIS positions need one "
                               "(or give no map: a local UTM frame)")  # fmt: skip
            self.crs = self.grid.crs
            self.origin = (0.0, 0.0)
        else:
            self.crs = utm_crs(float(lon0), float(lat0))
            e, n = lonlat_to_map(self.crs, float(start_lon), float(start_lat))
            self.origin = (float(round(e)), float(round(n)))

    def xy(self, lon, lat) -> np.ndarray:
        from usvtool.geodesy import lonlat_to_map

        x, y = lonlat_to_map(self.crs, np.asarray(lon, float), np.asarray(lat, float))
        return np.column_stack([np.atleast_1d(x) - self.origin[0],
                                np.atleast_1d(y) - self.origin[1]])  # fmt: skip

    def point(self, lon: float, lat: float, where: str = "own") -> object:
        if self.grid is not None:
            from usvtool.collision import check_point

            check_point(self.grid, tuple(self.xy(lon, lat)[0]), f"--map: {where} ({lon:.6f}, "
                        f"{lat:.6f})")  # fmt: skip
            return {"lon": round(float(lon), 7), "lat": round(float(lat), 7)}
        x, y = self.xy(lon, lat)[0]
        return [round(float(x), 2), round(float(y), 2)]

    def track_csv(self, t: np.ndarray, lon: np.ndarray, lat: np.ndarray) -> str:
        """A track CSV (docs/scenario.md); fixes less than a millisecond apart (its ``t``'s
        resolution) as one."""
        keep = np.r_[True, np.diff(np.round(t, 3)) > 0]
        t, lon, lat = t[keep], lon[keep], lat[keep]
        if self.grid is not None:
            rows = [f"{a:.3f},{b:.7f},{c:.7f}" for a, b, c in zip(t, lon, lat, strict=True)]
            return "t,lon,lat\n" + "\n".join(rows) + "\n"
        xy = self.xy(lon, lat)
        rows = [f"{a:.3f},{b:.2f},{c:.2f}" for a, (b, c) in zip(t, xy, strict=True)]
        return "t,x,y\n" + "\n".join(rows) + "\n"

    def route(self, lon: np.ndarray, lat: np.ndarray, mmsi: int) -> str:
        """The own ship's recorded track as a path GeoJSON (usvtool/route.py's layout)."""
        xy = np.round(self.xy(lon, lat), 3)
        props: dict = {"algorithm": "ais", "source": f"the recorded track of MMSI {mmsi}"}
        if self.grid is not None:
            coords = np.column_stack([lon, lat]).round(7).tolist()
            props |= {"crs": self.crs.to_string(), "map_coordinates": xy.tolist()}
        else:
            coords = xy.tolist()
            props["frame"] = self.describe()
        feature = {"type": "Feature", "geometry": {"type": "LineString", "coordinates": coords},
                   "properties": props}  # fmt: skip
        return json.dumps({"type": "FeatureCollection", "features": [feature]}, indent=1) + "\n"

    def describe(self) -> str:
        if self.grid is not None:
            return f"lon/lat on the map's CRS {self.crs.to_string()}"
        return (f"local metres: x = E - {self.origin[0]:.0f}, y = N - {self.origin[1]:.0f} in "
                f"{self.crs.to_string()} (WGS 84 / UTM), the origin the own ship's start")
