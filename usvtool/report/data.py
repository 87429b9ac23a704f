"""The report's inputs: results tables (:mod:`usvtool.results`) and the job files they point to.

Each row of a table is one metric of one job; :func:`load` gathers a job's rows into its
:class:`JobResults` with its directory (``<table's directory>/<kind>/<key>/``), its ``job.json``
(what the batch engine ran: the grid of a route, the scenario of a run) and its timings (the
``timings.csv`` beside the table, when there is one). Several tables may be given (several
batches); a key found in two of them is refused, as the report could not tell which is meant.
A table (or its timings) holding a value that is not of its metric's kind (``nan`` where a
number is expected: :mod:`usvtool.report.values`) is refused, naming how many and which.

Methods are shown in the order the caller gives (:func:`load`'s ``order``): the report imports
no other stage, so ``usvtool report`` hands it the registries' (the planners, then the
controllers); a method not in it comes after, alphabetically.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from usvtool.digest import RECORD
from usvtool.errors import UsvError
from usvtool.pipeline import ClaimSpec, claims_path, read_claims
from usvtool.report import values
from usvtool.report.papers.schema import Claim
from usvtool.results import Row, file_name, job_dir, read_results, timings_path


def method_order(name: str, order: Sequence[str] = ()) -> tuple:
    """Sort key of a method: its base name's place in ``order`` (a name not there comes after,
    alphabetically), then its variant suffix.

    >>> order = ("iwso", "astar", "udwa")
    >>> sorted(["udwa", "b", "astar", "iwso+g", "a", "iwso"], key=lambda m: method_order(m, order))
    ['iwso', 'iwso+g', 'astar', 'udwa', 'a', 'b']
    """
    base, plus, variant = name.partition("+")
    place = order.index(base) if base in order else len(order)
    return (place, base, plus + variant)


#: The row that says how a job ended: a route's collision check, a run's arrival.
ENDING = {"routes": "collision_free", "runs": "arrived"}


@dataclass
class JobResults:
    """One job of a results table: its metrics, files and configuration (its ``job.json``, which
    the batch's :class:`usvtool.batch.jobs.Job` wrote: what ran)."""

    key: str
    kind: str
    case: str
    method: str
    seed: int | None
    dir: Path
    metrics: dict[str, Row] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)
    config: dict = field(default_factory=dict)

    def number(self, metric: str) -> float | None:
        """The metric as a number (timings included); None when absent or a word."""
        if metric in self.timings:
            return self.timings[metric]
        row = self.metrics.get(metric)
        return None if row is None else row.number

    def grid_path(self) -> Path | None:
        """A route's grid job directory, there or not: ``<batch>/grids/<key>``, the key in
        ``job.json``'s ``grid`` (None without one)."""
        key = self.config.get("grid")
        return self.dir.parent.parent / "grids" / file_name(str(key)) if key else None

    def grid_dir(self) -> Path | None:
        """A route's grid job directory (:meth:`grid_path`), when it is there."""
        path = self.grid_path()
        return path if path is not None and path.is_dir() else None

    def text(self, metric: str) -> str | None:
        row = self.metrics.get(metric)
        return None if row is None else row.value

    @property
    def settled(self) -> bool:
        """Whether the table says how the job ended (:data:`ENDING`): a route or run without
        that row is no evidence either way, neither a success nor a failure."""
        metric = ENDING.get(self.kind)
        return metric is None or self.text(metric) is not None

    @property
    def failed(self) -> bool:
        """A route that collides; a run that collided or did not arrive."""
        if self.kind == "routes":
            return self.text("collision_free") == "False"
        if self.kind == "runs":
            return bool(self.text("collision")) or self.text("arrived") == "False"
        return False

    @property
    def succeeded(self) -> bool:
        """Settled and not failed: a collision-free route, a run that arrived without
        collision, any benchmark-function run."""
        return self.settled and not self.failed


@dataclass
class Results:
    """Every job of the tables given, in key order; ``order`` is the order the stages list
    their methods in (``usvtool report`` gives the registries': the planners, then the
    controllers), which :meth:`methods` keeps."""

    jobs: list[JobResults]
    tables: list[Path]
    order: tuple[str, ...] = ()
    #: The job folders that are missing, when the report goes on without them
    #: (:func:`usvtool.report.evidence.check`).
    missing: list[Path] = field(default_factory=list)
    #: The user's claims: those of the pipelines the tables' batches ran (the ``claims.json``
    #: beside each table, :func:`user_claims`), judged as the papers' are.
    claims: tuple[Claim, ...] = ()
    #: The jobs by (kind, method), made by :meth:`group` on its first call.
    _by_method: dict[tuple[str, str], list[JobResults]] = field(
        default_factory=dict, init=False, repr=False, compare=False)
    #: The jobs by (kind, case) and by (kind, None), made by :meth:`select` on its first call.
    _by_case: dict[tuple[str, str | None], list[JobResults]] = field(
        default_factory=dict, init=False, repr=False, compare=False)

    def select(
        self, kind: str, case: str | None = None, method: str | None = None
    ) -> list[JobResults]:
        """The jobs of ``kind`` (and ``case``, and ``method``), in key order; from an index by
        kind and case, as the sections select thousands of times (a scan of every job each
        time was 2-3 s of the bundled report's)."""
        if not self._by_case:
            for j in self.jobs:
                self._by_case.setdefault((j.kind, j.case), []).append(j)
                self._by_case.setdefault((j.kind, None), []).append(j)
        return [j for j in self._by_case.get((kind, case), ()) if method in (None, j.method)]

    def cases(self, kind: str) -> list[str]:
        return sorted({j.case for j in self.jobs if j.kind == kind})

    def methods(self, kind: str, case: str | None = None) -> list[str]:
        found = {j.method for j in self.select(kind, case)}
        return sorted(found, key=lambda m: method_order(m, self.order))

    def group(self, kind: str, group: str, method: str) -> list[JobResults]:
        """The jobs of (kind, method) in ``group`` (:func:`in_group`), by (case, seed)."""
        if not self._by_method:
            for j in self.jobs:
                self._by_method.setdefault((j.kind, j.method), []).append(j)
        jobs = [j for j in self._by_method.get((kind, method), ()) if in_group(j.case, group)]
        return sorted(jobs, key=pairing_key)

    def pairs(self, kind: str, group: str, method: str,
              rival: str) -> list[tuple[JobResults, JobResults]]:  # fmt: skip
        """The jobs of ``method`` and ``rival`` in ``group`` that share a :func:`pairing_key`
        (the same scene and seed), by that key; a job without its partner is left out."""
        theirs = {pairing_key(j): j for j in self.group(kind, group, rival)}
        return [(j, theirs[pairing_key(j)]) for j in self.group(kind, group, method)
                if pairing_key(j) in theirs]  # fmt: skip

    def values(self, kind: str, case: str, method: str, metric: str,
               succeeded: bool = False) -> list[float]:  # fmt: skip
        """The metric's numbers over the seeds of (kind, case, method), in seed order; with
        ``succeeded``, of the jobs that succeeded only (:attr:`JobResults.succeeded`)."""
        jobs = sorted(self.select(kind, case, method), key=lambda j: (j.seed is None, j.seed))
        return [v for v in (j.number(metric) for j in jobs if j.succeeded or not succeeded)
                if v is not None]  # fmt: skip


def in_group(case: str, group: str) -> bool:
    """Whether a job's case is of ``group``: the case itself, or a scene family's kind
    ``ENTRY/KIND`` standing for its scenes' cases ``ENTRY/KIND/sNNN`` (docs/families.md).

    >>> in_group("emergency/head-on/s007", "emergency/head-on"), in_group("env1", "env1")
    (True, True)
    >>> in_group("emergency/head-on-2/s000", "emergency/head-on")
    False
    """
    return case == group or case.startswith(group + "/")


def pairing_key(job: JobResults) -> tuple[str, int]:
    """What pairs two methods' runs: the same case (one scene) and seed (-1 for none)."""
    return (job.case, -1 if job.seed is None else job.seed)


def load(tables, order: Sequence[str] = ()) -> Results:
    """Read the tables, their timings and every job's ``job.json``; ``order``: the methods'
    (:attr:`Results.order`)."""
    if not tables:
        raise UsvError("no results table given")
    jobs: dict[str, JobResults] = {}
    where: dict[str, Path] = {}
    for table in map(Path, tables):
        rows = _read(table)
        timings = _read(timings_path(table)) if timings_path(table).is_file() else []
        mine: dict[str, JobResults] = {}
        for row in rows:
            if row.key in where and where[row.key] != table:
                raise UsvError(f"{table}: job {row.key} is also in {where[row.key]}")
            where[row.key] = table
            job = mine.get(row.key)
            if job is None:
                job = mine[row.key] = JobResults(row.key, row.kind, row.case, row.method,
                                                 row.seed, job_dir(table, row))  # fmt: skip
                job.config = read_record(job.dir)
            job.metrics[row.metric] = row
        for row in timings:
            if row.key in mine and row.number is not None:
                mine[row.key].timings[row.metric] = row.number
        jobs.update(mine)
    paths = [Path(t) for t in tables]
    return Results([jobs[k] for k in sorted(jobs)], paths, tuple(order),
                   claims=user_claims(paths))  # fmt: skip


def user_claims(tables: Sequence[Path]) -> tuple[Claim, ...]:
    """The claims of the pipelines behind ``tables``: each table's ``claims.json``
    (:func:`usvtool.pipeline.claims_path`; none without it), in the tables' order. A claim
    given by two tables must be the same claim: one of the same id that differs is refused,
    naming both files and the first field that differs."""
    found: dict[str, tuple[ClaimSpec, Path]] = {}
    for table in tables:
        path = claims_path(table)
        if not path.is_file():
            continue
        for spec in read_claims(path):
            if spec.id not in found:
                found[spec.id] = (spec, path)
                continue
            was, where = found[spec.id]
            if was != spec:
                mine, theirs = spec.to_json(), was.to_json()
                field_ = next(k for k in (*mine, *theirs) if mine.get(k) != theirs.get(k))
                raise UsvError(f"{path}: claim {spec.id!r} is also in {where}, with another "
                               f"{field_} ({mine.get(field_)!r}, there {theirs.get(field_)!r}): "
                               "give each claim its own id")  # fmt: skip
    return tuple(as_claim(spec) for spec, _ in found.values())


def as_claim(spec: ClaimSpec) -> Claim:
    """A user's claim (:class:`usvtool.pipeline.ClaimSpec`) as the report judges claims."""
    return Claim(spec.id, "", (), spec.kind, spec.metric, spec.statistic, spec.better,
                 spec.method, spec.rivals, spec.cases, target=spec.target,
                 share=spec.share)  # fmt: skip


def read_record(directory: Path) -> dict:
    """A job folder's ``job.json`` ({} when there is none)."""
    path = directory / RECORD
    if not path.is_file():
        return {}
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except ValueError as e:
        raise UsvError(f"{path}: not JSON ({e})") from None


def _read(path: Path) -> list[Row]:
    """A results table whose every value is of its metric's kind."""
    rows = read_results(path)
    bad = values.invalid(rows)
    if bad:
        raise UsvError(values.refusal(path, bad))
    return rows


def stats(values) -> dict[str, float | None]:
    """Best, worst, median, mean, sample variance and standard deviation (ddof 1; None for one
    value) and the count of a list of numbers."""
    a = np.asarray(values, float)
    if a.size == 0:
        return {"n": 0, "best": None, "worst": None, "median": None, "mean": None,
                "variance": None, "std": None}  # fmt: skip
    var = float(a.var(ddof=1)) if a.size > 1 else None
    return {"n": int(a.size), "best": float(a.min()), "worst": float(a.max()),
            "median": float(np.median(a)), "mean": float(a.mean()), "variance": var,
            "std": None if var is None else float(np.sqrt(var))}  # fmt: skip


def seed_text(seeds: list[int]) -> str:
    """Seeds for a caption: ``1-25 (25)`` for a run of consecutive seeds, else a list."""
    if not seeds:
        return "none"
    if len(seeds) > 2 and seeds == list(range(seeds[0], seeds[-1] + 1)):
        return f"{seeds[0]}-{seeds[-1]} ({len(seeds)})"
    return ", ".join(map(str, seeds))


def statistic(results: Results, kind: str, case: str, method: str, metric: str,
              name: str, succeeded: bool = False) -> float | None:  # fmt: skip
    """A figure of our runs as a paper states one (:data:`usvtool.report.papers.STATISTICS`):
    ``value`` and ``median`` the median over seeds, ``min``, ``max``, ``mean``, ``variance``,
    ``std`` (ddof 1), ``of-best`` the metric of the run with the lowest ``fitness``; None when
    there is no data (or one run for a spread). With ``succeeded``, over the jobs that
    succeeded only (:attr:`JobResults.succeeded`)."""
    jobs = sorted((j for j in results.select(kind, case, method) if j.number(metric) is not None
                   and (j.succeeded or not succeeded)), key=pairing_key)  # fmt: skip
    return summarise([j.number(metric) for j in jobs], name,
                     [j.number("fitness") for j in jobs])  # fmt: skip


def summarise(values: Sequence[float], name: str,
              fitness: Sequence[float | None] = ()) -> float | None:  # fmt: skip
    """The figure ``name`` (:func:`statistic`) of ``values``; ``of-best`` takes the value whose
    ``fitness`` (one per value, None: unknown) is lowest, of equal fitnesses the first: give
    the values in :func:`pairing_key` order (case, then seed), the one tie rule of the
    report (docs/statistics.md)."""
    if name == "of-best":
        known = [(f, v) for f, v in zip(fitness, values, strict=True) if f is not None]
        return min(known, key=lambda fv: fv[0])[1] if known else None
    figures = stats(values)
    return figures["median" if name == "value" else {"min": "best", "max": "worst"}.get(name, name)]
