"""An input file read safely: its decompressed bytes counted as they stream, its lines bounded,
a damaged compressed stream refused in one line, the memory it needs checked against the
budget (:mod:`usvtool.budget`) before it is read whole.

:func:`scan` streams a file once in chunks of :data:`CHUNK` (plain, gzip, bzip2, zstd or a zip
holding one file: :func:`usvtool.csvtable.open_binary`), so a 4 MB gzip of 4 GB, a zip or zstd
bomb or a sparse file is refused after the budget's share of it, never held. A table read whole
needs :data:`TEXT_BYTES` bytes of memory per byte of text; one read block by block (``--bbox``)
holds only the rows it keeps (:func:`keep_guard`).
"""

from __future__ import annotations

import contextlib
import io
import os
import zipfile
import zlib

from usvtool.budget import require, size_text
from usvtool.errors import UsvError, check_input_file

#: Peak memory of ``ais read`` per byte of decompressed text read whole (measured: 10.5 MB of
#: MarineCadastre CSV 225 MiB, 52 MB 457 MiB: 5.5 bytes a byte beyond the interpreter's own).
TEXT_BYTES = 6
#: Peak memory per fix kept when a CSV is read block by block (``--bbox``): that many bytes of
#: text (some 100 a row) times :data:`TEXT_BYTES`.
ROW_BYTES = 600
#: Peak memory per row of a parquet tracks file read (twelve columns and a name string each,
#: twice while converted).
TRACK_ROW_BYTES = 300
#: The longest line accepted (bytes): a CSV row or an NMEA sentence is far shorter.
MAX_LINE = 1 << 20
#: Bytes read at a time.
CHUNK = 1 << 20
_COMPRESSION = {".gz": "gzip", ".bz2": "bzip2", ".zst": "zstd", ".zip": "zip"}


def scan(path, budget: int, remedy: str, whole: bool = True, before: int = 0) -> int:
    """The decompressed size of ``path``, streamed once; :class:`UsvError` for a file that
    expands past ``budget / TEXT_BYTES`` (less the ``before`` bytes of the files read with it)
    when it is read ``whole`` (``remedy`` says what to do), a line longer than
    :data:`MAX_LINE`, a truncated or corrupt compressed stream."""
    from usvtool.csvtable import open_binary

    limit = budget / TEXT_BYTES - before if whole else float("inf")
    size, line, number = 0, 0, 1  # bytes read, of the current line, its number
    with _decoding(path), open_binary(path) as stream:
        while chunk := stream.read(CHUNK):
            size += len(chunk)
            if size > limit:
                after = f" after {size_text(before)} of the files before it" if before else ""
                require((before + size) * TEXT_BYTES, f"{path}: expanding past "
                        f"{size_text(size)} while reading{after}", remedy, budget)  # fmt: skip
            first, last = chunk.find(b"\n"), chunk.rfind(b"\n")
            if line + (len(chunk) if first < 0 else first) > MAX_LINE:
                raise UsvError(f"{path}: line {number} is longer than {size_text(MAX_LINE)}: "
                               "not a table of AIS fixes or an NMEA log")  # fmt: skip
            if first >= 0:
                number += chunk.count(b"\n")
                line = len(chunk) - last - 1
            else:
                line += len(chunk)
    return size


def first_lines(path, n: int = 1) -> list[str]:
    """The first ``n`` lines of ``path`` (decompressed, UTF-8, a byte order mark dropped, line
    ends stripped), each at most :data:`MAX_LINE` long."""
    from usvtool.csvtable import open_binary

    check_input_file(path)
    lines = []
    with _decoding(path), io.TextIOWrapper(open_binary(path), encoding="utf-8-sig",
                                           newline="") as f:  # fmt: skip
        while len(lines) < n:
            line = f.readline(MAX_LINE + 1)
            if len(line) > MAX_LINE:
                raise UsvError(f"{path}: line {len(lines) + 1} is longer than "
                               f"{size_text(MAX_LINE)}: not a table of AIS fixes or an NMEA log")
            if not line:
                break
            lines.append(line.rstrip("\r\n"))
    return lines


def keep_guard(path, budget: int):
    """A function ``check(kept)`` refusing, in one line, more fixes kept block by block
    (``--bbox``) than the budget holds (:data:`ROW_BYTES` each)."""

    def check(kept: int) -> None:
        require(kept * ROW_BYTES, f"{path}: {kept:,} fixes inside --bbox", "give a smaller "
                "--bbox or split the file", budget)  # fmt: skip

    return check


def read_tracks_within(path, budget: int, remedy: str):
    """:func:`usvtool.tracks.read_tracks` of ``path`` once its size (a parquet file's rows, a
    CSV file's text) is known to fit ``budget``."""
    from usvtool.tracks import check_suffix, read_tracks

    check_input_file(path)
    if check_suffix(path) == ".csv":
        scan(path, budget, remedy)
    else:
        rows = _parquet_rows(path)
        require(rows * TRACK_ROW_BYTES, f"{path}: reading {rows:,} fixes", remedy, budget)
    return read_tracks(path)


def _parquet_rows(path) -> int:
    """The rows a parquet file's footer declares (0 when it is unreadable: read_tracks says
    why)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    try:
        return pq.ParquetFile(path).metadata.num_rows
    except (pa.ArrowException, OSError):
        return 0


@contextlib.contextmanager
def _decoding(path):
    """Turn a failed decompression or read inside the block into one line naming the file."""
    try:
        yield
    except UnicodeDecodeError as exc:
        raise UsvError(f"{path}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    except (OSError, EOFError, zlib.error, zipfile.BadZipFile) as exc:
        text = " ".join(str(exc).split()) or type(exc).__name__
        kind = _COMPRESSION.get(os.path.splitext(os.fspath(path))[1].lower())
        if kind is None:
            raise UsvError(f"{path}: not readable ({text})") from None
        what = "truncated" if isinstance(exc, EOFError) or "runcated" in text else "corrupt"
        raise UsvError(f"{path}: {what} {kind} file ({text})") from None
