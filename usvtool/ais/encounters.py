"""``usvtool ais encounters``: every pair of vessels whose tracks come within the CPA distance.

The tracks (:mod:`usvtool.tracks`) are interpolated linearly between fixes onto one time grid
(multiples of ``step`` seconds since the epoch, within each track's first and last fix; tracks
are already split at gaps). For a pair, at each common grid time: the relative position ``p`` of
vessel b from vessel a in a local east/north frame (``R cos φ Δλ``, ``R Δφ``, R the mean Earth
radius), the relative velocity ``v`` (each vessel's velocity that of her track's segment), the
range ``|p|`` and the straight-line CPA (:func:`usvtool.encounter.cpa`: ``tcpa = -p·v/|v|²``).

An *encounter* is a maximal run of grid times at which the pair is in close quarters or heading
for them: range ``<= cpa``, or closing with ``dcpa <= cpa`` and ``tcpa <= --tcpa``; it counts
when, within the run, the range comes down to ``cpa`` or less (the minimum refined between grid
times, the relative motion linear between them) while at least one of the two makes
``min_speed`` over ground (two moored vessels alongside are no encounter). Its row: the window
(the run's first and last grid times), the CPA and its time, and, at *first detection* (the
run's first time), the TCPA, range, speeds, courses and the COLREGs class of each seen from the
other (:func:`usvtool.encounter.assess`, the simulation's classifier). A window that starts or
ends with the pair's common time is ``censored`` (the encounter may have begun earlier or gone
on later). Rows are ranked by CPA.

Search: spatial and temporal bucketing. Every grid sample goes to a cube of side ``cpa +
margin`` in Earth-centred coordinates (``margin = 2 v_max · step``, ``v_max`` the fastest
segment: no pair that comes within ``cpa`` between grid times is missed); a sample of a moving
vessel looks in its own and the 26 neighbouring cubes at the same grid time, through sorted
integer keys (NumPy ``searchsorted``), so the work grows with the samples and the vessels near
each other, not with the square of the vessels. Only the candidate pairs found so are then
followed over their whole common time.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field

import numpy as np

from usvtool.ais.fixes import check_bbox
from usvtool.angles import wrap180, wrap360
from usvtool.budget import default_budget, require
from usvtool.encounter import CLASS_NAMES, assess
from usvtool.encounter import cpa as straight_cpa
from usvtool.errors import UsvError
from usvtool.tracks import NS, Tracks, format_time
from usvtool.traffic import EARTH_RADIUS, KNOT, STILL, encounters_csv

#: Pair samples followed at once in the second phase (bounds its memory: some 40 B each x 20).
CHUNK = 2_000_000
#: Peak memory per grid sample (measured over the 99 999-row extract at 10, 5 and 2 s: 1.09,
#: 2.19 and 5.47 M samples took 427, 651 and 1 340 MiB, some 215 B a sample).
SAMPLE_BYTES = 250


@dataclass(frozen=True)
class EncounterOptions:
    """``cpa`` m; ``tcpa`` s; ``bbox`` (lon min, lat min, lon max, lat max) or None; ``step`` s,
    the time grid; ``min_speed`` kn (module docstring); ``max_memory`` the budget (bytes; None:
    :func:`usvtool.budget.default_budget`) the time grid's samples must fit."""

    cpa: float = 500.0
    tcpa: float = 900.0
    bbox: tuple[float, float, float, float] | None = None
    step: float = 10.0
    min_speed: float = 1.0
    max_memory: int | None = None

    def __post_init__(self):
        for name in ("cpa", "tcpa", "step"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise UsvError(f"--{name.replace('_', '-')}: must be a number > 0, not {value}")
        if not (math.isfinite(self.min_speed) and self.min_speed >= 0):
            raise UsvError(f"--min-speed: must be a number >= 0, not {self.min_speed}")
        if round(self.step * NS) < 1:
            raise UsvError(f"--step: must be 1e-9 s or more, not {self.step}")
        object.__setattr__(self, "bbox", check_bbox(self.bbox))


@dataclass
class EncounterResult:
    """The encounters (one dict per row, :data:`usvtool.traffic.COLUMNS`, ranked) and the
    search's figures."""

    rows: list[dict]
    figures: dict = field(default_factory=dict)

    def summary(self) -> dict:
        closest = self.rows[0] if self.rows else None
        classes: dict[str, int] = {}
        for r in self.rows:
            classes[r["class_a"]] = classes.get(r["class_a"], 0) + 1
        return {"encounters": len(self.rows), "classes": dict(sorted(classes.items())),
                "closest": None if closest is None else {
                    k: closest[k] for k in ("mmsi_a", "mmsi_b", "name_a", "name_b", "cpa_m",
                                            "cpa_time", "class_a", "class_b")},
                **self.figures}  # fmt: skip

    def to_csv(self) -> str:
        """The encounters CSV (:func:`usvtool.traffic.encounters_csv`)."""
        return encounters_csv(self.rows)


def find_encounters(tracks: Tracks, options: EncounterOptions = EncounterOptions(),
                    source: str = "tracks") -> EncounterResult:  # fmt: skip
    """The encounters in ``tracks`` (module docstring); ``source`` names them in messages
    (the file)."""
    ids = tracks.track  # the tracks file's ids, which the rows name
    if options.bbox is not None:
        tracks, ids = _in_box(tracks, options.bbox)
    first, stop = tracks.track_bounds()
    if not (stop - first >= 2).any():
        inside = " inside --bbox" if options.bbox is not None else ""
        raise UsvError(f"{source}: no track of two fixes or more{inside} to interpolate (fixes: "
                       f"{tracks.n_rows}, tracks: {tracks.n_tracks})")  # fmt: skip
    step_ns = round(options.step * NS)
    budget = default_budget() if options.max_memory is None else options.max_memory
    grid = _Samples(tracks, step_ns, budget)
    figures = {"tracks": tracks.n_tracks, "tracks_searched": grid.n_tracks,
               "samples": grid.n}  # fmt: skip
    pairs = grid.candidates(options.cpa, options.min_speed * KNOT)
    figures["candidate_pairs"] = int(len(pairs))
    rows = []
    for chunk in _chunks(grid, pairs):
        rows += grid.follow(chunk, options, tracks, ids)
    rows.sort(key=lambda r: (r["cpa_m"], r["start"], r["mmsi_a"], r["mmsi_b"]))
    for i, r in enumerate(rows, start=1):
        r["rank"] = i
    return EncounterResult(rows, figures)


def _in_box(tracks: Tracks, box) -> tuple[Tracks, np.ndarray]:
    """The fixes inside ``box`` (a track that leaves it and comes back is two tracks), and the
    track id in ``tracks`` of each."""
    inside = ((tracks.lon >= box[0]) & (tracks.lon <= box[2]) & (tracks.lat >= box[1])
              & (tracks.lat <= box[3]))  # fmt: skip
    index = np.flatnonzero(inside)
    if index.size == 0:
        raise UsvError(f"--bbox: no fix inside {box}")
    t = tracks.track[index]
    new = np.r_[True, (t[1:] != t[:-1]) | (np.diff(index) != 1)]
    columns = {c: getattr(tracks, c)[index] for c in ("mmsi", "time", "lon", "lat", "sog", "cog",
                                                      "heading", "length", "beam", "name",
                                                      "ship_type")}  # fmt: skip
    return Tracks(**columns, track=np.cumsum(new) - 1), t


class _Samples:
    """Every track of two or more fixes sampled on the grid: per sample its track (ordinal),
    grid index ``k``, lon/lat, velocity east/north (m/s) and course (compass deg)."""

    def __init__(self, tracks: Tracks, step_ns: int, budget: int):
        first, stop = tracks.track_bounds()
        long_enough = stop - first >= 2
        first, stop = first[long_enough], stop[long_enough]
        self.first_row = first
        self.n_tracks = int(first.size)
        self.step_ns = step_ns
        t = tracks.time
        k0 = -(-t[first] // step_ns)  # ceil
        k1 = t[stop - 1] // step_ns
        count = np.maximum(k1 - k0 + 1, 0)
        n = int(count.sum())
        require(n * SAMPLE_BYTES, f"--step {step_ns / NS:g}: {self.n_tracks:,} tracks sampled "
                f"every {step_ns / NS:g} s ({n:,} samples)", "give a larger --step, or search "
                "by parts with --bbox", budget)  # fmt: skip
        self.k0, self.count = k0, count
        self.start = np.cumsum(count) - count  # first sample per track
        self.n = n
        ordinal = np.repeat(np.arange(first.size), count)
        k = np.repeat(k0, count) + np.arange(n) - np.repeat(self.start, count)
        times = k * step_ns
        # each sample's segment: the last fix of its track at or before it, by one sort of the
        # fixes and samples together (a fix before a sample of the same time)
        rows = np.flatnonzero(np.repeat(long_enough, np.diff(np.r_[tracks.track_bounds()[0],
                                                                    tracks.n_rows])))  # fmt: skip
        fix_ordinal = np.repeat(np.arange(first.size), stop - first)
        merged = np.lexsort((np.r_[np.zeros(rows.size, np.int8), np.ones(n, np.int8)],
                             np.r_[t[rows], times], np.r_[fix_ordinal, ordinal]))  # fmt: skip
        is_fix = merged < rows.size
        fixes_before = np.cumsum(is_fix)[~is_fix]  # per sample, in (ordinal, time) order
        fix_start = np.r_[0, np.cumsum(stop - first)[:-1]]
        j = fixes_before - fix_start[ordinal] - 1
        seg = first[ordinal] + np.clip(j, 0, (stop - first)[ordinal] - 2)
        lon0, lat0 = tracks.lon[seg], tracks.lat[seg]
        dlon = wrap180(tracks.lon[seg + 1] - lon0)
        dlat = tracks.lat[seg + 1] - lat0
        dt = (t[seg + 1] - t[seg]) / NS
        f = (times - t[seg]) / NS / dt
        self.lat = lat0 + f * dlat
        self.lon = wrap180(lon0 + f * dlon)
        scale = EARTH_RADIUS * np.radians(1.0)
        self.ve = scale * np.cos(np.radians(self.lat)) * dlon / dt
        self.vn = scale * dlat / dt
        self.speed = np.hypot(self.ve, self.vn)
        reported = np.where(np.isnan(tracks.heading[seg]), tracks.cog[seg], tracks.heading[seg])
        moving = wrap360(np.degrees(np.arctan2(self.ve, self.vn)))
        self.course = np.where(self.speed < STILL, np.nan_to_num(reported), moving)
        self.ordinal, self.k, self.time = ordinal, k, times

    def candidates(self, cpa: float, min_speed: float) -> np.ndarray:
        """Pairs of track ordinals ``(m, 2)`` (a < b) that come within ``cpa + margin`` at a
        grid time when one of them makes ``min_speed`` (module docstring)."""
        if self.n == 0:
            return np.zeros((0, 2), np.int64)
        margin = 2.0 * float(self.speed.max()) * self.step_ns / NS
        cell = cpa + margin
        lat, lon = np.radians(self.lat), np.radians(self.lon)
        xyz = EARTH_RADIUS * np.column_stack([np.cos(lat) * np.cos(lon),
                                              np.cos(lat) * np.sin(lon), np.sin(lat)])  # fmt: skip
        c = np.floor(xyz / cell).astype(np.int64)
        c -= c.min(axis=0) - 1  # >= 1: a neighbour's index stays >= 0
        size = c.max(axis=0) + 2
        space = int(np.prod(size))
        kk = self.k - self.k.min()
        if space >= 1 << 62:
            raise UsvError(f"--cpa {cpa:g}: too small for an area this large; search it by parts "
                           "(--bbox)")  # fmt: skip
        per = (1 << 62) // space  # grid times per part: the keys fit in int64
        cells = (c[:, 0] * size[1] + c[:, 1]) * size[2] + c[:, 2]
        offsets = np.array([(dx * size[1] + dy) * size[2] for dx in (-1, 0, 1)
                            for dy in (-1, 0, 1)], np.int64)  # the dz cells: one key range
        found = []
        for lo_k in range(0, int(kk.max()) + 1, per):
            part = np.flatnonzero((kk >= lo_k) & (kk < lo_k + per))
            keys = (kk[part] - lo_k) * space + cells[part]
            order = np.argsort(keys, kind="stable")
            sorted_keys, members = keys[order], part[order]
            query = members[self.speed[members] >= min_speed]  # in key order: fast searches
            qkeys = (kk[query] - lo_k) * space + cells[query]
            for off in offsets:
                lo = np.searchsorted(sorted_keys, qkeys + off - 1, "left")
                hi = np.searchsorted(sorted_keys, qkeys + off + 1, "right")
                n = hi - lo
                if not n.any():
                    continue
                a = np.repeat(query, n)
                b = members[np.repeat(lo, n) + np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)]
                near = (self.ordinal[a] != self.ordinal[b]) & (
                    ((xyz[a] - xyz[b]) ** 2).sum(axis=1) <= cell * cell)  # fmt: skip
                pa, pb = self.ordinal[a[near]], self.ordinal[b[near]]
                found.append(np.unique(np.minimum(pa, pb) * self.n_tracks + np.maximum(pa, pb)))
        if not found:
            return np.zeros((0, 2), np.int64)
        pairs = np.unique(np.concatenate(found))
        return np.column_stack([pairs // self.n_tracks, pairs % self.n_tracks])

    def follow(self, pairs: np.ndarray, options: EncounterOptions, tracks: Tracks,
               ids: np.ndarray) -> list[dict]:  # fmt: skip
        """The encounters of candidate ``pairs`` over their common grid times (``ids``: each
        row's track id in the file)."""
        a, b = pairs[:, 0], pairs[:, 1]
        k_lo = np.maximum(self.k0[a], self.k0[b])
        k_hi = np.minimum(self.k0[a] + self.count[a], self.k0[b] + self.count[b]) - 1
        length = np.maximum(k_hi - k_lo + 1, 0)
        pair = np.repeat(np.arange(len(pairs)), length)
        offset = np.arange(int(length.sum())) - np.repeat(np.cumsum(length) - length, length)
        k = np.repeat(k_lo, length) + offset
        ia = self.start[a][pair] + k - self.k0[a][pair]
        ib = self.start[b][pair] + k - self.k0[b][pair]
        scale = EARTH_RADIUS * np.radians(1.0)
        mid = np.radians(0.5 * (self.lat[ia] + self.lat[ib]))
        p = np.column_stack([scale * np.cos(mid) * wrap180(self.lon[ib] - self.lon[ia]),
                             scale * (self.lat[ib] - self.lat[ia])])  # fmt: skip
        v = np.column_stack([self.ve[ib] - self.ve[ia], self.vn[ib] - self.vn[ia]])
        dcpa, tcpa = straight_cpa(p, v)
        rng = np.hypot(p[:, 0], p[:, 1])
        closing = (p * v).sum(axis=1) < 0
        on = (rng <= options.cpa) | (closing & (dcpa <= options.cpa) & (tcpa <= options.tcpa))
        if not on.any():
            return []
        boundary = np.r_[True, (pair[1:] != pair[:-1]) | (on[1:] != on[:-1])]
        run = np.cumsum(boundary) - 1
        starts = np.flatnonzero(boundary)
        stops = np.r_[starts[1:], len(on)]
        by_range = np.lexsort((rng, run))
        closest = by_range[np.r_[True, run[by_range][1:] != run[by_range][:-1]]]  # per run
        keep = on[starts]
        s, e, m = starts[keep], stops[keep], closest[keep]
        # the CPA refined over the grid intervals on either side of the closest grid time
        d_min, shift = rng[m].copy(), np.zeros(len(m))
        for side in (-1, 1):
            n = np.clip(m + side, 0, len(pair) - 1)
            valid = (m + side >= 0) & (m + side < len(pair)) & (pair[n] == pair[m])
            d, frac = segment_min(p[m], p[n])
            better = valid & (d < d_min)
            d_min[better], shift[better] = d[better], side * frac[better]
        moving = np.maximum(self.speed[ia[m]], self.speed[ib[m]]) >= options.min_speed * KNOT
        ok = (d_min <= options.cpa) & moving
        s, e, m, d_min, shift = s[ok], e[ok], m[ok], d_min[ok], shift[ok]
        if not len(s):
            return []
        step = self.step_ns / NS
        seconds = np.round(shift * step)  # the CPA's time to the second
        frac = np.abs(seconds / step)
        n = m + np.sign(seconds).astype(np.int64)
        at = {}
        for name, idx in (("a", ia), ("b", ib)):
            lon_m = self.lon[idx[m]]
            at["lon" + name] = lon_m + frac * wrap180(self.lon[idx[n]] - lon_m)
            at["lat" + name] = self.lat[idx[m]] + frac * (self.lat[idx[n]] - self.lat[idx[m]])
        lon = wrap180(at["lona"] + 0.5 * wrap180(at["lonb"] - at["lona"]))
        lat = 0.5 * (at["lata"] + at["latb"])
        own = assess((0.0, 0.0), self.course[ia[s]], self.speed[ia[s]], p[s],
                     self.course[ib[s]], self.speed[ib[s]]).cls  # fmt: skip
        other = assess((0.0, 0.0), self.course[ib[s]], self.speed[ib[s]], -p[s],
                       self.course[ia[s]], self.speed[ia[s]]).cls  # fmt: skip
        i = pair[s]
        ra, rb = self.first_row[a[i]], self.first_row[b[i]]
        censored = (s == 0) | (pair[np.maximum(s - 1, 0)] != i) | (e == len(pair)) | (
            pair[np.minimum(e, len(pair) - 1)] != i)  # fmt: skip
        columns = {
            "mmsi_a": tracks.mmsi[ra], "mmsi_b": tracks.mmsi[rb],
            "track_a": ids[ra], "track_b": ids[rb],
            "name_a": tracks.name[ra], "name_b": tracks.name[rb],
            "length_a": tracks.length[ra], "length_b": tracks.length[rb],
            "start": np.array(format_time(self.time[ia[s]])),
            "end": np.array(format_time(self.time[ia[e - 1]])),
            "cpa_time": np.array(format_time(self.time[ia[m]] + seconds.astype(np.int64) * NS)),
            "cpa_m": d_min, "tcpa_s": tcpa[s], "range_m": rng[s],
            "class_a": np.array(CLASS_NAMES)[own], "class_b": np.array(CLASS_NAMES)[other],
            "sog_a": self.speed[ia[s]] / KNOT, "sog_b": self.speed[ib[s]] / KNOT,
            "cog_a": self.course[ia[s]], "cog_b": self.course[ib[s]],
            "lon": lon, "lat": lat, "censored": censored,
        }  # fmt: skip
        lists = {k: v.tolist() for k, v in columns.items()}
        return [{k: lists[k][j] for k in columns} for j in range(len(s))]


def segment_min(p0: np.ndarray, p1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The least ``|p0 + f (p1 - p0)|`` over ``f`` in [0, 1] of each row, and its ``f``.

    >>> d, f = segment_min(np.array([[-3.0, 4.0], [1.0, 1.0]]), np.array([[3.0, 4.0], [2.0, 2.0]]))
    >>> d.tolist(), f.tolist()
    ([4.0, 1.4142135623730951], [0.5, 0.0])
    """
    d = p1 - p0
    dd = (d * d).sum(axis=1)
    f = np.clip(-(p0 * d).sum(axis=1) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    at = p0 + f[:, None] * d
    return np.hypot(at[:, 0], at[:, 1]), f


def _chunks(grid: _Samples, pairs: np.ndarray):
    """The candidate pairs in groups of at most :data:`CHUNK` pair samples (one pair longer
    than that alone)."""
    if len(pairs) == 0:
        return
    a, b = pairs[:, 0], pairs[:, 1]
    lengths = np.maximum(np.minimum(grid.k0[a] + grid.count[a], grid.k0[b] + grid.count[b])
                         - np.maximum(grid.k0[a], grid.k0[b]), 0)  # fmt: skip
    start, total = 0, 0
    for i, n in enumerate(lengths.tolist()):
        if total and total + n > CHUNK:
            yield pairs[start:i]
            start, total = i, 0
        total += n
    yield pairs[start:]


# --- the encounters CSV -----------------------------------------------------------------------


def write_encounters(path: str | os.PathLike, result: EncounterResult) -> None:
    """Write the encounters CSV (:data:`usvtool.traffic.COLUMNS`, one row per encounter; read by
    :func:`usvtool.traffic.read_encounters`), atomically."""
    from usvtool.atomic import write_text

    write_text(path, result.to_csv())
