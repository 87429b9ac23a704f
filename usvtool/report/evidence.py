"""The job folders the report reads, checked against their records before anything is built.

Every job of the tables has its folder beside its table (``<kind>/<key>/``, its ``job.json``
listing each of its files with the size and SHA-256 the batch recorded), as has each route's
grid job (``grids/<key>/``). :func:`check` reads each file of those folders once, before the
sections read any, and refuses in one line (:func:`usvtool.digest.fault`, the batch's own
check, and files the record does not list, as the batch lists every file of the folder):

- a file changed since its job ran (another size or SHA-256), gone from its folder, or one its
  record does not list, naming the file and the job;
- a folder without its record, a record that does not parse, lists no files, is another job's
  or names a path outside the folder;
- folders that are missing (a table copied without its batch), naming up to :data:`NAMED` of
  them and how many, unless the report is told to go on without them (``allow_missing``: the
  methods section lists them). A folder that is there is checked either way: no file of it is
  read unchecked.
"""

from __future__ import annotations

from pathlib import Path

from usvtool.digest import fault
from usvtool.errors import UsvError
from usvtool.report.data import Results

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
    """Refuse the folder of job ``key`` when it is not what the job wrote, or holds a file its
    record does not list (:func:`usvtool.digest.fault`)."""
    problem = fault(folder, key, unlisted=True)
    if problem is not None:
        raise UsvError(f"{problem} (job {key}): run the batch again")
