"""The batch's results tables: ``metrics.csv`` and ``timings.csv`` (the :mod:`usvtool.results`
contract), and ``metrics.parquet`` when pyarrow is installed; beside them the pipeline's
claims, ``claims.json`` (:mod:`usvtool.pipeline`), which ``usvtool report`` judges.

Routes and runs are measured by ``usvtool metrics`` commands (:func:`measure`, run by the
workers like jobs, as many at once as the executor runs), each over every route and the runs
of whole scenarios (:func:`parts`), so that its cross-job figures hold: a route's
``length_ratio`` against the any-angle route of the same grid and ends, a run's optimisation
rates against the reference controller's run of the same scenario and seed; every route in
each part also gives each command the columns one command over all of them would, so the
table is the same whatever the number of parts. A command sees its jobs through a hidden
directory of symbolic links, one subdirectory per grid and ends (the directory is what
``usvtool metrics`` takes as a route's chart), removed afterwards. A function run's
``final_cost`` is the ``best`` of its ``usvtool functions --runs 1`` summary.

Each job's metrics become rows (key, kind, case, method, seed, metric, value) in the command's
column order, without the columns that name the job (chart, algorithm, run, scenario,
controller, seed, reference_controller) and without timings; its wall time and, for routes,
``planning_time_s`` are the rows of ``timings.csv``.
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import shutil
from collections import defaultdict
from pathlib import Path

from usvtool.batch.jobs import Job
from usvtool.batch.record import cannot_write
from usvtool.batch.worker import Command, fresh_directory, in_directory, one_line
from usvtool.errors import UsvError
from usvtool.pipeline import ClaimSpec, claims_path, claims_text
from usvtool.results import COLUMNS, FILES, KINDS, TIMING_METRICS, Row, timings_path, write_results

#: Columns of ``usvtool metrics`` that say which job a row is, not what it measured.
IDENTITY = {"chart", "algorithm", "run", "scenario", "controller", "seed", "reference_controller"}
#: The ``usvtool metrics`` column of each kind's method.
METHOD_COLUMN = {"routes": "algorithm", "runs": "controller"}


def _view_name(job: Job) -> str:
    """A job's file in the view: routes grouped by grid and ends, runs together."""
    if job.kind == "runs":
        return f"runs/{job.key}.csv"
    ends = json.dumps([job.needs, job.info["frame"], job.info["start"], job.info["goal"]])
    return f"{hashlib.sha256(ends.encode()).hexdigest()[:12]}/{job.key}.geojson"


def parts(out: Path, jobs: list[Job], count: int) -> list[list[Job]]:
    """The routes and runs ``jobs`` (done, in ``out``) as at most ``count`` parts to measure at
    once: the runs by scenario (the name in a run's ``summary.json``), each scenario's runs in
    one part, the largest first to the part with the fewest runs; every route in every part.
    One part when there are no runs."""
    routes = [j for j in jobs if j.kind == "routes"]
    scenarios: dict[str, list[Job]] = defaultdict(list)
    for job in jobs:
        if job.kind == "runs":
            summary = json.loads((out / job.kind / job.key / "summary.json").read_text())
            scenarios[str(summary.get("scenario"))].append(job)
    runs: list[list[Job]] = [[] for _ in range(max(1, min(count, len(scenarios))))]
    for name in sorted(scenarios, key=lambda n: (-len(scenarios[n]), n)):
        min(runs, key=len).extend(scenarios[name])
    return [routes + part for part in runs]


def measure(out: str, jobs: list[Job], command: Command, reference_controller: str | None) -> str:
    """``usvtool metrics`` of the routes and runs ``jobs`` (done, in ``out``): its CSV text,
    one row per job in the order of :func:`view_order`."""
    view = fresh_directory(Path(out), "view")
    try:
        for job in jobs:
            name = view / _view_name(job)
            target = Path("..", "..", job.kind, job.key, FILES[job.kind])
            try:
                name.parent.mkdir(exist_ok=True)
                name.symlink_to(target)
                if job.kind == "runs":
                    events = target.with_name("trace.events.json")
                    name.with_suffix(".events.json").symlink_to(events)
            except OSError as exc:
                raise cannot_write(exc, name) from None
        args = ["metrics", *view_order(jobs), "-o", "metrics.csv"]
        if reference_controller is not None:
            args += ["--reference-controller", reference_controller]
        status, _, stderr, _ = in_directory(view, command, args)
        if status != 0:
            raise UsvError(f"usvtool metrics: {one_line(stderr)}")
        return (view / "metrics.csv").read_text(encoding="utf-8")
    finally:
        shutil.rmtree(view, ignore_errors=True)


def view_order(jobs: list[Job]) -> list[str]:
    """The view's files in the order of ``usvtool metrics``' rows (sorted by path)."""
    return sorted(_view_name(j) for j in jobs)


def joined(measured: list[tuple[list[Job], str]]) -> dict[str, dict[str, str]]:
    """The rows of the ``usvtool metrics`` tables of some parts (each part's jobs and its CSV
    text, :func:`measure`), by view name (a route measured in several parts has the same row
    in each)."""
    table = {}
    for jobs, text in measured:
        rows = list(csv.DictReader(io.StringIO(text)))
        if len(rows) != len(jobs):
            raise UsvError(f"usvtool metrics: {len(rows)} rows for {len(jobs)} routes and runs")
        table.update(zip(view_order(jobs), rows, strict=True))
    return table


def rows(jobs: list[Job], table: dict[str, dict], out: Path) -> tuple[list[Row], list[Row]]:
    """The metrics and timings rows of every done job of :data:`KINDS` in ``jobs``, those of
    the routes and runs from their ``usvtool metrics`` rows (:func:`joined`)."""
    measured = [j for j in jobs if j.kind in METHOD_COLUMN]
    by_name = {_view_name(j): j for j in measured}
    metrics: list[Row] = []
    timings: list[Row] = []
    for name in view_order(measured):
        job, values = by_name[name], table[name]
        if values[METHOD_COLUMN[job.kind]] != job.method:
            raise UsvError(f"usvtool metrics: the row of {name} is not {job.label}'s")
        for metric, value in values.items():
            if value and metric not in IDENTITY:
                (timings if metric in TIMING_METRICS else metrics).append(_row(job, metric, value))
    for job in jobs:
        if job.kind == "functions":
            summary = json.loads((out / job.kind / job.key / "summary.json").read_text())
            metrics.append(_row(job, "final_cost", repr(float(summary["results"][0]["best"]))))
        if job.kind in KINDS:
            record = json.loads((out / job.kind / job.key / "job.json").read_text())
            timings.append(_row(job, "wall_time_s", str(record["wall_time_s"])))
    return metrics, timings


def _row(job: Job, metric: str, value: str) -> Row:
    return Row(job.key, job.kind, job.case, job.method, job.seed, metric, value)


def write(path: Path, metrics: list[Row], timings: list[Row],
          claims: tuple[ClaimSpec, ...] = ()) -> Path | None:  # fmt: skip
    """Write ``metrics.csv`` at ``path``, ``timings.csv`` beside it, the pipeline's claims
    beside them (``claims.json``, :func:`usvtool.pipeline.claims_text`; an empty list when it
    declares none, so that no earlier batch's claims stay beside this table) and
    ``metrics.parquet`` when pyarrow is importable (its path, or None), renamed into place
    together (``metrics.csv`` last)."""
    from usvtool.atomic import staged

    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        pa = None
    parquet = path.with_suffix(".parquet") if pa is not None else None
    with staged(path, timings_path(path), claims_path(path), parquet) as (
        metrics_tmp, timings_tmp, claims_tmp, parquet_tmp):  # fmt: skip
        write_results(metrics_tmp, metrics)
        write_results(timings_tmp, timings)
        Path(claims_tmp).write_text(claims_text(claims), encoding="utf-8")
        if parquet_tmp is not None:
            ordered = sorted(metrics, key=lambda r: r.key)  # the CSV's order
            columns = {c: [getattr(r, c) for r in ordered] for c in COLUMNS}
            schema = pa.schema([(c, pa.int64() if c == "seed" else pa.string())
                                for c in COLUMNS])  # fmt: skip
            pq.write_table(pa.table(columns, schema=schema), parquet_tmp)
    return parquet
