"""A job directory's record, ``job.json``, and the batch's own writes.

``job.json`` says what ran (:meth:`usvtool.batch.jobs.Job.record`) and lists every other file
of the directory with its size and SHA-256 (``files``), so that a later batch reads a result
only when its files are the bytes the job wrote: :func:`damage` tells why a directory is not
(a file cut short, changed or gone, a record that does not parse or is another job's).

Every file the batch writes itself goes through :func:`write_text`: a write the system refuses
(a full disk: ``ENOSPC``, which names no file) raises :class:`CannotWrite` naming the path.

>>> import tempfile
>>> d = Path(tempfile.mkdtemp())
>>> write_text(d / "trace.csv", "t,x\\n0,1\\n")
>>> write_record(d, {"key": "k"})
>>> json.loads((d / RECORD).read_text())["files"]["trace.csv"]["size"]
8
>>> damage(d, "k") is None
True
>>> write_text(d / "trace.csv", "t,x\\n")
>>> damage(d, "k").endswith("trace.csv: 4 bytes, job.json records 8")
True
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from usvtool.digest import sha256
from usvtool.errors import UsvError

RECORD = "job.json"


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


def _files(directory: Path) -> list[Path]:
    return sorted(p for p in directory.rglob("*") if p.is_file() and p.name != RECORD)


def write_record(directory: Path, record: dict) -> None:
    """Write ``directory/job.json``: ``record`` and the size and SHA-256 of every other file
    in the directory."""
    files = {p.relative_to(directory).as_posix(): {"size": p.stat().st_size, "sha256": sha256(p)}
             for p in _files(directory)}  # fmt: skip
    write_text(directory / RECORD, json.dumps({**record, "files": files}, indent=1) + "\n")


def damage(directory: Path, key: str) -> str | None:
    """Why the job directory ``directory`` of ``key`` is not the result its job wrote, naming
    the file (None when every file ``job.json`` lists has its size and SHA-256). The sizes are
    compared first: the common damage, a file cut short, costs no read."""
    path = directory / RECORD
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        return f"{path}: missing"
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) else "not JSON"
        return f"{path}: unreadable ({reason})"
    files = record.get("files") if isinstance(record, dict) else None
    if not isinstance(files, dict) or record.get("key") != key:
        return f"{path}: not the record of job {key}"
    for name, expected in files.items():
        try:
            size = (directory / name).stat().st_size
        except OSError:
            return f"{directory / name}: missing"
        if not isinstance(expected, dict) or size != expected.get("size"):
            recorded = expected.get("size") if isinstance(expected, dict) else None
            return f"{directory / name}: {size} bytes, job.json records {recorded}"
    for name, expected in files.items():
        try:
            if sha256(directory / name) != expected.get("sha256"):
                return f"{directory / name}: its SHA-256 is not the one job.json records"
        except OSError as exc:
            return f"{directory / name}: unreadable ({exc.strerror})"
    return None
