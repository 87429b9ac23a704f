"""The files that come with a file: what its readers also read, beside it.

A raster is read by GDAL with its sidecars: the PAM ``X.tif.aux.xml`` (which may override the
geotransform, the CRS, the no-data value), the ``.aux`` of older ESRI tools, external overviews
``X.tif.ovr``, an external mask ``X.tif.msk``, a MapInfo ``X.tab`` and a world file (``X.tfw``,
``X.tifw`` or ``X.wld`` for ``X.tif``; ``X.pgw`` for ``X.png``, ``X.jgw`` for ``X.jpg``: the
first and last letters of the extension and ``w``). An S-57 base cell ``X.000`` is read with its
update files ``X.001``, ``X.002``, ... beside it (GDAL's S57 driver applies them in turn), or,
on a CD laid out as ``X/<edition>/0/X.000``, in ``X/<edition>/1/X.001``, ... .

:func:`companions` names them, so that whoever must know every byte a command reads (the keys of
``usvtool batch``) and the S-57 reader agree. GDAL matches sidecar names in either case on a
case-sensitive filesystem, so they are matched here regardless of case: a superset is harmless
(a file taken for a sidecar that is none only makes a job run again when it changes).

>>> import tempfile
>>> d = Path(tempfile.mkdtemp())
>>> for name in ("c.tif", "c.tif.aux.xml", "c.TFW", "c.wld", "d.tif", "US1.000", "US1.001"):
...     _ = (d / name).write_bytes(b"x")
>>> [p.name for p in companions(d / "c.tif")]
['c.TFW', 'c.tif.aux.xml', 'c.wld']
>>> [p.name for p in companions(d / "US1.000")]
['US1.001']
"""

from __future__ import annotations

import os
from pathlib import Path


def sidecars(path: str | os.PathLike) -> list[Path]:
    """The GDAL sidecar files beside ``path`` (module docstring), sorted by name."""
    path = Path(path)
    name, stem, ext = path.name, path.stem, path.suffix[1:]
    wanted = {f"{name}.aux.xml", f"{name}.aux", f"{stem}.aux", f"{name}.ovr", f"{name}.msk",
              f"{stem}.tab", f"{stem}.wld"}  # fmt: skip
    if ext:
        wanted |= {f"{stem}.{ext[0]}{ext[-1]}w", f"{stem}.{ext}w"}
    wanted = {w.lower() for w in wanted} - {name.lower()}
    try:
        beside = os.listdir(path.parent)
    except OSError:  # no folder: no sidecar (the reader reports the missing file)
        return []
    return sorted(path.parent / n for n in beside if n.lower() in wanted)


def s57_updates(path: str | os.PathLike) -> list[Path]:
    """The update files of the S-57 base cell ``path`` in the order of their numbers: same
    name, extension .001 to .999, beside it; and, where GDAL's driver looks when one is not
    beside it, ``../<n>/X.00n`` for n = 1, 2, ... until one is in neither place."""
    path = Path(path)
    try:
        beside = {int(p.suffix[1:]): p for p in path.parent.iterdir()
                  if p.stem == path.stem and len(p.suffix) == 4 and p.suffix[1:].isdigit()
                  and p.suffix != ".000"}  # fmt: skip
    except OSError:
        return []
    n = 1
    while True:
        elsewhere = path.parent.parent / str(n) / f"{path.stem}.{n:03d}"
        if n not in beside and elsewhere.is_file():
            beside[n] = elsewhere
        elif n not in beside:
            break
        n += 1
    return [beside[n] for n in sorted(beside)]


def companions(path: str | os.PathLike) -> list[Path]:
    """Every file read with ``path``: its GDAL sidecars, and the update files of an S-57 cell
    (a file with a three-digit extension, as ``usvtool preprocess`` tells one)."""
    suffix = Path(path).suffix
    s57 = len(suffix) == 4 and suffix[1:].isdigit()
    updates = [p for p in s57_updates(path) if p.name != Path(path).name] if s57 else []
    return sidecars(path) + updates
