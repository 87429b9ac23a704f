"""A simulated encounter and its files: trace CSV, events JSON, tracks GeoJSON.

The contract between the simulation and the stages after it (metrics, reports).

Trace CSV (:func:`write_trace`, :func:`read_trace`)
    UTF-8, ``\\n`` line ends, the header ``t,ship,x,y,heading,speed,yaw_rate``, then one row per
    ship and time step. A step is the run of rows sharing one ``t``; the own ship is named
    ``own`` and comes first in every step, and every step holds the same ships (the writer
    keeps one order). Units: ``t`` seconds, strictly increasing from step to step; ``x``, ``y``
    map metres (x east, y north, in the grid's CRS, or the local frame of a grid without one);
    ``heading`` compass degrees in [0, 360) (0 = north, clockwise; :mod:`usvtool.geodesy`
    converts); ``speed`` m/s; ``yaw_rate`` deg/s (positive turning clockwise, to starboard).
    Numbers are fixed-point with :data:`DECIMALS` decimals (t, x, y, heading 3; speed and
    yaw_rate 4), no exponent and no negative zero, so the same run gives the same bytes. Ship
    names are non-empty and hold no comma, quote or line break.
Events JSON (:func:`write_events`, :func:`read_events`)
    One JSON object, whatever the simulation reports (encounters, COLREGs classifications,
    collisions, arrival); keys sorted, indent 2, a trailing newline; NaN and infinity are
    refused (not JSON).
Tracks GeoJSON (:func:`tracks_geojson`, :func:`write_tracks`)
    A FeatureCollection with one LineString feature per ship, in the trace's order, its
    property ``ship`` the name. With a CRS the coordinates are WGS84 lon/lat (RFC 7946) with 7
    decimals (about 1 cm); without one they are the trace's local metres (3 decimals) and the
    collection has the foreign member ``"frame": "local"`` (the convention of the GeoJSON
    obstacle maps). A one-step trace repeats its position (a LineString has two or more).

Every reader refuses a bad file with one :class:`~usvtool.errors.UsvError` line naming the file
and the line and column at fault. Every writer builds its text first (refusing bad values
before any file exists), then writes it atomically (:mod:`usvtool.atomic`); given a path handed
out by :class:`usvtool.atomic.staged` it writes that path in place, so a command stages its
outputs together, all renamed at the end or none::

    with staged(trace_path, events_path, tracks_path) as (trace_tmp, events_tmp, tracks_tmp):
        write_trace(trace_tmp, trace)
        write_events(events_tmp, events)
        if tracks_tmp:
            write_tracks(tracks_tmp, trace, grid.crs)

>>> tr = Trace.from_states([0.0, 0.1], ["own", "target"],
...                        [[[0, 0, 0, 4, 0], [50, 100, 180, 3, 0]],
...                         [[0, 0.4, 0, 4, 0.5], [50, 99.7, 180, 3, 0]]])
>>> print(format_trace(tr), end="")
t,ship,x,y,heading,speed,yaw_rate
0.000,own,0.000,0.000,0.000,4.0000,0.0000
0.000,target,50.000,100.000,180.000,3.0000,0.0000
0.100,own,0.000,0.400,0.000,4.0000,0.5000
0.100,target,50.000,99.700,180.000,3.0000,0.0000
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from dataclasses import dataclass

import numpy as np

from usvtool.angles import wrap360
from usvtool.errors import UsvError, check_input_file

HEADER = ("t", "ship", "x", "y", "heading", "speed", "yaw_rate")
#: The state of a ship at a step, in the order of :meth:`Trace.states`.
STATE = ("x", "y", "heading", "speed", "yaw_rate")
OWN = "own"
#: Decimals written per column.
DECIMALS = {"t": 3, "x": 3, "y": 3, "heading": 3, "speed": 4, "yaw_rate": 4}
LONLAT_DECIMALS = 7
LOCAL_DECIMALS = 3
_BAD_NAME = (",", '"', "\n", "\r")


@dataclass(frozen=True, eq=False)
class Trace:
    """Ship states over time: ``t`` ``(n,)``; ``x``, ``y``, ``heading``, ``speed``, ``yaw_rate``
    ``(n, k)`` for the ``k`` ships of ``ships`` (own first), units as in the module docstring.

    Checked on construction (:class:`UsvError`): shapes, at least one step, ``t`` strictly
    increasing, every value finite, names unique and writable with ``own`` first.
    """

    t: np.ndarray
    ships: tuple[str, ...]
    x: np.ndarray
    y: np.ndarray
    heading: np.ndarray
    speed: np.ndarray
    yaw_rate: np.ndarray

    def __post_init__(self):
        t = np.asarray(self.t, float)
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "ships", tuple(str(s) for s in self.ships))
        n, k = t.size, len(self.ships)
        if t.ndim != 1 or n == 0:
            raise UsvError(f"trace: t must be a non-empty 1-D array, not of shape {t.shape}")
        for name in STATE:
            a = np.asarray(getattr(self, name), float)
            if a.shape != (n, k):
                raise UsvError(f"trace: {name} has shape {a.shape}, expected ({n}, {k})")
            if not np.isfinite(a).all():
                raise UsvError(f"trace: {name} holds NaN or infinite values")
            object.__setattr__(self, name, a)
        if not np.isfinite(t).all() or (np.diff(t) <= 0).any():
            raise UsvError("trace: t must be finite and strictly increasing")
        _check_ships(self.ships, "trace")

    @classmethod
    def from_states(cls, t, ships, states) -> Trace:
        """A trace from ``states`` ``(n, k, 5)``: x, y, heading, speed, yaw_rate per step and
        ship (the order of :data:`STATE`)."""
        s = np.asarray(states, float)
        if s.ndim != 3 or s.shape[2] != len(STATE):
            raise UsvError(f"trace: states must have shape (n, k, 5), not {s.shape}")
        return cls(np.asarray(t, float), tuple(ships), *np.moveaxis(s, 2, 0))

    @property
    def n_steps(self) -> int:
        return int(self.t.size)

    def states(self) -> np.ndarray:
        """The states ``(n, k, 5)`` (the inverse of :meth:`from_states`)."""
        return np.stack([getattr(self, name) for name in STATE], axis=2)

    def ship(self, name: str) -> np.ndarray:
        """The states ``(n, 5)`` of ship ``name``."""
        return self.states()[:, self.ships.index(name)]


# --- trace CSV ------------------------------------------------------------------------------


def format_trace(trace: Trace) -> str:
    """The trace CSV text (module docstring)."""
    n, k = trace.x.shape
    t = _fixed(trace.t, DECIMALS["t"])
    if len(set(t)) != n:
        i = next(i for i in range(1, n) if t[i] == t[i - 1])
        raise UsvError(
            f"trace: steps {i - 1} and {i} both write t {t[i]}: steps must be at least "
            f"{10 ** -DECIMALS['t']:g} s apart"
        )
    heading = wrap360(trace.heading)
    columns = []
    for name, values in zip(STATE, (trace.x, trace.y, heading, trace.speed, trace.yaw_rate),
                            strict=True):  # fmt: skip
        text = _fixed(values.ravel(), DECIMALS[name])
        if name == "heading":  # 359.9996 rounds to 360.000, the same direction as 0
            full = f"{360:.{DECIMALS['heading']}f}"
            zero = f"{0:.{DECIMALS['heading']}f}"
            text = [zero if s == full else s for s in text]
        columns.append(text)
    times = [text for text in t for _ in range(k)]
    names = trace.ships * n
    lines = [",".join(HEADER)]
    lines += [",".join(row) for row in zip(times, names, *columns, strict=True)]
    return "\n".join(lines) + "\n"


def write_trace(path: str | os.PathLike, trace: Trace) -> None:
    """Write ``trace`` as a trace CSV, atomically (headings are written modulo 360)."""
    from usvtool.atomic import write_text

    text = format_trace(trace)
    write_text(path, text)


def read_trace(path: str | os.PathLike) -> Trace:
    """Read and check a trace CSV (module docstring); :class:`UsvError` names the line at fault.

    Lines are counted from 1, the header being line 1.
    """
    check_input_file(path)
    try:
        with open(path, encoding="utf-8", newline="") as f:
            text = f.read()
    except UnicodeDecodeError as exc:
        raise UsvError(f"{path}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    well_formed = _well_formed(text)
    if well_formed is not None:
        return well_formed
    rows = csv.reader(io.StringIO(text, newline=""))
    header = next(rows, None)
    if header != list(HEADER):
        got = ",".join(header) if header is not None else ""
        raise UsvError(f"{path}: line 1: the header must be {','.join(HEADER)!r}, not {got!r}")
    steps: list[tuple[int, str, float, dict[str, list[float]]]] = []  # (line, t text, t, ships)
    first: tuple[str, ...] | None = None
    for number, row in enumerate(rows, start=2):
        if len(row) != len(HEADER):
            raise UsvError(
                f"{path}: line {number}: {len(row)} fields, expected {len(HEADER)} "
                f"({','.join(HEADER)})"
            )
        t_text, ship = row[0], row[1]
        t = _number(path, number, "t", t_text)
        state = [_number(path, number, n, v) for n, v in zip(STATE, row[2:], strict=True)]
        heading = state[STATE.index("heading")]
        if not 0.0 <= heading < 360.0:
            raise UsvError(f"{path}: line {number}, column heading: {row[4]} is not in [0, 360)")
        if not ship or any(c in ship for c in _BAD_NAME):
            raise UsvError(f"{path}: line {number}, column ship: {ship!r} is not a ship name")
        if not steps or t != steps[-1][2]:  # a new step
            if steps:
                if t < steps[-1][2]:
                    raise UsvError(
                        f"{path}: line {number}, column t: {t_text} is before the previous "
                        f"step's t {steps[-1][1]} (t must increase)"
                    )
                first = _close_step(path, steps[-1], first)
            if ship != OWN:
                raise UsvError(
                    f"{path}: line {number}, column ship: the step at t {t_text} starts with "
                    f"{ship!r}; the own ship ({OWN!r}) must come first"
                )
            steps.append((number, t_text, t, {}))
        ships = steps[-1][3]
        if ship in ships:
            raise UsvError(f"{path}: line {number}, column ship: {ship!r} twice at t {t_text}")
        if first is not None and ship not in first:
            raise UsvError(
                f"{path}: line {number}, column ship: {ship!r} at t {t_text} is not in the "
                f"first step ({', '.join(first)})"
            )
        ships[ship] = state
    if not steps:
        raise UsvError(f"{path}: no rows after the header")
    first = _close_step(path, steps[-1], first)
    states = np.array([[step[3][name] for name in first] for step in steps], float)
    return Trace.from_states([step[2] for step in steps], first, states)


def _well_formed(text: str) -> Trace | None:
    """The trace of a text that follows the format as the writer writes it (every step the
    first step's ships in its order), read at once: the numbers by NumPy's C parser (correctly
    rounded, as ``float``), the checks on whole columns. None for anything else, which the
    line-by-line reader then reads or refuses naming the line: this path only makes the common
    case fast (a 450 s run of 4 ships, 18 000 rows: about ten times faster), never decides
    what is refused."""
    head, _, body = text.partition("\n")
    if head != ",".join(HEADER) or not body or "\r" in body or '"' in body:
        return None
    lines = body[:-1].split("\n") if body.endswith("\n") else body.split("\n")
    names = [line.split(",", 2)[1] if line.count(",") == len(HEADER) - 1 else "" for line in lines]
    if "" in names:
        return None
    try:
        numbers = np.loadtxt(io.StringIO(body), delimiter=",", usecols=(0, 2, 3, 4, 5, 6),
                             dtype=float, ndmin=2, comments=None)  # fmt: skip
    except ValueError:
        return None
    if numbers.shape != (len(lines), 6) or not np.isfinite(numbers).all():
        return None
    t = numbers[:, 0]
    k = int(np.argmax(t != t[0])) if (t != t[0]).any() else t.size  # the first step's ships
    first = tuple(names[:k])
    if (t.size % k or first[0] != OWN or len(set(first)) != k
            or any(c in n for n in first for c in _BAD_NAME)):  # fmt: skip
        return None
    steps = t.size // k
    if names != list(first) * steps:
        return None
    t = t.reshape(steps, k)
    heading = numbers[:, 3]
    if (t != t[:, :1]).any() or (np.diff(t[:, 0]) <= 0).any() or (heading < 0).any() or (
            heading >= 360).any():  # fmt: skip
        return None
    return Trace.from_states(t[:, 0], first, numbers[:, 1:].reshape(steps, k, len(STATE)))


def _close_step(path, step, first: tuple[str, ...] | None) -> tuple[str, ...]:
    """The ships of the first step; a later step must hold them all."""
    number, t_text, _, ships = step
    if first is None:
        return tuple(ships)
    missing = [name for name in first if name not in ships]
    if missing:
        raise UsvError(
            f"{path}: line {number}: the step at t {t_text} lacks ship "
            f"{', '.join(map(repr, missing))} (the first step has {', '.join(first)})"
        )
    return first


def _number(path, line: int, column: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise UsvError(f"{path}: line {line}, column {column}: {text!r} is not a number") from None
    if not math.isfinite(value):
        raise UsvError(f"{path}: line {line}, column {column}: {text!r} is not a finite number")
    return value


def _fixed(values, decimals: int) -> list[str]:
    """Fixed-point texts with ``decimals`` decimals, never ``-0.000``."""
    negative_zero = f"-{0:.{decimals}f}"
    zero = negative_zero[1:]
    texts = [f"{v:.{decimals}f}" for v in np.asarray(values, float).tolist()]
    return [zero if s == negative_zero else s for s in texts]


def _check_ships(ships: tuple[str, ...], where: str) -> None:
    if not ships or ships[0] != OWN:
        raise UsvError(f"{where}: the first ship must be {OWN!r}, not {ships[0]!r}"
                       if ships else f"{where}: no ship")  # fmt: skip
    if len(set(ships)) != len(ships):
        raise UsvError(f"{where}: ship names must be unique: {', '.join(ships)}")
    for name in ships:
        if not name or any(c in name for c in _BAD_NAME):
            raise UsvError(f"{where}: {name!r} is not a ship name (non-empty, no comma, quote "
                           "or line break)")  # fmt: skip


# --- events JSON ----------------------------------------------------------------------------


def format_events(events: dict, where: str = "events") -> str:
    """The events JSON text: keys sorted, indent 2, a trailing newline; NaN refused."""
    if not isinstance(events, dict):
        raise UsvError(f"{where}: events must be a dict, not {type(events).__name__}")
    try:
        text = json.dumps(events, sort_keys=True, indent=2, allow_nan=False, default=_plain)
    except ValueError:
        raise UsvError(f"{where}: events hold NaN or an infinite number (not JSON)") from None
    except TypeError as exc:
        raise UsvError(f"{where}: events are not JSON data ({exc})") from None
    return text + "\n"


def write_events(path: str | os.PathLike, events: dict) -> None:
    """Write ``events`` (a dict of JSON data; NumPy values allowed) as events JSON, atomically."""
    from usvtool.atomic import write_text

    write_text(path, format_events(events, os.fspath(path)))


def read_events(path: str | os.PathLike) -> dict:
    """Read an events JSON file: one JSON object (NaN and infinity refused)."""
    check_input_file(path)

    def refuse(name):
        raise ValueError(f"{name} is not JSON")

    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f, parse_constant=refuse)
    except json.JSONDecodeError as exc:
        raise UsvError(
            f"{path}: line {exc.lineno}, column {exc.colno}: not JSON ({exc.msg})"
        ) from None
    except (UnicodeDecodeError, ValueError) as exc:
        raise UsvError(f"{path}: not an events JSON file ({exc})") from None
    if not isinstance(data, dict):
        raise UsvError(f"{path}: events must be a JSON object, not {_json_kind(data)}")
    return data


def _plain(value):
    """``json`` default: NumPy arrays and scalars as Python values; anything else refused."""
    if isinstance(value, np.ndarray | np.generic):
        return value.tolist()
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


def _json_kind(value) -> str:
    kinds = {list: "an array", str: "a string", bool: "a boolean", type(None): "null"}
    return kinds.get(type(value), "a number")


# --- tracks GeoJSON -------------------------------------------------------------------------


def tracks_geojson(trace: Trace, crs=None) -> dict:
    """The ships' tracks as a GeoJSON FeatureCollection (module docstring): lon/lat via
    :mod:`usvtool.geodesy` when ``crs`` is given, else local metres with ``"frame": "local"``."""
    features = []
    for j, name in enumerate(trace.ships):
        x, y = trace.x[:, j], trace.y[:, j]
        if crs is None:
            coords = np.column_stack([x, y]).round(LOCAL_DECIMALS)
        else:
            from usvtool.geodesy import map_to_lonlat

            lon, lat = map_to_lonlat(crs, x, y)
            coords = np.column_stack([lon, lat]).round(LONLAT_DECIMALS)
        if len(coords) == 1:
            coords = np.vstack([coords, coords])
        features.append(
            {
                "type": "Feature",
                "geometry": {"type": "LineString", "coordinates": (coords + 0.0).tolist()},
                "properties": {"ship": name},
            }
        )
    collection: dict = {"type": "FeatureCollection"}
    if crs is None:
        collection["frame"] = "local"
    collection["features"] = features
    return collection


def write_tracks(path: str | os.PathLike, trace: Trace, crs=None) -> None:
    """Write :func:`tracks_geojson` compactly (one line and a newline), atomically."""
    from usvtool.atomic import write_text

    text = json.dumps(tracks_geojson(trace, crs), separators=(",", ":"))
    write_text(path, text + "\n")
