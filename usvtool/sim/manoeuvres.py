"""The own ship's manoeuvres on her sampled track, for the verdicts (:mod:`usvtool.sim.verdicts`).

Manoeuvre (:meth:`Track.manoeuvre`)
    A manoeuvre is detected at the first sample ``i`` (from the encounter's onset) from which
    the heading changes by at least ``MANOEUVRE_COURSE_DEG`` (5°), or the speed by at least
    ``MANOEUVRE_SPEED_FRACTION`` (10 %) of the speed at ``i`` (at least ``SPEED_FLOOR`` m/s),
    within the following ``MANOEUVRE_WINDOW_S`` (10 s). It starts at the last sample before the
    threshold is crossed whose heading is within ``MANOEUVRE_START_DEG`` (1°) and speed within
    ``MANOEUVRE_START_FRACTION`` (2 %) of those at ``i`` (so a fast turn is not dated up to 10 s
    early). Its course change is the signed heading deviation from ``i`` of largest magnitude
    until the CPA (positive = starboard), its speed change the signed relative speed deviation of
    largest magnitude; its side is starboard/port when the course change is at least 5° either
    way, else none (a speed manoeuvre).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

MANOEUVRE_COURSE_DEG = 5.0
MANOEUVRE_WINDOW_S = 10.0
MANOEUVRE_SPEED_FRACTION = 0.1
MANOEUVRE_START_DEG = 1.0
MANOEUVRE_START_FRACTION = 0.02
SPEED_FLOOR = 0.01  # m/s: speed thresholds are relative to at least this


class Manoeuvre(NamedTuple):
    """A manoeuvre: the sample it starts at, its course change (degrees, + to starboard) and
    its speed change (a fraction of the speed where it was detected; None from a standstill)."""

    start: int
    course: float
    speed: float | None

    @property
    def side(self) -> str | None:
        """``starboard`` or ``port`` for a course change of 5° or more, else None."""
        if self.course >= MANOEUVRE_COURSE_DEG:
            return "starboard"
        if self.course <= -MANOEUVRE_COURSE_DEG:
            return "port"
        return None


class Track:
    """The own ship's sampled track ``t`` (s), compass ``heading`` (deg) and ``speed`` (m/s),
    with its manoeuvre flags (module docstring). ``h`` is the heading unwrapped (no jump at
    0/360), ``v`` the speed."""

    def __init__(self, t, heading, speed):
        self.t = t
        self.h = np.degrees(np.unwrap(np.radians(heading)))
        self.v = speed
        n = len(t)
        self.end = np.searchsorted(t, t + MANOEUVRE_WINDOW_S, side="right") - 1
        self.thr = MANOEUVRE_SPEED_FRACTION * np.maximum(speed, SPEED_FLOOR)
        lo = np.minimum(np.arange(n) + 1, n - 1)
        hi = np.maximum(self.end, lo)
        valid = self.end > np.arange(n)
        hmax, hmin = _range_extrema(self.h, lo, hi)
        vmax, vmin = _range_extrema(self.v, lo, hi)
        dev_h = np.maximum(hmax - self.h, self.h - hmin)
        dev_v = np.maximum(vmax - self.v, self.v - vmin)
        self.flag = valid & ((dev_h >= MANOEUVRE_COURSE_DEG) | (dev_v >= self.thr))

    def manoeuvre(self, first: int, last: int) -> Manoeuvre | None:
        """The first manoeuvre detected at a sample in ``[first, last]``, its extent measured up
        to sample ``last`` (the CPA); None when there is none."""
        hits = np.flatnonzero(self.flag[first : last + 1])
        if not hits.size:
            return None
        i = first + int(hits[0])
        h0, v0 = self.h[i], self.v[i]
        win = slice(i + 1, self.end[i] + 1)
        over = (np.abs(self.h[win] - h0) >= MANOEUVRE_COURSE_DEG) | (
            np.abs(self.v[win] - v0) >= self.thr[i]
        )
        cross = i + 1 + int(np.argmax(over))
        seg = slice(i, cross)
        v_tol = MANOEUVRE_START_FRACTION * max(v0, SPEED_FLOOR)
        calm = np.abs(self.h[seg] - h0) <= MANOEUVRE_START_DEG
        calm &= np.abs(self.v[seg] - v0) <= v_tol
        start = i + int(np.flatnonzero(calm)[-1])
        span = slice(start, max(last, cross) + 1)
        dh = self.h[span] - h0
        dv = self.v[span] - v0
        course = float(dh[np.argmax(np.abs(dh))])
        speed = float(dv[np.argmax(np.abs(dv))] / v0) if v0 > 0 else None
        return Manoeuvre(start, course, speed)

    def deviation(self, first: int, stop: int) -> tuple[float, float]:
        """The largest heading (deg) and speed (m/s) deviations from sample ``first`` over the
        samples ``first`` … ``stop - 1`` (``stop > first``)."""
        keep = slice(first, stop)
        return (
            float(np.abs(self.h[keep] - self.h[first]).max()),
            float(np.abs(self.v[keep] - self.v[first]).max()),
        )


def _range_extrema(a: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """Max and min of ``a[lo_i … hi_i]`` (inclusive, ``lo ≤ hi``) for all ``i``: sparse table."""
    n = len(a)
    tmax, tmin = [a], [a]
    width = 1
    while 2 * width <= n:
        m, s = tmax[-1], tmin[-1]
        tmax.append(np.concatenate([np.maximum(m[:-width], m[width:]), m[-width:]]))
        tmin.append(np.concatenate([np.minimum(s[:-width], s[width:]), s[-width:]]))
        width *= 2
    level = np.floor(np.log2(hi - lo + 1)).astype(int)
    tmax, tmin = np.array(tmax), np.array(tmin)
    right = hi - (1 << level) + 1
    return (
        np.maximum(tmax[level, lo], tmax[level, right]),
        np.minimum(tmin[level, lo], tmin[level, right]),
    )
