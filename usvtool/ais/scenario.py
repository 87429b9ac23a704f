"""``usvtool ais scenario``: a window of real traffic as a scenario YAML that ``usvtool simulate``
runs with any controller (the format of docs/scenario.md, written here from that document: this
stage imports no other).

The own ship is the vessel ``--own`` (the USV under test takes her place, with its own
``--vessel`` preset): she starts at her position at the window's start, on her course over
ground and at her speed over ground there (from her track's segment, m/s), bound for her
position at the window's end, and her recorded track is the scenario's ``route`` (a path
GeoJSON; gdwa follows it). The window is ``--start`` … ``--end``, or an encounter's (``usvtool
ais encounters``: its start and end) widened by ``--pad`` seconds on each side; either way cut
to the own ship's track. Every other track that comes within ``--radius`` metres of the own
ship's recorded track during the window (both interpolated every :data:`SAMPLE` seconds) is a
target replaying its track (a track CSV of its fixes in the window, with its positions at the
window's ends interpolated; ``t`` from the window's start), with its length (or
:data:`DEFAULT_LENGTH` when it has none: counted in the summary).

Frame: on a ``--map`` (a grid GeoTIFF with a CRS) every point is ``{lon, lat}`` and every track
``t,lon,lat``, and the own ship's start and goal must be navigable cells of it; without a map,
the scenario is in a local metre frame: the WGS84 / UTM zone of the own ship's start, less an
origin (her start, to the metre), stated in the YAML's first lines and the summary.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from usvtool.ais.clean import EARTH_RADIUS
from usvtool.angles import wrap180, wrap360
from usvtool.errors import UsvError
from usvtool.tracks import NS, Tracks, format_time

#: Seconds between the samples that test the radius.
SAMPLE = 5.0
#: A target's length (m) when her AIS static data give none.
DEFAULT_LENGTH = 20.0
SCENARIO = "scenario.yaml"
ROUTE = "route.geojson"


@dataclass(frozen=True)
class ScenarioOptions:
    """``own`` MMSI; the window as ``start``/``end`` (ISO 8601 UTC) or ``encounter`` (a rank
    of the ``encounters`` CSV); ``radius`` m; ``map`` a grid GeoTIFF or None; ``vessel`` the
    USV's preset; ``controller``; ``pad`` s; ``duration`` s (None: twice the window)."""

    own: int | None = None
    start: str | None = None
    end: str | None = None
    encounter: int | None = None
    encounters: str | None = None
    radius: float = 2000.0
    map: str | None = None
    vessel: str = "udwa-usv"
    controller: str = "udwa"
    pad: float = 60.0
    duration: float | None = None

    def __post_init__(self):
        if (self.encounter is None) == (self.start is None and self.end is None):
            raise UsvError("ais scenario: give --start and --end, or --encounter (not both)")
        if self.encounter is None and (self.start is None or self.end is None or self.own is None):
            raise UsvError("ais scenario: --start and --end need each other and --own")
        if self.encounter is not None and self.encounters is None:
            raise UsvError("--encounter: name the encounters file with --encounters")
        for name in ("radius", "pad", "duration"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value >= 0):
                raise UsvError(f"--{name}: must be a number >= 0, not {value}")


@dataclass
class ScenarioResult:
    """The files' texts (name relative to the output directory: text) and the summary."""

    files: dict[str, str]
    figures: dict

    def summary(self) -> dict:
        return dict(self.figures)


def make_scenario(tracks: Tracks, options: ScenarioOptions,
                  directory: str | os.PathLike = ".") -> ScenarioResult:  # fmt: skip
    """The scenario files of ``options``' window of ``tracks`` (module docstring), to be written
    into ``directory`` (the map is named relative to it)."""
    own, window, encounter = _window(tracks, options)
    first, stop = tracks.track_bounds()
    t0, t1 = window
    own_rows = slice(first[own], stop[own])
    own_times = _times_in(tracks.time[own_rows], t0, t1)
    own_lon, own_lat = _at(tracks, own_rows, own_times)
    frame = _Frame(tracks.lon[first[own]], tracks.lat[first[own]], own_lon[0], own_lat[0],
                   options.map)  # fmt: skip
    grid_t = np.arange(t0, t1 + 1, round(SAMPLE * NS), dtype=np.int64)
    own_glon, own_glat = _at(tracks, own_rows, grid_t)
    targets, files, assumed = [], {}, 0
    names: set[str] = set()
    for i in range(first.size):
        rows = slice(first[i], stop[i])
        if i == own or tracks.mmsi[first[i]] == tracks.mmsi[first[own]]:
            continue
        lo, hi = max(t0, tracks.time[first[i]]), min(t1, tracks.time[stop[i] - 1])
        if hi <= lo:
            continue
        inside = (grid_t >= lo) & (grid_t <= hi)
        lon, lat = _at(tracks, rows, grid_t[inside])
        if not inside.any() or _distance(own_glon[inside], own_glat[inside], lon, lat).min() \
                > options.radius:  # fmt: skip
            continue
        times = _times_in(tracks.time[rows], lo, hi)
        lon, lat = _at(tracks, rows, times)
        name = f"ais-{tracks.mmsi[first[i]]}"
        name = name if name not in names else f"{name}-{tracks.track[first[i]]}"
        names.add(name)
        length = float(tracks.length[first[i]])
        if not length > 0:
            length, assumed = DEFAULT_LENGTH, assumed + 1
        files[f"{name}.csv"] = frame.track_csv((times - t0) / NS, lon, lat)
        targets.append({"name": name, "track": f"{name}.csv", "speed": 0,
                        "length": round(length, 2)})  # fmt: skip
    course, speed = _course_speed(tracks, own_rows, t0)
    duration = options.duration if options.duration is not None else 2 * (t1 - t0) / NS
    stamp = format_time([t0])[0].replace("-", "").replace(":", "").rstrip("Z")
    mmsi = int(tracks.mmsi[first[own]])
    scenario = {
        "name": f"ais-{mmsi}-{stamp}",
        **({"map": os.path.relpath(os.path.abspath(options.map), os.path.abspath(directory))}
           if options.map else {}),
        "route": ROUTE,
        "sim": {"dt": 0.1, "duration": round(duration, 1)},
        "own": {"start": frame.point(own_lon[0], own_lat[0]),
                "goal": frame.point(own_lon[-1], own_lat[-1]),
                "heading": round(float(course), 1), "speed": round(float(speed), 3),
                "vessel": options.vessel},
        "targets": targets,
        "controller": {"name": options.controller},
    }  # fmt: skip
    figures = {
        "scenario": scenario["name"], "own": mmsi, "own_name": tracks.name[first[own]],
        "own_track": int(tracks.track[first[own]]), "window": format_time([t0, t1]),
        "encounter": encounter, "targets": len(targets),
        "target_mmsis": [int(t["name"].split("-")[1]) for t in targets],
        "lengths_assumed": assumed, "frame": frame.describe(),
        "own_recorded_length_m": round(float(_distance(own_lon[:-1], own_lat[:-1], own_lon[1:],
                                                       own_lat[1:]).sum()), 1),
    }  # fmt: skip
    files[ROUTE] = frame.route(own_lon, own_lat, mmsi)
    files[SCENARIO] = _yaml(scenario, _comments(figures, options))
    return ScenarioResult(files, figures)


def scenario_paths(directory: str | os.PathLike, result: ScenarioResult) -> list[Path]:
    """The paths :func:`write_scenario` writes, the scenario first."""
    out = Path(directory)
    return [out / SCENARIO] + [out / n for n in result.files if n != SCENARIO]


def write_scenario(directory: str | os.PathLike, result: ScenarioResult,
                   extra: dict | None = None) -> list[Path]:  # fmt: skip
    """Write the files into ``directory`` (made if missing; its parent must exist), and the
    texts ``extra`` (path: text, e.g. the summary), all renamed at the end or none
    (:class:`usvtool.atomic.staged`); the paths of :func:`scenario_paths`."""
    from usvtool.atomic import staged

    out = Path(directory)
    if out.exists() and not out.is_dir():
        raise UsvError(f"-o {out}: is a file, not a directory")
    if not out.parent.is_dir():
        raise UsvError(f"-o {out}: directory {out.parent} does not exist")
    out.mkdir(exist_ok=True)
    paths = scenario_paths(out, result)
    texts = [result.files[p.name] for p in paths] + list((extra or {}).values())
    with staged(*paths, *(extra or {})) as temporaries:
        for text, tmp in zip(texts, temporaries, strict=True):
            tmp.write_text(text, encoding="utf-8")
    return paths


# --- the window ------------------------------------------------------------------------------


def _window(tracks: Tracks, options: ScenarioOptions) -> tuple[int, tuple[int, int], int | None]:
    """(the own ship's track ordinal, the window (ns), the encounter's rank or None)."""
    from usvtool.csvtable import time_ns

    first, stop = tracks.track_bounds()
    mmsi = tracks.mmsi[first]
    if options.encounter is not None:
        from usvtool.ais.encounters import read_encounters

        rows = read_encounters(options.encounters)
        row = next((r for r in rows if r["rank"] == options.encounter), None)
        if row is None:
            raise UsvError(f"--encounter {options.encounter}: no such rank in "
                           f"{options.encounters} (1 … {len(rows)})")  # fmt: skip
        own = options.own if options.own is not None else row["mmsi_a"]
        if own not in (row["mmsi_a"], row["mmsi_b"]):
            raise UsvError(f"--own {own}: not a vessel of encounter {options.encounter} "
                           f"({row['mmsi_a']}, {row['mmsi_b']})")  # fmt: skip
        track = row["track_a"] if own == row["mmsi_a"] else row["track_b"]
        ordinal = np.flatnonzero(tracks.track[first] == track)
        if ordinal.size == 0 or mmsi[ordinal[0]] != own:
            raise UsvError(f"--encounters {options.encounters}: track {track} of {own} is not "
                           "in the tracks file (made from other tracks?)")  # fmt: skip
        import pyarrow as pa

        ends = time_ns(options.encounters, pa.array([row["start"], row["end"]]), "start", 1)
        pad = round(options.pad * NS)
        t0, t1 = int(ends[0]) - pad, int(ends[1]) + pad
        own_ordinal = int(ordinal[0])
        rank = options.encounter
    else:
        import pyarrow as pa

        try:
            t0, t1 = (int(v) for v in time_ns("--start/--end", pa.array([options.start,
                                                                        options.end]), "", 0))
        except UsvError:
            raise UsvError(f"--start/--end: {options.start!r}, {options.end!r} are not ISO 8601 "
                           "times") from None  # fmt: skip
        if t1 <= t0:
            raise UsvError(f"--end {options.end}: not after --start {options.start}")
        candidates = np.flatnonzero((mmsi == options.own) & (tracks.time[first] < t1)
                                    & (tracks.time[stop - 1] > t0))  # fmt: skip
        if candidates.size == 0:
            raise UsvError(f"--own {options.own}: no track of that MMSI in {options.start} … "
                           f"{options.end}")  # fmt: skip
        spans = np.minimum(tracks.time[stop - 1][candidates], t1) - np.maximum(
            tracks.time[first][candidates], t0)  # fmt: skip
        own_ordinal = int(candidates[np.argmax(spans)])
        rank = None
    t0 = max(t0, int(tracks.time[first[own_ordinal]]))
    t1 = min(t1, int(tracks.time[stop[own_ordinal] - 1]))
    if t1 <= t0:
        raise UsvError(f"--own {mmsi[own_ordinal]}: her track holds no time of the window")
    return own_ordinal, (t0, t1), rank


def _times_in(fix_times: np.ndarray, t0: int, t1: int) -> np.ndarray:
    """The window's ends and the fix times strictly inside it."""
    inner = fix_times[(fix_times > t0) & (fix_times < t1)]
    return np.r_[t0, inner, t1].astype(np.int64)


def _at(tracks: Tracks, rows: slice, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lon/lat of a track at ``times`` (within its span), interpolated linearly (lon across
    the antimeridian unwrapped)."""
    t = tracks.time[rows]
    lon = tracks.lon[rows]
    unwrapped = lon[0] + np.r_[0.0, np.cumsum(wrap180(np.diff(lon)))]
    x = (times - t[0]) / NS
    tx = (t - t[0]) / NS
    return wrap180(np.interp(x, tx, unwrapped)), np.interp(x, tx, tracks.lat[rows])


def _distance(lon1, lat1, lon2, lat2) -> np.ndarray:
    """Distances (m) in the local east/north frame of the encounter search."""
    scale = EARTH_RADIUS * np.radians(1.0)
    mid = np.radians(0.5 * (np.asarray(lat1) + np.asarray(lat2)))
    return np.hypot(scale * np.cos(mid) * wrap180(np.asarray(lon2) - lon1),
                    scale * (np.asarray(lat2) - lat1))  # fmt: skip


def _course_speed(tracks: Tracks, rows: slice, t0: int) -> tuple[float, float]:
    """Course over ground (compass deg) and speed (m/s) of the track's segment at ``t0``;
    a vessel standing still keeps her reported heading."""
    t = tracks.time[rows]
    j = int(np.clip(np.searchsorted(t, t0, side="right") - 1, 0, t.size - 2))
    lon, lat = tracks.lon[rows], tracks.lat[rows]
    scale = EARTH_RADIUS * np.radians(1.0)
    dt = (t[j + 1] - t[j]) / NS
    ve = scale * math.cos(math.radians(lat[j])) * float(wrap180(lon[j + 1] - lon[j])) / dt
    vn = scale * (lat[j + 1] - lat[j]) / dt
    speed = math.hypot(ve, vn)
    if speed < 0.05:
        heading = tracks.heading[rows][j]
        return (float(heading) if heading == heading else 0.0), speed
    return float(wrap360(math.degrees(math.atan2(ve, vn)))), speed


# --- the frame -------------------------------------------------------------------------------


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


def _comments(figures: dict, options: ScenarioOptions) -> list[str]:
    what = (f"encounter {figures['encounter']} of {options.encounters}"
            if figures["encounter"] is not None else "a window")  # fmt: skip
    return [
        f"Real traffic (usvtool ais scenario): {what}, {figures['window'][0]} … "
        f"{figures['window'][1]}.",
        f"Own ship: MMSI {figures['own']} {figures['own_name'] or ''}".rstrip() + "'s start, "
        "goal and recorded track (the route); the USV under test in her place.",
        f"Targets: the {figures['targets']} other tracks within {options.radius:g} m, replayed.",
        f"Frame: {figures['frame']}.",
    ]


def _yaml(data: dict, comments: list[str]) -> str:
    import yaml

    body = yaml.safe_dump(data, sort_keys=False, default_flow_style=None, width=100,
                          allow_unicode=True)  # fmt: skip
    return "".join(f"# {c}\n" for c in comments) + body
