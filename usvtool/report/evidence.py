"""The job folders the report reads, checked against their records before anything is built.

Every job of the tables has its folder beside its table (``<kind>/<key>/``, its ``job.json``
listing each of its files with the SHA-256 the batch recorded: :func:`usvtool.digest.recorded`),
as has each route's grid job (``grids/<key>/``). :func:`check` reads each file of those folders
once, before the sections read any, and refuses in one line:

- a file changed since its job ran (its SHA-256 is not the recorded one), gone from its
  folder, or one its record does not list (the batch lists every file of the folder), naming
  the file and the job;
- a folder without its record, a record that lists no SHA-256 (an older usvtool's batch) or
  is another job's;
- folders that are missing (a table copied without its batch), naming up to :data:`NAMED` of
  them and how many, unless the report is told to go on without them (``allow_missing``: the
  methods section lists them). A folder that is there is checked either way: no file of it is
  read unchecked.
"""

from __future__ import annotations

from pathlib import Path, PurePosixPath

from usvtool.digest import recorded, sha256
from usvtool.errors import UsvError
from usvtool.report.data import RECORD, Results, read_record

#: The missing folders the refusal names (then how many more).
NAMED = 3


def check(results: Results, allow_missing: bool = False) -> list[Path]:
    """The job folders of ``results`` that are missing (refused unless ``allow_missing``),
    once every file of the others is checked against its record."""
    folders = job_folders(results)
    missing = [d for d in folders if not d.exists()]
    if missing and not allow_missing:
        raise UsvError(refusal(missing, len(folders)))
    gone = set(missing)
    for folder, key in folders.items():
        if folder not in gone:
            _check_folder(folder, key)
    return missing


def job_folders(results: Results) -> dict[Path, str]:
    """The folder of each job and of each route's grid job, with its key, in key order."""
    folders = {j.dir: j.key for j in results.jobs}
    for j in results.select("routes"):
        grid = j.grid_path()
        if grid is not None:
            folders.setdefault(grid, str(j.config["grid"]))
    return folders


def refusal(missing: list[Path], total: int) -> str:
    """The line refusing to report without the ``missing`` folders, of ``total``."""
    named = ", ".join(map(str, missing[:NAMED]))
    more = f" and {len(missing) - NAMED} more" if len(missing) > NAMED else ""
    return (f"{len(missing)} of {total} job folders are missing ({named}{more}): give the "
            "batch's table with its job folders beside it, or --allow-missing to report "
            "without their files")  # fmt: skip


def _check_folder(folder: Path, key: str) -> None:
    """Refuse a file of the job ``key``'s folder that is not the one its record lists."""
    if not (folder / RECORD).is_file():
        raise UsvError(f"{folder / RECORD}: missing (job {key}): the folder's files cannot be "
                       "checked; run the batch again")  # fmt: skip
    record = read_record(folder)
    digests = recorded(record)
    if digests is None or record.get("key") != key:
        what = "records no SHA-256 of its files" if digests is None else "is not its record"
        raise UsvError(f"{folder / RECORD}: {what} (job {key}): run the batch again")
    for name, digest in digests.items():
        _check_file(folder, name, digest, key)
    unlisted = sorted(_files(folder) - digests.keys())
    if unlisted:
        raise UsvError(f"{folder / unlisted[0]}: not a file job {key} wrote (its job.json does "
                       "not list it): remove it, or run the batch again")  # fmt: skip


def _files(folder: Path) -> set[str]:
    """The files of a job folder but its record, by path relative to it (as the batch lists
    them: :mod:`usvtool.batch.record`)."""
    return {p.relative_to(folder).as_posix() for p in folder.rglob("*")
            if p.is_file() and p.name != RECORD}  # fmt: skip


def _check_file(folder: Path, name: str, digest: str, key: str) -> None:
    parts = PurePosixPath(name).parts
    if not parts or PurePosixPath(name).is_absolute() or ".." in parts:
        raise UsvError(f"{folder / RECORD}: lists {name!r}, not a file of its folder (job {key})")
    path = folder.joinpath(*parts)
    if not path.is_file():
        raise UsvError(f"{path}: gone since job {key} ran (its job.json lists it): run the batch "
                       "again")  # fmt: skip
    if sha256(path) != digest:
        raise UsvError(f"{path}: changed since job {key} ran (its SHA-256 is not the one its "
                       "job.json records): run the batch again")  # fmt: skip
