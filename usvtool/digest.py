"""A file's SHA-256, the one digest of a file's bytes: the batch keys its jobs and records their
files with it (:mod:`usvtool.batch.jobs`, :mod:`usvtool.batch.record`: a job's ``job.json``
lists each file of its folder with its size and SHA-256), and a reader checks with it that a
file is still the one a job read or wrote (:func:`fault`: the batch's check of its results and
the report's of the job folders it reads; the traffic section's of the AIS files)."""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path, PurePosixPath

#: A job folder's record: what ran, and the size and SHA-256 of each of its other files.
RECORD = "job.json"


def sha256(path: str | os.PathLike) -> str:
    """The SHA-256 of a file's bytes (hex), read in blocks of 1 MiB.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "x"
    >>> _ = p.write_bytes(b"abc")
    >>> sha256(p)[:16]
    'ba7816bf8f01cfea'
    """
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        while chunk := f.read(1 << 20):
            digest.update(chunk)
    return digest.hexdigest()


def folder_files(folder: Path) -> list[str]:
    """The files of a job folder but its record, by path relative to it, sorted (what a
    record lists)."""
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*")
                  if p.is_file() and p.name != RECORD)  # fmt: skip


def fault(folder: Path, key: str, unlisted: bool = False) -> str | None:
    """Why ``folder`` is not the result job ``key`` wrote, naming the file (None when every file
    its ``job.json`` lists has its size and SHA-256 and, with ``unlisted``, no other file is
    there): a record missing, unreadable, another job's or naming a path outside the folder; a
    file gone, of another size (compared first: the common damage, a file cut short, costs no
    read) or of another SHA-256. The batch's check of its results before it skips a job, and
    the report's of every job folder it reads."""
    path = folder / RECORD
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        return f"{path}: missing"
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        return f"{path}: unreadable ({exc.strerror if isinstance(exc, OSError) else 'not JSON'})"
    if not isinstance(record, dict) or record.get("key") != key:
        return f"{path}: not the record of job {key}"
    files = record.get("files")
    if not isinstance(files, dict):
        return f"{path}: lists no files with their size and SHA-256 (an older usvtool's batch)"
    listed = {}
    for name, expected in files.items():
        parts = PurePosixPath(name).parts
        if not parts or PurePosixPath(name).is_absolute() or ".." in parts:
            return f"{path}: lists {name!r}, not a file of its folder"
        listed[folder.joinpath(*parts)] = expected if isinstance(expected, dict) else {}
    for file, expected in listed.items():
        size = file.stat().st_size if file.is_file() else None
        if size is None:
            return f"{file}: missing"
        if size != expected.get("size"):
            return f"{file}: {size} bytes, job.json records {expected.get('size')}"
    for file, expected in listed.items():
        try:
            if sha256(file) != expected.get("sha256"):
                return f"{file}: its SHA-256 is not the one job.json records"
        except OSError as exc:
            return f"{file}: unreadable ({exc.strerror})"
    extra = sorted(set(folder_files(folder)) - set(files)) if unlisted else []
    return f"{folder / extra[0]}: a file job.json does not list" if extra else None
