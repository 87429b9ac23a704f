"""Vessel tracks: the tidy table of AIS fixes, the contract between reading AIS and what uses it.

One row per fix, sorted by ``track`` then ``time``; the columns (:data:`COLUMNS`):

============  ========================================================================
``mmsi``      the vessel's MMSI, an integer in 1 … 999 999 999
``time``      UTC, integer nanoseconds since the Unix epoch (``int64``; a parquet file
              stores it as ``timestamp[ns, tz=UTC]``, a CSV file as ISO 8601 text ending
              in ``Z``, e.g. ``2022-01-03T00:00:07Z``); strictly increasing within a track
``lon, lat``  WGS84 degrees, lon in [-180, 180], lat in [-90, 90]
``sog``       speed over ground, knots (>= 0), as reported; NaN: not available
``cog``       course over ground, compass degrees in [0, 360); NaN: not available
``heading``   true heading, compass degrees in [0, 360); NaN: not available
``length``    overall length, metres (> 0); NaN: unknown
``beam``      beam, metres (> 0); NaN: unknown
``name``      the vessel's name, ``""`` when unknown (no line break)
``ship_type`` AIS ship and cargo type (ITU-R M.1371 table 53), 0 = not available, <= 255
``track``     track id (>= 0): one vessel's fixes with no gap longer than the reader's
              ``--max-gap``; every fix of a track has the same ``mmsi``
============  ========================================================================

In memory a :class:`Tracks` holds one NumPy array per column (``name`` an object array of
``str``). NaN is written as an empty field in CSV and as null in parquet, and read back as NaN.

Files: ``.parquet`` (pyarrow) or ``.csv`` (UTF-8, the header :data:`COLUMNS` in this order; no
quotes when no name needs any, else every text quoted; a name a spreadsheet would take for a
formula written behind a ``'`` and read back without it: :func:`spreadsheet_safe`; a byte order
mark accepted). :func:`read_tracks` refuses a bad file
with one :class:`~usvtool.errors.UsvError` line naming the file, the line (CSV; the header is
line 1) or row (parquet, from 1) and the column at fault; :func:`write_tracks` checks the table
first (a :class:`Tracks` is checked when made), then writes atomically (:mod:`usvtool.atomic`; a
path handed out by :class:`usvtool.atomic.staged` is written in place).

>>> t = Tracks.from_columns(mmsi=[366000001, 366000001], time=[0, 60_000_000_000],
...                         lon=[-74.0, -73.99], lat=[40.6, 40.6], track=[0, 0])
>>> t.n_rows, t.n_tracks, float(t.sog[0]), t.name[0] == ""
(2, 1, nan, True)
>>> format_time(t.time)
['1970-01-01T00:00:00Z', '1970-01-01T00:01:00Z']
"""

from __future__ import annotations

import csv
import io
import os
import re
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from usvtool.errors import UsvError, check_input_file

COLUMNS = ("mmsi", "time", "lon", "lat", "sog", "cog", "heading", "length", "beam", "name",
           "ship_type", "track")  # fmt: skip
#: The columns of reals (NaN allowed in all but lon and lat).
REALS = ("lon", "lat", "sog", "cog", "heading", "length", "beam")
INTEGERS = ("mmsi", "time", "ship_type", "track")
MAX_MMSI = 999_999_999
#: Nanoseconds in a second.
NS = 1_000_000_000
SUFFIXES = (".parquet", ".csv")
#: A name the CSV writer must quote (without any, no field is quoted): a separator (``;`` too,
#: a spreadsheet's in some locales), a quote, white space or ``'`` first, white space last.
_NEEDS_QUOTES = re.compile(r'[,;"]|^[\s\']|\s$')
#: A text a spreadsheet takes for a formula: one starting with ``= + - @``, a tab or a carriage
#: return (OWASP, "CSV Injection"), after any ``'`` (so that the ``'`` put before it is told
#: from one of the text's own).
_FORMULA = "^'*[=+\\-@\t\r]"
#: Key of the parquet schema's metadata naming the contract (and its version).
PARQUET_KEY = b"usvtool.tracks"


@dataclass(frozen=True, eq=False)
class Tracks:
    """The tidy tracks table (module docstring); checked on construction (:class:`UsvError`
    naming the row and column)."""

    mmsi: np.ndarray
    time: np.ndarray
    lon: np.ndarray
    lat: np.ndarray
    sog: np.ndarray
    cog: np.ndarray
    heading: np.ndarray
    length: np.ndarray
    beam: np.ndarray
    name: np.ndarray
    ship_type: np.ndarray
    track: np.ndarray

    def __post_init__(self):
        for f in fields(self):
            object.__setattr__(self, f.name, _as_column(f.name, getattr(self, f.name)))
        fault = check_columns(self)
        if fault is not None:
            row, column, problem = fault
            raise UsvError(f"tracks: row {row + 1}, column {column}: {problem}")

    @classmethod
    def from_columns(cls, **columns) -> Tracks:
        """A table from the columns given; ``mmsi``, ``time``, ``lon``, ``lat`` and ``track``
        are required, the others default to not available."""
        missing = [c for c in ("mmsi", "time", "lon", "lat", "track") if c not in columns]
        unknown = sorted(set(columns) - set(COLUMNS))
        if missing or unknown:
            raise UsvError(f"tracks: missing columns {missing}, unknown columns {unknown}")
        n = len(np.asarray(columns["mmsi"]))
        defaults = {"name": np.full(n, "", object), "ship_type": np.zeros(n, np.int64)}
        return cls(**{c: columns[c] if c in columns else defaults.get(c, np.full(n, np.nan))
                      for c in COLUMNS})  # fmt: skip

    @property
    def n_rows(self) -> int:
        return int(self.mmsi.size)

    @property
    def n_tracks(self) -> int:
        return int(np.unique(self.track).size)

    def take(self, index) -> Tracks:
        """The rows ``index`` (a boolean mask or sorted indices), checked again."""
        return Tracks(**{c: getattr(self, c)[index] for c in COLUMNS})

    def track_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """``(first, stop)`` row indices of each track, in row order (track ``i`` is the rows
        ``first[i]:stop[i]``)."""
        n = self.n_rows
        if n == 0:
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
        first = np.flatnonzero(np.r_[True, self.track[1:] != self.track[:-1]])
        return first, np.r_[first[1:], n]


def _as_column(name: str, values) -> np.ndarray:
    if name == "name":
        a = np.asarray(values, dtype=object)
        return a.ravel() if a.ndim != 1 else a
    if name in INTEGERS:
        a = np.asarray(values)
        if a.dtype.kind == "f":
            if not np.isfinite(a).all() or (a != np.round(a)).any():
                raise UsvError(f"tracks: column {name} must hold integers")
        elif a.dtype.kind not in "iub":
            raise UsvError(f"tracks: column {name} must hold integers, not {a.dtype}")
        return a.astype(np.int64).ravel()
    return np.asarray(values, dtype=float).ravel()


def check_columns(t) -> tuple[int, str, str] | None:
    """The first fault of the columns of ``t`` (any object with the :data:`COLUMNS` as
    attributes) as ``(row index, column, problem)``, or None: the module docstring's rules."""
    n = t.mmsi.size
    for c in COLUMNS:
        if getattr(t, c).size != n:
            return 0, c, f"{getattr(t, c).size} values, mmsi has {n}"
    checks = (
        ("mmsi", (t.mmsi < 1) | (t.mmsi > MAX_MMSI), f"not an MMSI (1 … {MAX_MMSI})"),
        ("lon", ~(np.abs(t.lon) <= 180), "not a longitude in [-180, 180]"),
        ("lat", ~(np.abs(t.lat) <= 90), "not a latitude in [-90, 90]"),
        ("sog", ~(t.sog >= 0) & ~np.isnan(t.sog) | np.isinf(t.sog), "not a speed >= 0 (kn)"),
        ("cog", ~((t.cog >= 0) & (t.cog < 360)) & ~np.isnan(t.cog), "not a course in [0, 360)"),
        ("heading", ~((t.heading >= 0) & (t.heading < 360)) & ~np.isnan(t.heading),
         "not a heading in [0, 360)"),
        ("length", ~(t.length > 0) & ~np.isnan(t.length) | np.isinf(t.length),
         "not a length > 0 (m)"),
        ("beam", ~(t.beam > 0) & ~np.isnan(t.beam) | np.isinf(t.beam), "not a beam > 0 (m)"),
        ("ship_type", (t.ship_type < 0) | (t.ship_type > 255), "not a ship type (0 … 255)"),
        ("track", t.track < 0, "not a track id >= 0"),
    )  # fmt: skip
    faults = []
    for column, bad, problem in checks:
        if bad.any():
            i = int(np.argmax(bad))
            faults.append((i, column, f"{_show(getattr(t, column)[i])} is {problem}"))
    names_bad = []
    if any(not isinstance(s, str) or "\n" in s or "\r" in s for s in set(t.name.tolist())):
        names_bad = [i for i, s in enumerate(t.name) if not isinstance(s, str) or "\n" in s
                     or "\r" in s]  # fmt: skip
    if names_bad:
        faults.append((names_bad[0], "name", f"{_show(t.name[names_bad[0]])} is not a name "
                                             "(text without line breaks)"))  # fmt: skip
    if n > 1:
        same = t.track[1:] == t.track[:-1]
        order = (t.track[1:] < t.track[:-1]) | same & (t.time[1:] <= t.time[:-1])
        if order.any():
            i = int(np.argmax(order)) + 1
            column = "track" if t.track[i] < t.track[i - 1] else "time"
            faults.append((i, column, "rows must be sorted by track, then strictly by time "
                                      "within a track"))  # fmt: skip
        mixed = same & (t.mmsi[1:] != t.mmsi[:-1])
        if mixed.any():
            i = int(np.argmax(mixed)) + 1
            faults.append((i, "mmsi", f"track {t.track[i]} holds two MMSIs "
                                      f"({t.mmsi[i - 1]}, {t.mmsi[i]})"))  # fmt: skip
    return min(faults, key=lambda f: f[0]) if faults else None


def _show(value) -> str:
    text = repr(value.item() if hasattr(value, "item") else value)
    return text if len(text) <= 40 else text[:37] + "..."


# --- time text ------------------------------------------------------------------------------


def format_time(ns) -> list[str]:
    """ISO 8601 UTC texts of ``ns`` (nanoseconds since the epoch): whole seconds when every
    value is whole, else milliseconds or nanoseconds, whichever is exact.

    >>> format_time([1_641_168_007_500_000_000])
    ['2022-01-03T00:00:07.500Z']
    """
    ns = np.asarray(ns, np.int64)
    unit = "s" if not (ns % NS).any() else "ms" if not (ns % 1_000_000).any() else "ns"
    return [s + "Z" for s in np.datetime_as_string(ns.astype("datetime64[ns]"), unit=unit)]


# --- files ----------------------------------------------------------------------------------


def spreadsheet_safe(texts):
    """The texts (a pyarrow string array, or a sequence of ``str``) a spreadsheet shows as
    text: each that starts with a formula character (``= + - @``, tab, carriage return; after
    any ``'``) behind one more ``'`` (OWASP's "CSV Injection"); the others as they are. The one
    neutralisation of every CSV writer of tracks and encounters (their writers quote a field as
    RFC 4180 says); :func:`spreadsheet_text` undoes it.

    >>> spreadsheet_safe(["=SUM(A1)", "@A1", "+1-2", "'-cmd", "O'HARA", "TUG -7"])
    ["'=SUM(A1)", "'@A1", "'+1-2", "''-cmd", "O'HARA", 'TUG -7']
    """
    import pyarrow as pa
    import pyarrow.compute as pc

    array = texts if isinstance(texts, pa.Array | pa.ChunkedArray) else pa.array(
        list(texts), pa.string())  # fmt: skip
    safe = pc.if_else(pc.match_substring_regex(array, _FORMULA),
                      pc.binary_join_element_wise("'", array, ""), array)  # fmt: skip
    return safe if array is texts else safe.to_pylist()


def spreadsheet_text(texts):
    """The texts (a pyarrow string array, or a sequence of ``str``) as :func:`spreadsheet_safe`
    had them: the ``'`` it put before a formula character removed.

    >>> spreadsheet_text(["'=1", "''-cmd", "'quote", "=2"])
    ['=1', "'-cmd", "'quote", '=2']
    """
    import pyarrow as pa
    import pyarrow.compute as pc

    array = texts if isinstance(texts, pa.Array | pa.ChunkedArray) else pa.array(
        list(texts), pa.string())  # fmt: skip
    added = pc.match_substring_regex(array, "'" + _FORMULA[1:])
    text = pc.if_else(added, pc.utf8_slice_codeunits(array, 1), array)
    return text if array is texts else text.to_pylist()



def check_suffix(path, option: str = "") -> str:
    """The suffix of a tracks file (.parquet or .csv); one line naming ``option`` and the path
    for another."""
    suffix = Path(path).suffix.lower()
    if suffix not in SUFFIXES:
        raise UsvError(f"{option + ' ' if option else ''}{path}: a tracks file is .parquet or "
                       f".csv, not {suffix or 'without a suffix'}")  # fmt: skip
    return suffix


def to_arrow(tracks: Tracks):
    """The table as a pyarrow Table (time as ``timestamp[ns, tz=UTC]``, NaN as null)."""
    import pyarrow as pa

    arrays = {}
    for c in COLUMNS:
        values = getattr(tracks, c)
        if c == "time":
            arrays[c] = pa.array(values, pa.int64()).cast(pa.timestamp("ns", "UTC"))
        elif c == "name":
            arrays[c] = pa.array(values.tolist(), pa.string())
        elif c in REALS:
            arrays[c] = pa.array(values, pa.float64(), from_pandas=True)
        else:
            arrays[c] = pa.array(values, pa.int64())
    table = pa.table(arrays)
    return table.replace_schema_metadata({PARQUET_KEY: b"1"})


def write_tracks(path: str | os.PathLike, tracks: Tracks) -> None:
    """Write ``tracks`` as parquet or CSV (by the suffix of ``path``), atomically."""
    import pyarrow as pa

    from usvtool.atomic import atomic_path

    suffix = check_suffix(path)
    table = to_arrow(tracks)
    names = spreadsheet_safe(table.column("name"))
    with atomic_path(path) as tmp:
        if suffix == ".parquet":
            import pyarrow.parquet as pq

            pq.write_table(table, tmp, compression="zstd")
        else:
            import pyarrow.csv as pcsv

            table = table.set_column(1, "time", pa.array(format_time(tracks.time), pa.string()))
            table = table.set_column(COLUMNS.index("name"), "name", names)
            plain = not any(_NEEDS_QUOTES.search(s) for s in names.to_pylist())
            with open(tmp, "wb") as f:
                f.write((",".join(COLUMNS) + "\n").encode())
                pcsv.write_csv(table, f, pcsv.WriteOptions(
                    include_header=False, quoting_style="none" if plain else "needed"))


def read_tracks(path: str | os.PathLike) -> Tracks:
    """Read and check a tracks file (module docstring); one line naming the file, line or row,
    and column at fault."""
    check_input_file(path)
    if check_suffix(path) == ".parquet":
        table = _read_parquet(path)
        where = lambda row: f"row {row + 1}"  # noqa: E731
    else:
        from usvtool.csvtable import line_of

        table = _read_csv(path)
        where = lambda row: f"line {line_of(path, row)}"  # noqa: E731
    columns = {}
    for c in COLUMNS:
        try:
            columns[c] = _numpy(c, table.column(c))
        except _Fault as exc:
            raise UsvError(f"{path}: {where(exc.row)}, column {c}: {exc.problem}") from None
    fault = check_columns(_Columns(columns))
    if fault is not None:
        row, column, problem = fault
        raise UsvError(f"{path}: {where(row)}, column {column}: {problem}")
    return Tracks(**columns)


class _Fault(Exception):
    def __init__(self, row: int, problem: str):
        self.row, self.problem = row, problem


class _Columns:
    def __init__(self, columns: dict):
        self.__dict__.update(columns)


def _numpy(column: str, array) -> np.ndarray:
    """A column of the file as NumPy; :class:`_Fault` for a missing integer."""
    import pyarrow as pa
    import pyarrow.compute as pc

    if column == "name":
        return np.array(pc.fill_null(array.cast(pa.string()), "").to_pylist(), dtype=object)
    if column in REALS:
        values = array.to_numpy(zero_copy_only=False).astype(float)
        return values
    if array.null_count:
        row = int(np.argmax(array.is_null().to_numpy(zero_copy_only=False)))
        raise _Fault(row, "empty: a value is required")
    return np.asarray(array.to_numpy(zero_copy_only=False), np.int64)


def _read_parquet(path):
    import pyarrow as pa
    import pyarrow.parquet as pq

    try:
        table = pq.read_table(path)
    except (pa.ArrowException, OSError) as exc:
        raise UsvError(f"{path}: not a readable parquet file ({exc})") from None
    _check_names(path, table.column_names, "the columns")
    out = {}
    for c in COLUMNS:
        array = table.column(c)
        kind = array.type
        ok = (
            pa.types.is_timestamp(kind) and kind.tz in (None, "UTC", "Z", "+00:00")
            if c == "time"
            else pa.types.is_string(kind) or pa.types.is_large_string(kind) or
            pa.types.is_dictionary(kind) or pa.types.is_null(kind)
            if c == "name"
            else pa.types.is_floating(kind) or pa.types.is_integer(kind) or pa.types.is_null(kind)
            if c in REALS
            else pa.types.is_integer(kind)
        )  # fmt: skip
        if not ok:
            raise UsvError(f"{path}: column {c}: type {kind} is not that of the contract "
                           "(usvtool/tracks.py)")  # fmt: skip
        if c == "time":
            array = array.cast(pa.timestamp("ns", kind.tz)).cast(pa.int64())
        elif c in REALS:
            array = array.cast(pa.float64())
        out[c] = array
    return pa.table(out)


def _read_csv(path):
    import pyarrow as pa

    from usvtool.csvtable import first_lines, read_table, time_ns

    line = next(iter(first_lines(path, 1)), "").removeprefix("\ufeff")  # a byte order mark
    header = next(csv.reader(io.StringIO(line)), [])
    if header != list(COLUMNS):
        raise UsvError(f"{path}: line 1: the header must be {','.join(COLUMNS)!r}, not "
                       f"{','.join(header)[:200]!r}")  # fmt: skip
    types = {c: pa.float64() for c in REALS} | {c: pa.int64() for c in INTEGERS if c != "time"}
    table = read_table(path, types | {"name": pa.string(), "time": pa.string()})
    ns = time_ns(path, table.column("time"), "time", 1)
    table = table.set_column(table.column_names.index("name"), "name",
                             spreadsheet_text(table.column("name")))  # fmt: skip
    return table.set_column(table.column_names.index("time"), "time", pa.array(ns, pa.int64()))


def _check_names(path, names, what: str) -> None:
    missing = [c for c in COLUMNS if c not in names]
    extra = [c for c in names if c not in COLUMNS]
    if missing or extra:
        raise UsvError(f"{path}: {what} must be {','.join(COLUMNS)}: missing "
                       f"{','.join(missing) or 'none'}, unknown "
                       f"{','.join(extra) or 'none'}")  # fmt: skip
