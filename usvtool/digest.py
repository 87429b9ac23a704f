"""A file's SHA-256, the one digest of a file's bytes: the batch keys its jobs and records their
files with it (:mod:`usvtool.batch.jobs`, :mod:`usvtool.batch.record`: a job's ``job.json``
lists each file of its folder with its size and SHA-256), and a reader checks with it that a
file is still the one a job read or wrote (:func:`recorded`: the report's check of the job
folders; its traffic section's of the AIS files)."""

from __future__ import annotations

import hashlib
import os


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


def recorded(record: object) -> dict[str, str] | None:
    """The SHA-256 a job's record (its parsed ``job.json``) gives each file of the job's folder,
    by the file's path relative to the folder; None when it gives none in that form (a record
    of an older usvtool, or not a record).

    >>> recorded({"key": "0a", "files": {"trace.csv": {"size": 3, "sha256": "ba78"}}})
    {'trace.csv': 'ba78'}
    >>> recorded({"key": "0a"}), recorded({"files": {"trace.csv": 3}})
    (None, None)
    """
    files = record.get("files") if isinstance(record, dict) else None
    if not isinstance(files, dict):
        return None
    digests = {str(name): entry.get("sha256") for name, entry in files.items()
               if isinstance(entry, dict)}  # fmt: skip
    if len(digests) != len(files) or not all(isinstance(d, str) for d in digests.values()):
        return None
    return digests
