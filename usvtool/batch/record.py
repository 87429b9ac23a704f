"""A job directory's record, ``job.json``, and the batch's own writes.

``job.json`` says what ran (:meth:`usvtool.batch.jobs.Job.record`) and lists every other file
of the directory with its size and SHA-256 (``files``), so that a later batch reads a result
only when its files are the bytes the job wrote: :func:`usvtool.digest.fault` tells why a
directory is not (a file cut short, changed or gone, a record that does not parse or is
another job's).

Every file the batch writes itself goes through :func:`write_text`: a write the system refuses
(a full disk: ``ENOSPC``, which names no file) raises :class:`CannotWrite` naming the path.

>>> import tempfile
>>> d = Path(tempfile.mkdtemp())
>>> write_text(d / "trace.csv", "t,x\\n0,1\\n")
>>> write_record(d, {"key": "k"})
>>> json.loads((d / RECORD).read_text())["files"]["trace.csv"]["size"]
8
>>> from usvtool.digest import fault
>>> fault(d, "k") is None
True
>>> write_text(d / "trace.csv", "t,x\\n")
>>> fault(d, "k").endswith("trace.csv: 4 bytes, job.json records 8")
True
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from usvtool.digest import RECORD, folder_files, sha256
from usvtool.errors import UsvError


class CannotWrite(UsvError):
    """The system refused a file or folder the batch writes (its message names it)."""


def cannot_write(exc: OSError, path: str | os.PathLike) -> CannotWrite:
    """``exc`` (raised writing ``path``) as one line naming the path and the reason."""
    return CannotWrite(f"{exc.filename or path}: cannot write: {exc.strerror or exc}")


def write_text(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` (UTF-8); :class:`CannotWrite` when the system refuses."""
    try:
        path.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise cannot_write(exc, path) from None


def write_record(directory: Path, record: dict) -> None:
    """Write ``directory/job.json``: ``record`` and the size and SHA-256 of every other file
    in the directory."""
    files = {name: {"size": (directory / name).stat().st_size, "sha256": sha256(directory / name)}
             for name in folder_files(directory)}  # fmt: skip
    write_text(directory / RECORD, json.dumps({**record, "files": files}, indent=1) + "\n")
