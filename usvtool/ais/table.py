"""The CSV formats' one reader: named columns of a delimited file into :class:`~.fixes.Fixes`.

Each CSV format (:mod:`.marinecadastre`, :mod:`.dma`, :mod:`.generic`) is a mapping from the
roles below to its header's column names, read here with :mod:`usvtool.csvtable` (a bad value
is refused in one line naming the file, the line and the column). Every row is a position
report carrying its vessel's static data.
"""

from __future__ import annotations

import csv
import io

import numpy as np

from usvtool.ais.fixes import Fixes, from_columns
from usvtool.errors import UsvError
from usvtool.tracks import MAX_MMSI

#: The roles a column may play, and the ones a file must have.
ROLES = ("mmsi", "time", "lon", "lat", "sog", "cog", "heading", "length", "beam", "name",
         "ship_type")  # fmt: skip
REQUIRED = ("mmsi", "time", "lon", "lat")
NUMBERS = ("lon", "lat", "sog", "cog", "heading", "length", "beam")


def header(path, delimiter: str = ",", skip_rows: int = 0) -> list[str]:
    """The column names on line ``skip_rows + 1`` of ``path``."""
    from usvtool.ais.source import first_lines

    lines = first_lines(path, skip_rows + 1)
    if len(lines) <= skip_rows:
        raise UsvError(f"{path}: no header line")
    return next(csv.reader(io.StringIO(lines[skip_rows]), delimiter=delimiter), [])


def read_columns(path, columns: dict[str, str], *, delimiter: str = ",",
                 time_formats: tuple[str, ...] = (), epoch_seconds: bool = False,
                 ship_types: dict[str, int] | None = None,
                 keep: tuple[str, frozenset[str], str] | None = None,
                 bbox: tuple[float, float, float, float] | None = None,
                 guard=None) -> Fixes:  # fmt: skip
    """The fixes of the CSV file ``path`` whose roles (:data:`ROLES`) are the columns
    ``columns`` (role: column name).

    ``time_formats``: ``strptime`` formats tried after ISO 8601; ``epoch_seconds``: a time
    column of numbers is Unix seconds. ``ship_types``: the ship type column is text, read
    through this table (other texts: 0), a number being taken as the code itself. ``keep``:
    ``(column, values, count)``: only rows whose column holds one of the values are fixes, the
    others counted under ``count``. ``bbox`` (lon min, lat min, lon max, lat max): only the rows
    inside are read, block by block (counted as ``outside_bbox``), so that a day of a whole
    coast is read for one region in the memory of that region's rows; ``guard(kept)``, called
    after each block, refuses more rows than the budget holds
    (:func:`usvtool.ais.source.keep_guard`).

    An MMSI is an integer; one written as a decimal with no fraction (``219021240.0``, a
    pandas round trip) is read as that integer, any other fraction refused.
    """
    import pyarrow as pa
    import pyarrow.compute as pc

    from usvtool.csvtable import line_of, read_filtered, read_table

    names = header(path, delimiter)
    missing = [r for r in REQUIRED if r not in columns]
    if missing:
        raise UsvError(f"{path}: no column for {', '.join(missing)} (name it with --columns "
                       f"ROLE=NAME; the header is {','.join(names)[:200]})")  # fmt: skip
    absent = [f"{r}={c}" for r, c in columns.items() if c not in names]
    if absent:
        raise UsvError(f"{path}: line 1: no column {', '.join(absent)} (the header is "
                       f"{','.join(names)[:200]})")  # fmt: skip
    types = {columns["mmsi"]: pa.float64(), columns["time"]: pa.string()}
    for role in NUMBERS:
        if role in columns:
            types[columns[role]] = pa.float64()
    if "name" in columns:
        types[columns["name"]] = pa.string()
    if "ship_type" in columns:
        types[columns["ship_type"]] = pa.string() if ship_types is not None else pa.float64()
    if keep is not None:
        types[keep[0]] = pa.string()
    counts = {}
    rows = None
    if bbox is None:
        table = read_table(path, types, delimiter=delimiter)
    else:
        lon_name, lat_name = columns["lon"], columns["lat"]
        n_inside = 0

        def inside(batch):
            nonlocal n_inside
            lon = batch.column(lon_name).to_numpy(zero_copy_only=False)
            lat = batch.column(lat_name).to_numpy(zero_copy_only=False)
            with np.errstate(invalid="ignore"):
                mask = (lon >= bbox[0]) & (lon <= bbox[2]) & (lat >= bbox[1]) & (lat <= bbox[3])
            n_inside += int(mask.sum())
            if guard is not None:
                guard(n_inside)
            return mask

        table, rows, n = read_filtered(path, types, inside, delimiter=delimiter)
        counts["outside_bbox"] = n - int(rows.size)
    times = _times(path, table.column(columns["time"]), columns["time"], time_formats,
                   epoch_seconds, delimiter, rows)  # fmt: skip
    mmsi = table.column(columns["mmsi"])
    if mmsi.null_count:
        row = int(np.argmax(mmsi.is_null().to_numpy(zero_copy_only=False)))
        row = int(rows[row]) if rows is not None else row
        raise UsvError(f"{path}: line {line_of(path, row, 1, delimiter)}, column "
                       f"{columns['mmsi']}: empty: an MMSI is required")  # fmt: skip
    mmsi = _mmsi(path, mmsi, columns["mmsi"], delimiter, rows)
    if keep is not None:
        column, values, label = keep
        kept = pc.is_in(table.column(column), value_set=pa.array(sorted(values)))
        kept = kept.to_numpy(zero_copy_only=False)
        counts[label] = int(kept.size - kept.sum())
        table, times, mmsi = table.filter(pa.array(kept)), times[kept], mmsi[kept]

    def number(role):
        return table.column(columns[role]).to_numpy(zero_copy_only=False).astype(float) \
            if role in columns else None  # fmt: skip

    lon, lat = number("lon"), number("lat")
    ship_type = None
    if "ship_type" in columns:
        ship_type = _ship_types(table.column(columns["ship_type"]), ship_types)
    return from_columns(
        mmsi, times, lon, lat, number("sog"), number("cog"),
        number("heading"), number("length"), number("beam"),
        table.column(columns["name"]) if "name" in columns else None, ship_type, counts,
    )  # fmt: skip


def _mmsi(path, column, name: str, delimiter: str, rows) -> np.ndarray:
    """The MMSIs of a column of numbers as integers; one line naming the first with a fraction
    (a value beyond any MMSI stays beyond, dropped as ``invalid_mmsi``)."""
    from usvtool.csvtable import line_of

    values = column.to_numpy(zero_copy_only=False)
    with np.errstate(invalid="ignore"):
        fraction = values != np.round(values)
    if fraction.any():
        row = int(np.argmax(fraction))
        line = line_of(path, int(rows[row]) if rows is not None else row, 1, delimiter)
        raise UsvError(f"{path}: line {line}, column {name}: {float(values[row])!r} is not an "
                       "MMSI (an integer)")  # fmt: skip
    return np.where(np.abs(values) <= MAX_MMSI + 1, values, -1).astype(np.int64)


def _ship_types(column, table: dict[str, int] | None) -> np.ndarray:
    """Ship type codes of a column of numbers (NaN: 0), or of texts through ``table``."""
    import pyarrow as pa

    if table is None:
        return np.nan_to_num(column.to_numpy(zero_copy_only=False).astype(float)).astype(np.int64)
    encoded = column.combine_chunks().dictionary_encode()
    values = []
    for text in encoded.dictionary.to_pylist():
        try:
            values.append(int(float(text)))
        except (TypeError, ValueError):
            values.append(table.get(" ".join(str(text).lower().split()), 0))
    codes = np.array(values + [0], np.int64)
    return codes[encoded.indices.fill_null(len(values)).cast(pa.int64()).to_numpy()]


def _times(path, column, name: str, formats: tuple[str, ...], epoch_seconds: bool,
           delimiter: str, rows) -> np.ndarray:  # fmt: skip
    """Nanoseconds (UTC) of a time column: Unix seconds when ``epoch_seconds`` and every value
    is a number, else text (:func:`usvtool.csvtable.time_ns`)."""
    import pyarrow as pa

    from usvtool.csvtable import time_ns

    if epoch_seconds:
        try:
            seconds = column.cast(pa.float64()).to_numpy(zero_copy_only=False)
        except (pa.ArrowInvalid, pa.ArrowNotImplementedError):
            seconds = None
        if seconds is not None and np.isfinite(seconds).all():
            return np.round(seconds * 1e9).astype(np.int64)
    return time_ns(path, column, name, 1, formats, delimiter, rows)
