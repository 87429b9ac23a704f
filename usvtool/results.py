"""The results table: the contract between the batch engine and the report and compare stages.

A long-format CSV (UTF-8, ``\\n`` line ends), one row per metric of a job, with the header
``key,kind,case,method,seed,metric,value``:

- ``key``: the job's key (hex digits, a hash of its whole configuration); the job's files are
  in ``<the table's directory>/<kind>/<key>/`` (:func:`job_dir`, :data:`FILES`);
- ``kind``: ``routes`` (a planned route), ``runs`` (a simulated encounter) or ``functions`` (one
  run of an optimizer on a benchmark function);
- ``case``: what the job is about: the chart's name (routes), the scenario file's stem or, for
  a scene of a scene family, ``ENTRY/KIND/sNNN`` (runs: :func:`usvtool.pipeline.family_case`),
  or the benchmark function (functions, ``F1`` ... ``F10``);
- ``method``: the algorithm (routes, functions) or the controller (runs);
- ``seed``: an integer, or empty for a deterministic job (the exact planners);
- ``metric``: a column of ``usvtool metrics`` (docs/metrics.md), or ``final_cost`` for
  functions;
- ``value``: as ``usvtool metrics`` writes it: a number, ``True``/``False``, or a word (a class
  name, a failed rule); never empty (a metric a job has not got has no row).

Rows are sorted by key; a job's rows keep the order of its metrics. Timings differ between
machines and runs, so the table holds none: they are in a table of the same form beside it,
``timings.csv`` (:func:`timings_path`), whose metrics are :data:`TIMING_METRICS`.

>>> row = Row("0a1b", "routes", "env1", "iwso", 3, "length_m", "701.5")
>>> row.number, Row("0a1b", "routes", "env1", "iwso", 3, "collision_free", "True").number
(701.5, 1.0)
>>> row.group
('routes', 'env1', 'iwso', 'length_m')
"""

from __future__ import annotations

import csv
import io
import math
import string
from dataclasses import dataclass
from pathlib import Path

from usvtool.errors import UsvError, check_input_file

COLUMNS = ("key", "kind", "case", "method", "seed", "metric", "value")
KINDS = ("routes", "runs", "functions")
#: The main file of each kind of job, in its directory.
FILES = {"routes": "route.geojson", "runs": "trace.csv"}
#: The metrics of ``timings.csv``: a job's wall time, and the stage's own figure.
TIMING_METRICS = ("wall_time_s", "planning_time_s")
#: The characters a name keeps in a file name (:func:`file_name`).
FILE_NAME_CHARACTERS = frozenset(string.ascii_letters + string.digits + "._+-")


@dataclass(frozen=True)
class Row:
    """One metric of one job (see the module docstring)."""

    key: str
    kind: str
    case: str
    method: str
    seed: int | None
    metric: str
    value: str

    @property
    def number(self) -> float | None:
        """The value as a number: ``True``/``False`` as 1/0; None for a word."""
        if self.value in ("True", "False"):
            return float(self.value == "True")
        try:
            number = float(self.value)
        except ValueError:
            return None
        return number if math.isfinite(number) else None

    @property
    def group(self) -> tuple[str, str, str, str]:
        """What replicate runs share: kind, case, method and metric (not the seed)."""
        return (self.kind, self.case, self.method, self.metric)


def format_results(rows) -> str:
    """The table's text: the header, then the rows sorted by key (stable)."""
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(COLUMNS)
    for r in sorted(rows, key=lambda r: r.key):
        writer.writerow([r.key, r.kind, r.case, r.method, "" if r.seed is None else r.seed,
                         r.metric, r.value])  # fmt: skip
    return text.getvalue()


def write_results(path: str | Path, rows) -> None:
    """Write the table atomically."""
    from usvtool.atomic import atomic_path

    with atomic_path(path) as tmp:
        Path(tmp).write_text(format_results(rows), encoding="utf-8")


def read_results(path: str | Path) -> list[Row]:
    """Read and check a results table; one-line errors name the file, line and column."""
    check_input_file(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise UsvError(f"{path}: not a UTF-8 text file") from None
    reader = csv.reader(io.StringIO(text))
    header = next(reader, None)
    if header is None or tuple(header) != COLUMNS:
        raise UsvError(f"{path}: not a results table (its header must be {','.join(COLUMNS)})")
    rows = []
    for line, cells in enumerate(reader, start=2):
        if len(cells) != len(COLUMNS):
            raise UsvError(f"{path}: line {line}: {len(cells)} columns, expected {len(COLUMNS)}")
        key, kind, case, method, seed, metric, value = cells
        if kind not in KINDS:
            raise UsvError(f"{path}: line {line}: kind {kind!r} is not one of {', '.join(KINDS)}")
        for name, cell in (("key", key), ("case", case), ("method", method),
                           ("metric", metric), ("value", value)):  # fmt: skip
            if not cell:
                raise UsvError(f"{path}: line {line}: {name} is empty")
        try:
            number = None if seed == "" else int(seed)
        except ValueError:
            raise UsvError(f"{path}: line {line}: seed {seed!r} is not an integer") from None
        rows.append(Row(key, kind, case, method, number, metric, value))
    _check_one_value(path, rows)
    return rows


def _check_one_value(path: str | Path, rows: list[Row]) -> None:
    """Refuse a job whose rows disagree on what it is (kind, case, method, seed) and a metric
    of a job given twice (the same row repeated, or two values): which is meant cannot be told.
    The rows are the file's, in order (line 2 first)."""
    jobs: dict[str, int] = {}
    metrics: dict[tuple[str, str], int] = {}
    for line, r in enumerate(rows, start=2):
        first = jobs.setdefault(r.key, line)
        was = rows[first - 2]
        if (was.kind, was.case, was.method, was.seed) != (r.kind, r.case, r.method, r.seed):
            raise UsvError(f"{path}: job {r.key}: line {first} says {_job(was)}, line {line} "
                           f"says {_job(r)}")  # fmt: skip
        first = metrics.setdefault((r.key, r.metric), line)
        if first != line:
            was = rows[first - 2]
            said = (f"line {line} repeats line {first}" if was == r else
                    f"line {first} says {was.value!r}, line {line} says {r.value!r}")  # fmt: skip
            raise UsvError(f"{path}: job {r.key}, metric {r.metric}: {said} (a job has one row "
                           "a metric)")  # fmt: skip


def _job(row: Row) -> str:
    """What a row says its job is: ``routes/env1/iwso seed 3``."""
    return f"{row.kind}/{row.case}/{row.method} seed {'-' if row.seed is None else row.seed}"


def timings_path(table: str | Path) -> Path:
    """The timings table beside a results table."""
    return Path(table).with_name("timings.csv")


def job_dir(table: str | Path, row: Row) -> Path:
    """The directory of a row's job: ``<the table's directory>/<kind>/<key>`` (the key as a
    :func:`file_name`: the batch's hex keys are their own)."""
    return Path(table).parent / row.kind / file_name(row.key)


def file_name(name: str) -> str:
    """``name`` (a key, case, method, a figure's id made of them...) as one file name, reversibly:
    letters, digits and ``._+-`` kept, every other character as the ``%XX`` of its UTF-8 bytes,
    ``.`` and ``..`` alone (a folder's names) as ``%2E``, so that no name read from a table or
    a job's files makes a subfolder or reaches outside the folder it is put in.

    >>> file_name("routes-env1-map"), file_name("x/../a b"), file_name(".."), file_name("5%")
    ('routes-env1-map', 'x%2F..%2Fa%20b', '%2E%2E', '5%25')
    """
    if name in (".", ".."):
        return "%2E" * len(name)
    return "".join(c if c in FILE_NAME_CHARACTERS else "".join(f"%{b:02X}" for b in c.encode())
                   for c in name)  # fmt: skip
