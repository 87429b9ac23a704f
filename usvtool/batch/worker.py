"""What a worker process does with a job: run its command in a fresh directory, and rename the
directory into place once complete.

The command is a function given by the caller (``usvtool batch`` gives one that runs the CLI
in-process: :func:`usvtool.cli.batch.run_command`), taking the ``usvtool`` arguments and
returning (exit status, stdout, stderr); the engine itself imports no stage. A job works in a
hidden ``DIR/<kind>/.tmp-<key>-<random>/`` as its current directory, so that every path it
writes is relative to it; the directory is renamed onto ``DIR/<kind>/<key>/`` when complete, so
a result appears whole or not at all. It holds the command's outputs, its stdout as
``summary.json`` and ``job.json`` (with the size and SHA-256 of every other file:
:mod:`usvtool.batch.record`); a failed job holds ``error.txt`` (its one-line error) and
``job.json`` only. A job whose files the batch cannot write (a full disk) fails, the error
naming the file; when even its failure cannot be written, its outcome says why
(:attr:`Outcome.unrecorded`). Jobs of one process run one at a time (the current directory is
the process's).
"""

from __future__ import annotations

import os
import secrets
import shutil
import signal
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from usvtool.batch.failpoint import reach
from usvtool.batch.jobs import Job
from usvtool.batch.record import CannotWrite, cannot_write, write_record, write_text

#: ``command(args) -> (exit status, stdout, stderr)``: runs one ``usvtool`` command line.
Command = Callable[[list[str]], tuple[int, str, str]]
#: The exit status of a command stopped by SIGINT or SIGTERM (128 + the signal).
INTERRUPTED = {128 + signal.SIGINT, 128 + signal.SIGTERM}
TMP_PREFIX = ".tmp-"
_CWD = threading.Lock()
#: The commands given a job's share of the batch's memory budget (``--max-memory``).
BUDGETED = ("preprocess", "plan", "simulate")


@dataclass(frozen=True)
class Outcome:
    """What became of a job: its one-line error (None when it succeeded), its wall time, and
    why its failure could not be recorded in its directory (None when it was, or it
    succeeded)."""

    error: str | None
    wall_time_s: float
    unrecorded: str | None = None


def one_line(text: str) -> str:
    """The last non-empty line of a command's stderr (its error line)."""
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return lines[-1] if lines else "failed without a message"


def with_memory(command: Command, max_memory: int, args: list[str]) -> tuple[int, str, str]:
    """``command(args)``, with ``--max-memory MAX_MEMORY`` (bytes) added for the commands that
    take it (:data:`BUDGETED`): the job's share of the batch's memory budget, given when it
    runs, so that neither its ``args`` (its ``job.json``) nor its key hold it."""
    if args and args[0] in BUDGETED:
        args = [*args, "--max-memory", str(max_memory)]
    return command(args)


def in_directory(directory: Path, command: Command, args: list[str]) -> tuple[int, str, str, float]:
    """Run ``command(args)`` with ``directory`` as the current directory: (status, stdout,
    stderr, wall time in seconds)."""
    with _CWD:
        previous = os.getcwd()
        os.chdir(directory)
        try:
            started = time.perf_counter()
            status, stdout, stderr = command(args)
            return status, stdout, stderr, time.perf_counter() - started
        finally:
            os.chdir(previous)


def fresh_directory(parent: Path, name: str) -> Path:
    """A new hidden directory ``parent/.tmp-<name>-<random>`` (mode 0777 less the umask);
    :class:`CannotWrite` when the system refuses."""
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise cannot_write(exc, parent) from None
    while True:
        path = parent / f"{TMP_PREFIX}{name}-{secrets.token_hex(4)}"
        try:
            path.mkdir()
            return path
        except FileExistsError:
            continue
        except OSError as exc:
            raise cannot_write(exc, path) from None


def execute(job: Job, out: str, command: Command) -> Outcome:
    """Run ``job`` into ``out/<kind>/<key>/``. An interrupted command (SIGINT, SIGTERM) leaves
    no directory, so the job runs again on the next batch; a job whose files cannot be written
    fails with the reason."""
    kind_dir = Path(out) / job.kind
    wall = 0.0
    try:
        tmp = fresh_directory(kind_dir, job.key)
        try:
            reach("during", job.key)
            status, stdout, stderr, wall = in_directory(tmp, command, list(job.args))
            wall = round(wall, 3)
            if status in INTERRUPTED:
                return Outcome(one_line(stderr), wall)
            if status == 0:
                write_text(tmp / "summary.json", stdout)
                _finish(job, tmp, kind_dir, wall, None)
                reach("written", job.key)
                return Outcome(None, wall)
            error = one_line(stderr)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    except CannotWrite as exc:
        error = str(exc)
    return record_failure(job, out, error, wall)


def record_failure(job: Job, out: str, error: str, wall: float = 0.0) -> Outcome:
    """Leave ``out/<kind>/<key>/`` with the job's ``error.txt`` and ``job.json`` only (a failed
    job runs again on the next batch): the job's outcome, ``unrecorded`` when the system
    refused them (a full disk; the directory is then absent, and the job runs again too)."""
    kind_dir = Path(out) / job.kind
    try:
        tmp = fresh_directory(kind_dir, job.key)
        try:
            write_text(tmp / "error.txt", error + "\n")
            _finish(job, tmp, kind_dir, wall, error)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    except CannotWrite as exc:
        return Outcome(error, wall, str(exc))
    return Outcome(error, wall)


def _finish(job: Job, tmp: Path, kind_dir: Path, wall: float, error: str | None) -> None:
    """Write ``job.json`` into ``tmp`` and rename it onto ``kind_dir/<key>``."""
    write_record(tmp, {**job.record(), "wall_time_s": wall, **({"error": error} if error else {})})
    try:
        os.rename(tmp, kind_dir / job.key)  # the result appears complete, or not at all
    except OSError as exc:
        if not (kind_dir / job.key).is_dir():  # else another batch has just done it
            raise cannot_write(exc, kind_dir / job.key) from None
