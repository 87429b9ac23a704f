"""The report's own record of what it wrote: ``.usvtool-report.json`` in its directory.

A report lists there every file it writes (``index.html``, ``report.pdf``, ``figures/*.png``,
``data/*.csv``, as paths relative to the directory), written together with them. The next
report in the same directory removes the files of that list it no longer writes, and nothing
else: the user's own files in the directory, in ``figures/`` or in ``data/`` are never touched,
and a directory without the list (a report of an older usvtool, or none) loses nothing. A list
that is not one the report wrote (unreadable, or naming a file the report never writes) is
refused in one line: what it names cannot be proved the report's.
"""

from __future__ import annotations

import json
from pathlib import Path
from urllib.parse import unquote

from usvtool.errors import UsvError
from usvtool.results import file_name

NAME = ".usvtool-report.json"
#: The files the report writes: its pages, and a figure's files by folder and suffix.
PAGES = ("index.html", "report.pdf")
FIGURE_FILES = {"figures": ".png", "data": ".csv"}


def previous(out: Path) -> set[Path]:
    """The files the report before in ``out`` wrote (empty when it left no list)."""
    path = out / NAME
    if not path.is_file():
        return set()
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise _refused(path, exc.strerror if isinstance(exc, OSError) else "not JSON") from None
    files = data.get("files") if isinstance(data, dict) else None
    if not isinstance(files, list):
        raise _refused(path, "no list of files")
    for f in files:
        if not isinstance(f, str) or not _ours(f):
            raise _refused(path, f"{f!r} is not a file a report writes")
    return {out / f for f in files}


def text(out: Path, files: list[Path]) -> bytes:
    """The list of ``files`` (each below ``out``), sorted, as the manifest's bytes."""
    names = sorted(p.relative_to(out).as_posix() for p in files)
    return (json.dumps({"files": names}, indent=1) + "\n").encode("utf-8")


def _refused(path: Path, why: str) -> UsvError:
    return UsvError(f"{path}: not the list of a report's files ({why}): remove it (the files "
                    "it listed stay) or choose another -o")  # fmt: skip


def _ours(name: str) -> bool:
    """Whether ``name`` is a file the report writes: a page, or a figure's file whose name is
    a :func:`usvtool.results.file_name` in its folder."""
    if name in PAGES:
        return True
    folder, _, rest = name.partition("/")
    suffix = FIGURE_FILES.get(folder)
    stem = rest.removesuffix(suffix) if suffix and rest.endswith(suffix) else ""
    return bool(stem) and file_name(unquote(stem)) == stem
