"""Cleaning raw fixes into tracks, each rule counted (``usvtool ais read``'s summary).

In this order, on the fixes of all the files read together:

1. ``invalid_mmsi``: an MMSI outside 1 … 999 999 999 is dropped.
2. ``invalid_position``: a latitude outside [-90, 90] or a longitude outside [-180, 180] (AIS
   sends 91 and 181 for "not available"), or exactly 0, 0, is dropped.
3. ``out_of_order``: a fix earlier than one before it in the input for the same MMSI is counted
   and put in its place (the fixes are sorted by MMSI, then time, stably).
4. ``duplicates``: a fix at the same time as the one before it for the same MMSI is dropped (the
   first in the input stays).
5. ``too_fast``: a fix that the vessel's last kept fix could only reach at more than
   ``max_speed`` (50 kn) is dropped (greedily, fix by fix: a single jump drops one fix, a
   vessel whose first fix is wrong loses the fixes up to her next gap). Distances are great
   circle (haversine, mean Earth radius 6 371 008.8 m).
6. ``gaps``: a gap longer than ``max_gap`` between two kept fixes of a vessel starts a new
   track (no speed test across it).

Static data (length, beam, name, ship type) are joined by MMSI: each vessel's last reported
value (latest time) of each, a missing value never overriding a known one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from usvtool.ais.fixes import Fixes
from usvtool.errors import UsvError
from usvtool.tracks import MAX_MMSI, NS, Tracks
from usvtool.traffic import EARTH_RADIUS, KNOT


@dataclass(frozen=True)
class CleanOptions:
    """``max_gap`` s: a longer gap starts a new track; ``max_speed`` kn: a fix implying more
    is dropped."""

    max_gap: float = 600.0
    max_speed: float = 50.0

    def __post_init__(self):
        for name in ("max_gap", "max_speed"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise UsvError(f"--{name.replace('_', '-')}: must be a number > 0, not {value}")


def haversine(lon1, lat1, lon2, lat2) -> np.ndarray:
    """Great-circle distance (m) between points in degrees, on the mean Earth sphere.

    >>> round(float(haversine(0.0, 0.0, 0.0, 1.0)), 1)  # a degree of latitude
    111195.1
    """
    p1, p2 = np.radians(lat1), np.radians(lat2)
    dlat = p2 - p1
    dlon = np.radians(np.asarray(lon2, float) - np.asarray(lon1, float))
    a = np.sin(dlat / 2) ** 2 + np.cos(p1) * np.cos(p2) * np.sin(dlon / 2) ** 2
    return 2 * EARTH_RADIUS * np.arcsin(np.sqrt(np.clip(a, 0.0, 1.0)))


def clean(fx: Fixes, options: CleanOptions = CleanOptions()) -> tuple[Tracks, dict]:
    """The tracks of the fixes and the counts of each rule (module docstring)."""
    counts = {"fixes_read": fx.n_positions}
    keep = (fx.mmsi >= 1) & (fx.mmsi <= MAX_MMSI)
    counts["invalid_mmsi"] = int((~keep).sum())
    with np.errstate(invalid="ignore"):
        valid = (np.abs(fx.lat) <= 90) & (np.abs(fx.lon) <= 180) & ~((fx.lat == 0) & (fx.lon == 0))
    counts["invalid_position"] = int((keep & ~valid).sum())
    order = by_vessel_and_time(fx.mmsi, fx.time)
    index = order[(keep & valid)[order]]  # the valid fixes by vessel and time
    mmsi, time = fx.mmsi[index], fx.time[index]
    counts["out_of_order"] = _out_of_order(index, mmsi)
    dup = ~_run_starts(mmsi) & ~_run_starts(time)
    counts["duplicates"] = int(dup.sum())
    index, mmsi, time = index[~dup], mmsi[~dup], time[~dup]
    lon, lat = fx.lon[index], fx.lat[index]
    max_gap_ns = options.max_gap * NS
    fast = _too_fast(mmsi, time, lon, lat, max_gap_ns, options.max_speed * KNOT)
    counts["too_fast"] = int(fast.sum())
    index, mmsi, time = index[~fast], mmsi[~fast], time[~fast]
    new_vessel = _run_starts(mmsi)
    gap = ~new_vessel & (np.diff(time, prepend=time[:1]) > max_gap_ns)
    counts["gaps"] = int(gap.sum())
    track = np.cumsum(new_vessel | gap) - 1
    static = _static(fx, mmsi, order)
    tracks = Tracks(mmsi=mmsi, time=time, lon=fx.lon[index], lat=fx.lat[index],
                    sog=fx.sog[index], cog=fx.cog[index], heading=fx.heading[index],
                    track=track, **static)  # fmt: skip
    counts |= {"fixes": tracks.n_rows, "vessels": int(new_vessel.sum()),
               "tracks": int(track[-1] + 1) if track.size else 0}  # fmt: skip
    return tracks, counts


def _run_starts(values: np.ndarray) -> np.ndarray:
    """Whether each value differs from the one before it (the first always does; none of
    none).

    >>> _run_starts(np.array([4, 4, 5])).tolist(), _run_starts(np.zeros(0)).tolist()
    ([True, False, True], [])
    """
    starts = np.ones(values.size, bool)
    starts[1:] = values[1:] != values[:-1]
    return starts


def by_vessel_and_time(mmsi: np.ndarray, time: np.ndarray) -> np.ndarray:
    """The stable order by MMSI, then time (the input order among equal times), by one argsort
    of one integer key (``np.lexsort`` on the two columns is three times slower).

    >>> by_vessel_and_time(np.array([2, 1, 2, 1]), np.array([5, 9, 5, 3])).tolist()
    [3, 1, 0, 2]
    """
    if mmsi.size == 0:
        return np.zeros(0, np.int64)
    rank = np.unique(time, return_inverse=True)[1].astype(np.int64)  # < n: no overflow
    return np.argsort(mmsi * (int(rank.max()) + 1) + rank, kind="stable")


def _out_of_order(index: np.ndarray, mmsi: np.ndarray) -> int:
    """How many fixes are earlier than one before them in the input for the same MMSI: given
    the fixes' input positions ``index`` sorted by vessel and time, those followed (in their
    vessel) by one of a smaller input position.

    >>> _out_of_order(np.array([0, 4, 1, 2, 3]), np.array([1, 1, 1, 1, 1]))  # the 2nd came last
    1
    """
    if index.size < 2:
        return 0
    group = np.cumsum(np.r_[True, mmsi[1:] != mmsi[:-1]]) - 1
    key = group * (int(index.max()) + 1) + index  # a later vessel's keys are all larger
    after = np.minimum.accumulate(key[::-1])[::-1]  # the least key from here to the end
    return int((key[:-1] > after[1:]).sum())


def _too_fast(mmsi, time, lon, lat, max_gap_ns: float, max_speed: float) -> np.ndarray:
    """The fixes rule 5 drops (sorted fixes, no duplicates): a vectorised test of consecutive
    fixes finds the vessels that have any, a greedy pass over those vessels' fixes decides."""
    n = mmsi.size
    drop = np.zeros(n, bool)
    if n < 2:
        return drop
    same = (mmsi[1:] == mmsi[:-1]) & (np.diff(time) <= max_gap_ns)
    with np.errstate(divide="ignore", invalid="ignore"):  # a new vessel at the same time
        speed = haversine(lon[:-1], lat[:-1], lon[1:], lat[1:]) / (np.diff(time) / NS)
    suspects = np.unique(mmsi[1:][same & (speed > max_speed)])
    if suspects.size == 0:
        return drop
    rows = np.flatnonzero(np.isin(mmsi, suspects))
    last = -1
    for i in rows.tolist():
        if last < 0 or mmsi[i] != mmsi[last] or time[i] - time[last] > max_gap_ns:
            last = i
            continue
        d = _distance(lon[last], lat[last], lon[i], lat[i])
        if d / ((time[i] - time[last]) / NS) > max_speed:
            drop[i] = True
        else:
            last = i
    return drop


def _distance(lon1: float, lat1: float, lon2: float, lat2: float) -> float:
    """:func:`haversine` of two points, in plain floats (the greedy loop's)."""
    p1, p2 = math.radians(lat1), math.radians(lat2)
    a = (math.sin((p2 - p1) / 2) ** 2
         + math.cos(p1) * math.cos(p2) * math.sin(math.radians(lon2 - lon1) / 2) ** 2)  # fmt: skip
    return 2 * EARTH_RADIUS * math.asin(math.sqrt(min(1.0, a)))


def _static(fx: Fixes, mmsi: np.ndarray, order: np.ndarray) -> dict:
    """The static columns of fixes of vessels ``mmsi`` (sorted): each vessel's last reported
    value of each (module docstring). ``order``: the positions' order by vessel and time, that
    of the static reports too when they are the positions (a CSV format's rows)."""
    vessels, first = np.unique(mmsi, return_index=True)
    per_row = np.repeat(np.arange(vessels.size), np.diff(np.r_[first, mmsi.size]))
    if not (fx.static_mmsi is fx.mmsi and fx.static_time is fx.time):
        order = by_vessel_and_time(fx.static_mmsi, fx.static_time)
    s_mmsi = fx.static_mmsi[order]
    out = {}
    for column, missing in (("length", np.nan), ("beam", np.nan), ("name", ""),
                            ("ship_type", 0)):  # fmt: skip
        values = getattr(fx, column)
        known = ~np.isnan(values) if column in ("length", "beam") else values != missing
        rows = order[known[order]]  # the known reports, by vessel and time (indices only)
        v_mmsi = s_mmsi[known[order]]
        last = np.r_[v_mmsi[1:] != v_mmsi[:-1], True] if rows.size else np.zeros(0, bool)
        v_mmsi, rows = v_mmsi[last], rows[last]
        at = np.searchsorted(v_mmsi, vessels)
        found = at < v_mmsi.size
        found[found] = v_mmsi[at[found]] == vessels[found]
        dtype = object if column == "name" else float if column in ("length", "beam") else np.int64
        per_vessel = np.full(vessels.size, missing, dtype=dtype)
        per_vessel[found] = values[rows[at[found]]]
        out[column] = per_vessel[per_row]
    return out
