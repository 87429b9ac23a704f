"""``usvtool ais read``: AIS files of any supported format into one tidy tracks table.

Each file's format is told by its first line: an NMEA sentence or tag block (:mod:`.nmea`), a
MarineCadastre header in either layout (:mod:`.marinecadastre`), the DMA's (:mod:`.dma`), else
any CSV (:mod:`.generic`); ``--columns`` reads every CSV file as :mod:`.generic` with that
mapping. With ``--bbox`` only the positions inside the box are kept (counted as
``outside_bbox``). The fixes of all the files are cleaned together (:mod:`.clean`), so one
vessel's fixes from several files make one track.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from usvtool.ais import dma, generic, marinecadastre, nmea
from usvtool.ais.clean import CleanOptions, clean
from usvtool.ais.fixes import Fixes, check_bbox
from usvtool.ais.source import first_lines, keep_guard, scan
from usvtool.budget import default_budget
from usvtool.errors import UsvError
from usvtool.tracks import Tracks, format_time

FORMATS = ("nmea", "marinecadastre", "dma", "generic")
#: A file's figures in the summary that count no skipped line or row.
_NOT_SKIPPED = ("file", "format", "positions", "static", "lines")
#: The cleaning rules that drop fixes (usvtool/ais/clean.py).
_DROPPED = ("invalid_mmsi", "invalid_position", "duplicates", "too_fast")


@dataclass(frozen=True)
class ReadOptions:
    """``columns``: the ``--columns`` mapping (role: column name; read every CSV as generic);
    ``clean``: the cleaning's limits; ``bbox``: only the positions inside (lon min, lat min, lon
    max, lat max; a CSV file is read block by block, holding only those); ``max_memory``: the
    budget (bytes; :mod:`usvtool.ais.source`)."""

    columns: dict = field(default_factory=dict)
    clean: CleanOptions = field(default_factory=CleanOptions)
    bbox: tuple[float, float, float, float] | None = None
    max_memory: int | None = None

    @property
    def budget(self) -> int:
        """``max_memory``, else :func:`usvtool.budget.default_budget`."""
        return default_budget() if self.max_memory is None else self.max_memory

    def __post_init__(self):
        object.__setattr__(self, "bbox", check_bbox(self.bbox))


@dataclass
class ReadResult:
    """The tracks, and per file its format and its format's counts."""

    tracks: Tracks
    counts: dict
    files: list[dict]

    def summary(self) -> dict:
        t = self.tracks
        span = format_time([t.time.min(), t.time.max()]) if t.n_rows else []
        box = [float(t.lon.min()), float(t.lat.min()), float(t.lon.max()), float(t.lat.max())] \
            if t.n_rows else []  # fmt: skip
        return {"files": self.files, "cleaning": self.counts, "fixes": t.n_rows,
                "vessels": int(np.unique(t.mmsi).size), "tracks": t.n_tracks,
                "time": span, "bbox": box}  # fmt: skip


def detect(path, columns: dict | None = None) -> str:
    """The format of ``path`` (module docstring)."""
    first = next((line for line in first_lines(path, 5) if line.strip()), "")
    if nmea.detect(first):
        return "nmea"
    if columns:
        return "generic"
    names = generic.header(path) if first else []
    if marinecadastre.layout(names):
        return "marinecadastre"
    if dma.detect(names):
        return "dma"
    return "generic"


def read_file(path, options: ReadOptions = ReadOptions(), before: int = 0
              ) -> tuple[str, Fixes, int]:  # fmt: skip
    """The format, the raw fixes and the decompressed size of one file, refused when it does
    not fit the budget with the ``before`` bytes of the files read before it
    (:func:`usvtool.ais.source.scan`)."""
    kind = detect(path, options.columns)
    box, budget = options.bbox, options.budget
    whole = box is None or kind == "nmea"  # a CSV with --bbox is read block by block
    size = scan(path, budget, "read it by parts with --bbox, or split it", whole,
                before if whole else 0)  # fmt: skip
    if kind == "nmea":
        fx = nmea.read(path)
        return kind, fx.within(box) if box is not None else fx, size
    guard = keep_guard(path, budget)
    if kind == "generic":
        return kind, generic.read(path, options.columns, box, guard), size
    names = generic.header(path)
    reader = marinecadastre if kind == "marinecadastre" else dma
    return kind, reader.read(path, names, box, guard), size


def read_ais(paths, options: ReadOptions = ReadOptions()) -> ReadResult:
    """The cleaned tracks of the AIS files ``paths`` (module docstring)."""
    paths = list(paths)
    if not paths:
        raise UsvError("ais read: give one or more AIS files")
    parts, files, size = [], [], 0
    for path in paths:
        kind, fx, n = read_file(path, options, size)
        size += n
        parts.append(fx)
        files.append({"file": str(path), "format": kind, "positions": fx.n_positions,
                      "static": int(fx.static_mmsi.size), **fx.counts})  # fmt: skip
    tracks, counts = clean(Fixes.concatenate(parts), options.clean)
    if tracks.n_rows == 0:
        raise UsvError(no_fix_left(paths, files, counts))
    return ReadResult(tracks, counts, files)


def no_fix_left(paths, files: list[dict], counts: dict) -> str:
    """The line refusing files of which no fix survives: what each file's format skipped and
    what each cleaning rule dropped, the counts that are not zero.

    >>> no_fix_left(["a.csv"], [{"file": "a.csv", "format": "generic", "positions": 2,
    ...             "static": 2}], {"fixes_read": 2, "invalid_mmsi": 0, "invalid_position": 2,
    ...             "fixes": 0})
    'a.csv: no fix left after cleaning: 2 positions read; dropped: invalid_position 2'
    """
    names = ", ".join(map(str, paths))
    skipped = [f"{f['file']}: {k} {v}" if len(files) > 1 else f"{k} {v}" for f in files
               for k, v in f.items() if k not in _NOT_SKIPPED and v]
    rules = [f"{k} {counts[k]}" for k in _DROPPED if counts.get(k)]
    n = counts["fixes_read"]
    text = f"{names}: no fix left after cleaning: {n} position{'' if n == 1 else 's'} read"
    if skipped:
        text += f" (skipped: {', '.join(skipped)})"
    return text + (f"; dropped: {', '.join(rules)}" if rules else "")
