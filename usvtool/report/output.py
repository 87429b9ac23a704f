"""All-or-nothing output of the report and ``compare``: every file appears, or none does.

:func:`write_together` makes the directories its files need, stages every file
(:class:`usvtool.atomic.staged`, the first one renamed last) and, when anything fails on the
way (a full disk, a signal), removes the temporaries and the directories it made: the output
directory is as it was, with no empty ``figures/`` or ``data/`` left behind. A write that fails
names its file. Once every file is in place, it removes the files it is given to remove (an
earlier report's that this one no longer writes).

Nothing is written or removed through a symbolic link below the output directory (the
directory itself may be one: the user named it): a link on the way to a file, or the file
itself a link, is refused in one line naming it before anything is written, so that no output
lands in, and no removal reaches, a folder the user did not name.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterable
from pathlib import Path

from usvtool.atomic import staged
from usvtool.errors import UsvError


def write_together(files: dict[Path, bytes], root: Path, remove: Iterable[Path] = ()) -> None:
    """Write each file's bytes (every file below ``root``); the first file is renamed into
    place last; then remove the files ``remove``."""
    remove = list(remove)
    refuse_links(root, [*files, *remove])
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
    _remove_files(remove)


def refuse_links(root: Path, paths: Iterable[Path]) -> None:
    """Refuse a symbolic link between ``root`` (which may be one) and any of ``paths`` (each
    below it), or at the path itself."""
    for path in paths:
        below = root
        for part in path.relative_to(root).parts:
            below = below / part
            if below.is_symlink():
                raise UsvError(f"{below}: a symbolic link (to {os.readlink(below)}) in the output "
                               f"directory {root}: nothing is written or removed through a link "
                               "below it; remove the link or choose another directory")  # fmt: skip


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


def _remove_files(paths: list[Path]) -> None:
    """Remove each of the files that is still a file."""
    for p in paths:
        if not p.is_file():
            continue
        try:
            p.unlink()
        except FileNotFoundError:
            continue
        except OSError as exc:
            raise UsvError(f"{p}: cannot remove it: {exc.strerror}") from None
