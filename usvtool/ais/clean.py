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

EARTH_RADIUS = 6_371_008.8  # m, IUGG mean radius
KNOT = 1852.0 / 3600.0  # m/s


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
    index = np.flatnonzero(keep & valid)
    mmsi, time = fx.mmsi[index], fx.time[index]
    counts["out_of_order"] = _out_of_order(mmsi, time)
    order = np.lexsort((time, mmsi))  # stable: the input order among equal times
    index, mmsi, time = index[order], mmsi[order], time[order]
    dup = np.r_[False, (mmsi[1:] == mmsi[:-1]) & (time[1:] == time[:-1])]
    counts["duplicates"] = int(dup.sum())
    index, mmsi, time = index[~dup], mmsi[~dup], time[~dup]
    lon, lat = fx.lon[index], fx.lat[index]
    max_gap_ns = options.max_gap * NS
    fast = _too_fast(mmsi, time, lon, lat, max_gap_ns, options.max_speed * KNOT)
    counts["too_fast"] = int(fast.sum())
    index, mmsi, time = index[~fast], mmsi[~fast], time[~fast]
    new_vessel = np.r_[True, mmsi[1:] != mmsi[:-1]]
    gap = np.r_[False, ~new_vessel[1:] & (np.diff(time) > max_gap_ns)]
    counts["gaps"] = int(gap.sum())
    track = np.cumsum(new_vessel | gap) - 1
    static = _static(fx, mmsi)
    tracks = Tracks(mmsi=mmsi, time=time, lon=fx.lon[index], lat=fx.lat[index],
                    sog=fx.sog[index], cog=fx.cog[index], heading=fx.heading[index],
                    track=track, **static)  # fmt: skip
    counts |= {"fixes": tracks.n_rows, "vessels": int(new_vessel.sum()),
               "tracks": int(track[-1] + 1) if track.size else 0}  # fmt: skip
    return tracks, counts


def _out_of_order(mmsi: np.ndarray, time: np.ndarray) -> int:
    """How many fixes (in input order) are earlier than one before them of the same MMSI."""
    if mmsi.size < 2:
        return 0
    by_vessel = np.argsort(mmsi, kind="stable")
    rank = np.unique(time[by_vessel], return_inverse=True)[1].astype(np.int64)
    group = np.cumsum(np.r_[True, np.diff(mmsi[by_vessel]) != 0]) - 1
    key = group * (rank.max() + 1) + rank  # increasing from vessel to vessel
    before = np.r_[-1, np.maximum.accumulate(key)[:-1]]
    return int((key < before).sum())


def _too_fast(mmsi, time, lon, lat, max_gap_ns: float, max_speed: float) -> np.ndarray:
    """The fixes rule 5 drops (sorted fixes, no duplicates): a vectorised test of consecutive
    fixes finds the vessels that have any, a greedy pass over those vessels' fixes decides."""
    n = mmsi.size
    drop = np.zeros(n, bool)
    if n < 2:
        return drop
    same = (mmsi[1:] == mmsi[:-1]) & (np.diff(time) <= max_gap_ns)
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
        d = float(haversine(lon[last], lat[last], lon[i], lat[i]))
        if d / ((time[i] - time[last]) / NS) > max_speed:
            drop[i] = True
        else:
            last = i
    return drop


def _static(fx: Fixes, mmsi: np.ndarray) -> dict:
    """The static columns of fixes of vessels ``mmsi`` (sorted): each vessel's last reported
    value of each (module docstring)."""
    vessels, first = np.unique(mmsi, return_index=True)
    per_row = np.repeat(np.arange(vessels.size), np.diff(np.r_[first, mmsi.size]))
    order = np.lexsort((fx.static_time, fx.static_mmsi))
    s_mmsi = fx.static_mmsi[order]
    out = {}
    for column, missing in (("length", np.nan), ("beam", np.nan), ("name", ""),
                            ("ship_type", 0)):  # fmt: skip
        values = getattr(fx, column)[order]
        known = ~np.isnan(values) if column in ("length", "beam") else (
            values != missing)  # fmt: skip
        v_mmsi, v = s_mmsi[known], values[known]
        last = np.r_[v_mmsi[1:] != v_mmsi[:-1], True] if v.size else np.zeros(0, bool)
        v_mmsi, v = v_mmsi[last], v[last]
        at = np.searchsorted(v_mmsi, vessels)
        found = at < v_mmsi.size
        found[found] = v_mmsi[at[found]] == vessels[found]
        dtype = object if column == "name" else float if column in ("length", "beam") else np.int64
        per_vessel = np.full(vessels.size, missing, dtype=dtype)
        per_vessel[found] = v[at[found]]
        out[column] = per_vessel[per_row]
    return out
