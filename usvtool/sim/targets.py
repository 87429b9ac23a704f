"""Target ships: their motion over a whole run, computed before it starts.

Targets do not react to the own ship, so each one's positions at every step are known in advance
(one array operation per target, no loop over steps):

- *straight*: from ``start`` on ``heading`` at ``speed``;
- *waypoints*: from ``start`` (when given) through the waypoints at ``speed``, then on along
  the last leg's course;
- *track*: a CSV file of ``t`` with ``x,y`` (map metres) or ``lon,lat``, replayed with linear
  interpolation the way AIS tracks are; before its first time the ship waits at the first
  position, after its last at the last one.

Noise (``heading_sd`` degrees, ``speed_sd`` m/s) perturbs each step's velocity: its direction by
a normal draw of ``heading_sd`` and its size by one of ``speed_sd`` (at least zero), the
positions then following the perturbed velocities, so that the track wanders the way a real
ship's does. Draws come from the run's seeded generator, target by target.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from usvtool.errors import UsvError, check_input_file


@dataclass(frozen=True)
class Course:
    """One target's nominal motion, in map metres and mathematical radians."""

    start: np.ndarray | None  # (2,)
    heading: float  # rad
    speed: float  # m/s
    waypoints: np.ndarray | None = None  # (m, 2)
    track: tuple[np.ndarray, np.ndarray] | None = None  # t (p,), xy (p, 2)
    heading_sd: float = 0.0  # rad
    speed_sd: float = 0.0  # m/s


def positions(course: Course, times: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """The target's positions ``(n, 2)`` at ``times`` (equally spaced, from 0)."""
    if course.track is not None:
        t, xy = course.track
        nominal = np.column_stack([np.interp(times, t, xy[:, 0]), np.interp(times, t, xy[:, 1])])
    elif course.waypoints is not None:
        nominal = _along(course, times)
    else:
        direction = np.array([np.cos(course.heading), np.sin(course.heading)])
        nominal = course.start + course.speed * times[:, None] * direction
    if course.heading_sd == 0 and course.speed_sd == 0 or len(times) < 2:
        return nominal
    step = np.diff(nominal, axis=0)
    turn = rng.normal(0.0, course.heading_sd, len(step)) if course.heading_sd else 0.0
    scale = rng.normal(0.0, course.speed_sd, len(step)) if course.speed_sd else 0.0
    dt = times[1] - times[0]
    length = np.maximum(np.hypot(step[:, 0], step[:, 1]) + scale * dt, 0.0)
    angle = np.arctan2(step[:, 1], step[:, 0]) + turn
    moved = length[:, None] * np.column_stack([np.cos(angle), np.sin(angle)])
    return np.vstack([nominal[:1], nominal[0] + np.cumsum(moved, axis=0)])


def _along(course: Course, times: np.ndarray) -> np.ndarray:
    points = course.waypoints
    if course.start is not None:
        points = np.vstack([course.start, points])
    legs = np.diff(points, axis=0)
    lengths = np.hypot(legs[:, 0], legs[:, 1]) if len(legs) else np.zeros(0)
    along = np.concatenate([[0.0], np.cumsum(lengths)])
    s = course.speed * times
    out = np.column_stack([np.interp(s, along, points[:, 0]), np.interp(s, along, points[:, 1])])
    beyond = s > along[-1]
    if beyond.any():
        if len(legs) and lengths[-1] > 0:
            direction = legs[-1] / lengths[-1]
        else:
            direction = np.array([np.cos(course.heading), np.sin(course.heading)])
        out[beyond] = points[-1] + (s[beyond] - along[-1])[:, None] * direction
    return out


def read_track(path: Path, to_map=None) -> tuple[np.ndarray, np.ndarray, str]:
    """(t, xy, columns) of a track CSV: ``t,x,y`` in map metres or ``t,lon,lat`` (then
    ``to_map(lon, lat)`` converts, and is required)."""
    check_input_file(path)
    with open(path, newline="", encoding="utf-8") as f:
        reader = csv.reader(f)
        try:
            rows = list(reader)
        except csv.Error as exc:  # a field past the csv module's limit (128 KiB), a NUL
            raise UsvError(f"{path}: line {reader.line_num}: not a track's CSV ({exc})") from None
        except UnicodeDecodeError:
            raise UsvError(f"{path}: not UTF-8 text: not a track's CSV") from None
    header = [h.strip().lower() for h in rows[0]] if rows else []
    columns = next((c for c in (["t", "x", "y"], ["t", "lon", "lat"]) if header[:3] == c), None)
    if columns is None:
        raise UsvError(f"{path}: a track's header is t,x,y or t,lon,lat, not {','.join(header)}")
    values = []
    for number, row in enumerate(rows[1:], start=2):
        try:
            values.append([float(row[i]) for i in range(3)])
        except (ValueError, IndexError):
            raise UsvError(f"{path}: line {number}: three numbers expected, not {row}") from None
    data = np.array(values, float).reshape(-1, 3)
    if len(data) < 2:
        raise UsvError(f"{path}: a track needs at least two rows")
    if not np.isfinite(data).all():
        raise UsvError(f"{path}: a track's values must be finite")
    if (np.diff(data[:, 0]) <= 0).any():
        bad = int(np.argmax(np.diff(data[:, 0]) <= 0)) + 3
        raise UsvError(f"{path}: line {bad}: t must increase")
    xy = data[:, 1:]
    if columns[1] == "lon":
        if to_map is None:
            raise UsvError(f"{path}: a lon/lat track needs a map with a CRS")
        xy = np.column_stack(to_map(xy[:, 0], xy[:, 1]))
    return data[:, 0], xy, columns[1]
