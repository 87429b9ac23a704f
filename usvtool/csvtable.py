"""CSV tables read by pyarrow (multi-threaded, gzip/bzip2/zstd/zip), refused in one line naming
the file, the line and the column at fault.

The fast path reads the file once with the columns' types. Only when that fails is the fault
located (a second, slower read): a row of the wrong number of fields by pyarrow's single-threaded
parser (its ``Row #n`` is the line), a value that is not of its column's type by reading the
columns as text and bisecting casts; a row index is turned into its line by counting the file's
non-empty lines (pyarrow skips empty lines; a quoted field holding line breaks counts them). A
:class:`~usvtool.errors.UsvError` says ``FILE: line N, column C: 'value' is not a number``.

Compression is detected from the suffix (``.gz``, ``.bz2``, ``.zst``; a ``.zip`` holding one
file), the text is UTF-8.
"""

from __future__ import annotations

import csv
import io
import os
import re
from pathlib import Path

import numpy as np

from usvtool.errors import UsvError, check_input_file

#: Texts read as a missing number.
NULLS = ("", "nan", "NaN", "NA", "null", "None")


def open_binary(path: str | os.PathLike):
    """A readable binary stream of the file's (decompressed) bytes."""
    import pyarrow as pa

    check_input_file(path)
    if Path(path).suffix.lower() == ".zip":
        import zipfile

        try:
            archive = zipfile.ZipFile(path)
        except zipfile.BadZipFile as exc:
            raise UsvError(f"{path}: not a zip archive ({exc})") from None
        members = [m for m in archive.namelist() if not m.endswith("/")]
        if len(members) != 1:
            raise UsvError(f"{path}: a zip archive must hold one file, not {len(members)}")
        return archive.open(members[0])
    return pa.input_stream(os.fspath(path), compression="detect")


def first_lines(path: str | os.PathLike, n: int = 1) -> list[str]:
    """The first ``n`` lines of the file (decompressed, line ends stripped)."""
    lines = []
    try:
        with io.TextIOWrapper(open_binary(path), encoding="utf-8", newline="") as f:
            for line in f:
                lines.append(line.rstrip("\r\n"))
                if len(lines) == n:
                    break
    except UnicodeDecodeError as exc:
        raise UsvError(f"{path}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    except OSError as exc:
        raise UsvError(f"{path}: not readable ({exc})") from None
    return lines


def _options(types: dict, delimiter: str):
    import pyarrow.csv as pcsv

    read = pcsv.ReadOptions(block_size=1 << 24)
    parse = pcsv.ParseOptions(delimiter=delimiter)
    convert = pcsv.ConvertOptions(column_types=types, include_columns=list(types),
                                  null_values=list(NULLS), strings_can_be_null=False,
                                  quoted_strings_can_be_null=False)  # fmt: skip
    return read, parse, convert


def read_table(path: str | os.PathLike, types: dict, *, delimiter: str = ","):
    """The columns ``types`` (name: pyarrow type; text columns ``pa.string()``, never null) of
    the CSV file ``path`` (its header on line 1)."""
    import pyarrow as pa
    import pyarrow.csv as pcsv

    read, parse, convert = _options(types, delimiter)
    try:
        with open_binary(path) as stream:
            return pcsv.read_csv(stream, read, parse, convert)
    except (pa.ArrowInvalid, pa.ArrowTypeError) as exc:
        raise _locate(path, exc, types, read, parse) from None
    except UnicodeDecodeError as exc:
        raise UsvError(f"{path}: not UTF-8 text ({exc.reason})") from None


def read_filtered(path: str | os.PathLike, types: dict, keep, *, delimiter: str = ","):
    """:func:`read_table` block by block, keeping the rows for which ``keep(batch)`` (a pyarrow
    record batch) is true, so that only they are held: ``(table, rows, n)``, ``rows`` the kept
    rows' indices in the file's data (for :func:`line_of`), ``n`` the data rows read."""
    import pyarrow as pa
    import pyarrow.csv as pcsv

    read, parse, convert = _options(types, delimiter)
    parts, rows, seen = [], [], 0
    try:
        with open_binary(path) as stream:
            for batch in pcsv.open_csv(stream, read, parse, convert):
                mask = np.asarray(keep(batch), bool)
                parts.append(batch.filter(pa.array(mask)))
                rows.append(seen + np.flatnonzero(mask))
                seen += batch.num_rows
    except (pa.ArrowInvalid, pa.ArrowTypeError) as exc:
        raise _locate(path, exc, types, read, parse) from None
    except UnicodeDecodeError as exc:
        raise UsvError(f"{path}: not UTF-8 text ({exc.reason})") from None
    if not parts:
        empty = pa.table({name: pa.array([], kind) for name, kind in types.items()})
        return empty, np.zeros(0, np.int64), 0
    return pa.Table.from_batches(parts), np.concatenate(rows), seen


def _locate(path, exc, types, read, parse) -> UsvError:
    """The one-line error of a failed typed read: the first row at fault, its line and column."""
    import pyarrow as pa
    import pyarrow.csv as pcsv

    message = str(exc)
    if "Expected" in message and "columns" in message:  # a row of the wrong number of fields
        single = pcsv.ReadOptions(use_threads=False)
        try:
            with open_binary(path) as stream:
                pcsv.read_csv(stream, single, parse)
        except pa.ArrowInvalid as again:
            found = re.search(r"Row #(\d+): Expected (\d+) columns, got (\d+)", str(again))
            if found:
                return UsvError(f"{path}: line {found[1]}: {found[3]} fields, expected "
                                f"{found[2]}")  # fmt: skip
        return UsvError(f"{path}: not a CSV table ({_short(message)})")
    if "No such column" in message or "not found" in message or "include_columns" in message:
        return UsvError(f"{path}: {_short(message)}")
    text_types = {name: pa.string() for name in types}
    convert = pcsv.ConvertOptions(column_types=text_types, include_columns=list(types),
                                  strings_can_be_null=False)  # fmt: skip
    try:
        with open_binary(path) as stream:
            table = pcsv.read_csv(stream, read, parse, convert)
    except (pa.ArrowInvalid, pa.ArrowTypeError) as again:
        return UsvError(f"{path}: not a CSV table ({_short(str(again))})")
    faults = []
    for name, kind in types.items():
        if kind == pa.string():
            continue
        column = table.column(name).combine_chunks()
        row = first_bad(column, kind)
        if row is not None:
            faults.append((row, name, column[row].as_py()))
    if not faults:
        return UsvError(f"{path}: not a CSV table ({_short(message)})")
    row, name, value = min(faults)
    kind = "a number" if pa.types.is_floating(types[name]) else "an integer" \
        if pa.types.is_integer(types[name]) else f"a {types[name]}"  # fmt: skip
    return UsvError(f"{path}: line {line_of(path, row, 1, parse.delimiter)}, "
                    f"column {name}: {_short(repr(value), 40)} is not {kind}")


def first_bad(column, kind) -> int | None:
    """The first index of the text array ``column`` that does not cast to ``kind`` (bisecting
    casts of slices), or None."""
    import pyarrow as pa

    nulls = pa.array([None] * len(NULLS), pa.string())
    column = column.combine_chunks() if hasattr(column, "combine_chunks") else column

    def ok(part) -> bool:
        import pyarrow.compute as pc

        part = pc.if_else(pc.is_in(part, value_set=pa.array(NULLS)), nulls[0], part)
        try:
            part.cast(kind)
        except (pa.ArrowInvalid, pa.ArrowNotImplementedError):
            return False
        return True

    if ok(column):
        return None
    lo, hi = 0, len(column)  # column[lo:hi] holds a bad value
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if ok(column.slice(lo, mid - lo)):
            lo = mid
        else:
            hi = mid
    return lo


def line_of(path: str | os.PathLike, row: int, before: int = 1, delimiter: str = ",") -> int:
    """The line (from 1) of data row ``row`` (from 0) of a CSV file whose data starts after its
    ``before`` first lines, empty lines skipped as pyarrow skips them."""
    with io.TextIOWrapper(open_binary(path), encoding="utf-8", newline="") as f:
        for _ in range(before):
            f.readline()
        reader = csv.reader(f, delimiter=delimiter)
        seen = -1
        for fields in reader:
            if fields:
                seen += 1
                if seen == row:
                    return reader.line_num + before
    return row + before + 1


def time_ns(path, column, name: str, before: int, formats: tuple[str, ...] = (),
            delimiter: str = ",", rows: np.ndarray | None = None) -> np.ndarray:  # fmt: skip
    """Nanoseconds since the epoch (UTC) of the text column ``column`` (pyarrow) of ``path``,
    all in the form of its first value: ISO 8601 without a zone (taken as UTC) or with one
    (converted to UTC), else the first of the ``strptime`` ``formats`` that reads it; one line
    naming the first value not in that form (``before``: the lines above the data; ``rows``:
    the file's data row of each value, when they are not all of them)."""
    import pyarrow as pa
    import pyarrow.compute as pc

    column = column.combine_chunks() if hasattr(column, "combine_chunks") else column

    def line(row: int) -> int:
        return line_of(path, int(rows[row]) if rows is not None else row, before, delimiter)

    empty = pc.equal(column, "")
    if pc.any(empty).as_py():
        row = int(np.argmax(empty.to_numpy(zero_copy_only=False)))
        raise UsvError(f"{path}: line {line(row)}, column {name}: empty: a time is required")
    readers = [lambda c, k=k: c.cast(k) for k in (pa.timestamp("ns"), pa.timestamp("ns", "UTC"))]
    readers += [lambda c, f=f: pc.strptime(c, format=f, unit="ns") for f in formats]
    form = next((r for r in readers if _reads(r, column.slice(0, 1))), None)
    if form is not None:
        if _reads(form, column):
            return form(column).cast(pa.int64()).to_numpy()
        lo, hi = 0, len(column)  # column[lo:hi] holds a value the first one's form does not read
        while hi - lo > 1:
            mid = (lo + hi) // 2
            lo, hi = (mid, hi) if _reads(form, column.slice(lo, mid - lo)) else (lo, mid)
        row, rule = lo, "in the form of the first"
    else:
        row, rule = 0, ", ".join(["ISO 8601", *formats])
    raise UsvError(f"{path}: line {line(row)}, column {name}: "
                   f"{_short(repr(column[row].as_py()), 40)} is not a time ({rule})")


def _reads(reader, column) -> bool:
    import pyarrow as pa

    try:
        reader(column)
    except (pa.ArrowInvalid, pa.ArrowNotImplementedError):
        return False
    return True


def _short(text: str, limit: int = 200) -> str:
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: limit - 3] + "..."
