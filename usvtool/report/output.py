"""All-or-nothing output of the report and ``compare``: every file appears, or none does.

:func:`write_together` makes the directories its files need, stages every file
(:class:`usvtool.atomic.staged`, the first one renamed last) and, when anything fails on the
way (a full disk, a signal), removes the temporaries and the directories it made: the output
directory is as it was, with no empty ``figures/`` or ``data/`` left behind. A write that fails
names its file.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

from usvtool.atomic import staged
from usvtool.errors import UsvError


def write_together(files: dict[Path, bytes]) -> None:
    """Write each file's bytes; the first file is renamed into place last."""
    made = _make_dirs(sorted({p.parent for p in files}))
    try:
        with staged(*files) as temporaries:
            for tmp, (target, content) in zip(temporaries, files.items(), strict=True):
                try:
                    tmp.write_bytes(content)
                except OSError as exc:
                    raise UsvError(f"{target}: cannot write it: {exc.strerror or exc}") from None
    except BaseException:
        _remove(made)
        raise


def _make_dirs(dirs: list[Path]) -> list[Path]:
    """Make the missing ones (and their missing parents): those made, parents first."""
    made: list[Path] = []
    for d in dirs:
        missing = [p for p in (d, *d.parents) if not p.exists()][::-1]
        for p in missing:
            try:
                p.mkdir()
            except FileExistsError:
                continue
            except OSError as exc:
                _remove(made)
                raise UsvError(f"{p}: cannot create the directory: {exc.strerror}") from None
            made.append(p)
    return made


def _remove(made: list[Path]) -> None:
    """Remove the directories made, children first, if they are empty."""
    for d in reversed(made):
        with contextlib.suppress(OSError):
            d.rmdir()
