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
from usvtool.errors import UsvError, check_input_file
from usvtool.tracks import Tracks, format_time

FORMATS = ("nmea", "marinecadastre", "dma", "generic")


@dataclass(frozen=True)
class ReadOptions:
    """``columns``: the ``--columns`` mapping (role: column name; read every CSV as generic);
    ``clean``: the cleaning's limits; ``bbox``: only the positions inside (lon min, lat min, lon
    max, lat max; a CSV file is read block by block, holding only those)."""

    columns: dict = field(default_factory=dict)
    clean: CleanOptions = field(default_factory=CleanOptions)
    bbox: tuple[float, float, float, float] | None = None

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
    from usvtool.csvtable import first_lines

    check_input_file(path)
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


def read_file(path, options: ReadOptions = ReadOptions()) -> tuple[str, Fixes]:
    """The format and the raw fixes of one file."""
    kind = detect(path, options.columns)
    box = options.bbox
    if kind == "nmea":
        fx = nmea.read(path)
        return kind, fx.within(box) if box is not None else fx
    if kind == "generic":
        return kind, generic.read(path, options.columns, box)
    names = generic.header(path)
    return kind, (marinecadastre if kind == "marinecadastre" else dma).read(path, names, box)


def read_ais(paths, options: ReadOptions = ReadOptions()) -> ReadResult:
    """The cleaned tracks of the AIS files ``paths`` (module docstring)."""
    paths = list(paths)
    if not paths:
        raise UsvError("ais read: give one or more AIS files")
    parts, files = [], []
    for path in paths:
        kind, fx = read_file(path, options)
        parts.append(fx)
        files.append({"file": str(path), "format": kind, "positions": fx.n_positions,
                      "static": int(fx.static_mmsi.size), **fx.counts})  # fmt: skip
    tracks, counts = clean(Fixes.concatenate(parts), options.clean)
    if tracks.n_rows == 0:
        raise UsvError(f"{', '.join(map(str, paths))[:200]}: no fix left after cleaning "
                       f"({', '.join(f'{k} {v}' for k, v in counts.items())})")  # fmt: skip
    return ReadResult(tracks, counts, files)
