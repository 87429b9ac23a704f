"""``run_batch``: every job of a pipeline on an executor, resumable, then the results tables.

The order: read and check the pipeline (names checked against the stages' :class:`Names`),
expand it into jobs and refuse a clash, connect the executor (a local pool, or a Dask
scheduler), lock ``DIR`` (one batch at a time), remove the temporaries of a killed batch, the
directories of failed jobs and those of damaged ones (files that are not the ones their
``job.json`` records: each named on one line; all of them run again), skip the jobs done, run
the others as they become ready (a route once its grid is done; a route whose grid failed
fails too), keeping the executor's capacity twice over in flight, then measure and write the
tables. A failure the batch cannot record (a full disk) stops it: no job starts after it, and
the batch ends with one line saying why and where.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import heapq
import json
import os
import queue
import shutil
import stat
import sys
import time
from collections import defaultdict
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from functools import partial
from pathlib import Path

from usvtool.batch import results_tables
from usvtool.batch.jobs import PRIORITY, Job, ScenarioFiles, check_expansion, expand
from usvtool.batch.progress import Bar, Lines
from usvtool.batch.worker import TMP_PREFIX, Command, Outcome, execute, record_failure, with_memory
from usvtool.budget import default_budget
from usvtool.digest import RECORD, fault
from usvtool.errors import UsvError
from usvtool.pipeline import Names, load


@dataclass(frozen=True)
class BatchOptions:
    """``command`` runs one ``usvtool`` command line in a worker and ``names`` are the stages'
    names (``usvtool batch`` gives both: :mod:`usvtool.cli.batch`); ``workers``: local worker
    processes (None: the number of cores); ``scheduler``: a Dask scheduler's address instead;
    ``out``: the results' directory; ``progress``: a progress bar (None: when stderr is a
    terminal) rather than plain lines; ``timeout``: the seconds a job may run on the local pool
    (None: no limit), after which it is stopped and fails; ``scenario_files``: the files a
    scenario names, for the runs' keys (:data:`~usvtool.batch.jobs.ScenarioFiles`; ``usvtool
    batch`` gives the simulation's reader)."""

    command: Command
    names: Names
    workers: int | None = None
    scheduler: str | None = None
    out: str = "build/batch"
    progress: bool | None = None
    timeout: float | None = None
    #: the memory budget (bytes) the jobs running at once share: each is given its share with
    #: ``--max-memory`` (None: :func:`usvtool.budget.default_budget`; with a scheduler, each
    #: job keeps the default of the machine it runs on)
    max_memory: int | None = None
    scenario_files: ScenarioFiles | None = None


@dataclass
class BatchResult:
    """What a batch did: its summary figures and the failed jobs."""

    figures: dict
    failed: list[Job] = field(default_factory=list)

    def summary(self) -> dict:
        return dict(self.figures)


def _executor(options: BatchOptions):
    if options.scheduler is not None:
        from usvtool.batch.cluster import DaskCluster

        if options.timeout is not None:
            raise UsvError("--timeout: not with --scheduler (a running Dask task cannot be "
                           "stopped)")  # fmt: skip
        return DaskCluster(options.scheduler)
    from usvtool.batch.local import LocalPool

    return LocalPool(options.workers or os.cpu_count() or 1, options.timeout)


def _capped(options: BatchOptions, jobs: int) -> BatchOptions:
    """``options`` with local workers no more than the ``jobs`` (``-j``, None: the cores), so
    that each job's share of the memory is the budget over the workers that can run."""
    if options.scheduler is not None:
        return options
    return replace(options, workers=max(1, min(options.workers or os.cpu_count() or 1, jobs)))


@contextmanager
def _locked(out: Path):
    """Hold ``out/.lock`` for the batch: a second batch in the same directory is refused. The
    lock is opened without truncating and never through a link (a ``.lock`` linked to a file
    elsewhere used to truncate that file)."""
    out.mkdir(parents=True, exist_ok=True)
    path = out / ".lock"
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_NOFOLLOW | os.O_NONBLOCK, 0o666)
    except OSError as exc:
        why = "a link" if exc.errno == errno.ELOOP else exc.strerror
        raise UsvError(f"-o {out}: cannot open its lock {path}: {why}; remove it") from None
    with os.fdopen(fd, "w") as lock:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise UsvError(f"-o {out}: its lock {path} is not a regular file; remove it")
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            raise UsvError(f"-o {out}: another batch is running in it") from None
        yield


def _refuse_links(out: Path, jobs: list[Job]) -> None:
    """Refuse a link where the batch writes its jobs' folders (``out/<kind>``): the results
    would land wherever it points."""
    for kind in sorted({j.kind for j in jobs}):
        if (out / kind).is_symlink():
            raise UsvError(f"-o {out}: {out / kind} is a link; the batch writes only inside -o: "
                           "remove it (or make it a folder)")  # fmt: skip


def _remove(path: Path, what: str) -> None:
    """Remove the folder ``path`` (only the link, if it is one); :class:`UsvError` naming it,
    the file refused and ``what`` it is when the system refuses."""
    try:
        if path.is_symlink():
            path.unlink()
        else:
            shutil.rmtree(path)
    except OSError as exc:
        where = f" ({exc.filename})" if exc.filename and str(exc.filename) != str(path) else ""
        raise UsvError(f"{path}: cannot remove {what}: {exc.strerror or exc}{where}") from None


def _remove_temporaries(out: Path) -> None:
    """Remove the hidden folders of jobs that did not finish (a link: the link only); what the
    system refuses stays, hidden and never read."""
    for stale in [*out.glob(f"*/{TMP_PREFIX}*"), *out.glob(f"{TMP_PREFIX}*")]:
        with contextlib.suppress(UsvError):
            _remove(stale, "a temporary folder")


def _state(job: Job, out: Path) -> bool | None:
    """True when the job's result is present, False when it failed before, None when absent
    (a link there is not a result: :func:`_clear` removes it)."""
    d = out / job.kind / job.key
    if not d.is_dir() or d.is_symlink():
        return None
    return not (d / "error.txt").is_file()


def _clear(jobs: list[Job], out: Path) -> list[tuple[Job, str]]:
    """Remove the directories of the jobs that failed before and of the damaged ones (their
    files are not those their ``job.json`` records; a link in place of the folder: the link
    only), so that they run again: the damaged jobs, each with what is wrong."""
    damaged = []
    for job in jobs:
        d = out / job.kind / job.key
        state = _state(job, out)
        problem = fault(d, job.key) if state else None
        if d.is_symlink():
            problem = f"{d}: a link, not the folder its job wrote (the link removed)"
        if state is False or problem is not None:
            _remove(d, f"the folder of {job.label} ({'failed' if problem is None else 'damaged'}) "
                    "to run it again")  # fmt: skip
        if problem is not None:
            damaged.append((job, problem))
    return damaged


def _complete(job: Job, out: Path) -> Outcome | None:
    """The outcome of a job whose worker died once its result was complete and in place (the
    files its ``job.json`` records): done (None when it is not)."""
    d = out / job.kind / job.key
    if not _state(job, out) or fault(d, job.key) is not None:
        return None
    return Outcome(None, json.loads((d / RECORD).read_text(encoding="utf-8"))["wall_time_s"])


class _Run:
    """The jobs to run, their dependencies, and what became of them."""

    def __init__(self, todo: list[Job], done_grids: set[str], progress: Lines):
        self.progress = progress
        self.ready: list[tuple[int, int, Job]] = []
        self.waiting: dict[str, list[Job]] = defaultdict(list)
        self.failed: list[Job] = []
        self.errors: dict[str, str] = {}
        self.stopped: str | None = None  # why no job starts any more
        self.not_run = 0
        self.stage_time: dict[str, float] = defaultdict(float)
        #: The groups (:func:`_groups`) whose first job is running (their other jobs wait for
        #: it), the groups one job of which has finished (:meth:`take`), and the groups each
        #: running job is the first of.
        self.priming: set = set()
        self.primed: set = set()
        self.firsts: dict[str, tuple] = {}
        for i, job in enumerate(todo):
            if job.needs is None or job.needs in done_grids:
                heapq.heappush(self.ready, (PRIORITY[job.kind], i, job))
            else:
                self.waiting[job.needs].append(job)
        self.count = len(todo)

    def take(self) -> Job | None:
        """The next ready job to start, or None when every ready job waits. A job waits while
        the first job of its kind, or of its kind and method, runs: that one compiles the numba
        kernels of the stage (of the method) into numba's cache on disk, which the others then
        load (0.5-1.5 s a process) rather than compile in every worker at once (15 s for the
        simulator's common kernels on a fresh clone, 12 s for a guided planner's own);
        meanwhile the other workers take the ready jobs of other kinds and methods."""
        held = []
        job = None
        while self.ready:
            entry = heapq.heappop(self.ready)
            groups = _groups(entry[2])
            if not self.priming.isdisjoint(groups):
                held.append(entry)
                continue
            job = entry[2]
            firsts = tuple(g for g in groups if g not in self.primed)
            if firsts:
                self.priming.update(firsts)
                self.firsts[job.key] = firsts
            break
        for entry in held:
            heapq.heappush(self.ready, entry)
        return job

    def finish(self, job: Job, error: str | None, wall: float = 0.0) -> None:
        firsts = self.firsts.pop(job.key, ())
        self.priming.difference_update(firsts)
        self.primed.update(firsts)
        self.stage_time[job.kind] += wall
        if error is not None:
            self.failed.append(job)
            self.errors[job.key] = error
        self.progress.advance(job.label, error)
        for route in self.waiting.pop(job.key, []) if job.kind == "grids" else []:
            if error is None:
                self.count += 1
                heapq.heappush(self.ready, (PRIORITY[route.kind], self.count, route))
            else:
                self.finish(route, f"its grid ({job.label}, {job.key}) failed")

    def stop(self, job: Job, reason: str) -> None:
        """Start no more jobs: the failure of ``job`` could not be recorded (``reason``)."""
        if self.stopped is None:
            self.stopped = f"cannot record the failure of {job.label} ({reason})"
        self.not_run += len(self.ready) + sum(map(len, self.waiting.values()))
        self.ready.clear()
        self.waiting.clear()


def _groups(job: Job) -> tuple:
    """The groups a job primes when it is their first (:meth:`_Run.take`): its kind, and its
    kind and method."""
    return job.kind, (job.kind, job.method)


def _run_jobs(executor, run: _Run, out: Path, command: Command) -> None:
    """Submit ready jobs (capacity x 2 in flight) until every job has finished."""
    finished: queue.Queue = queue.Queue()
    in_flight: dict = {}
    window = 2 * executor.capacity
    try:
        while run.ready or in_flight:
            while len(in_flight) < window and (job := run.take()) is not None:
                future = executor.submit(f"{job.kind}-{job.key}", execute, job, str(out), command,
                                         limited=True)  # fmt: skip
                in_flight[future] = job
                future.add_done_callback(finished.put)
            try:
                future = finished.get(timeout=0.5)
            except queue.Empty:
                run.progress.tick()
                continue
            job = in_flight.pop(future)
            try:
                outcome: Outcome = future.result()
            except Exception as exc:  # the task itself failed: its worker died, ...
                outcome = _complete(job, out) or record_failure(job, str(out),
                                                                 executor.failure(exc))
            run.finish(job, outcome.error, outcome.wall_time_s)
            if outcome.unrecorded is not None:
                run.stop(job, outcome.unrecorded)
    except BaseException:  # Ctrl-C, SIGTERM: stop the workers, keep what is complete
        executor.close(pending=list(in_flight))
        raise


def _measure(executor, pipeline, out: Path, jobs: list[Job], command: Command) -> dict:
    """The ``usvtool metrics`` rows of the routes and runs done, by view name: a command per
    part (:func:`results_tables.parts`), as many at once as the executor runs."""
    sim = pipeline.simulation
    reference = sim.reference_controller if sim is not None else None
    parts = results_tables.parts(out, jobs, executor.capacity)
    futures = [executor.submit("table", results_tables.measure, str(out), part, command,
                               reference) for part in parts]  # fmt: skip
    try:
        tables = [(part, future.result()) for part, future in zip(parts, futures, strict=True)]
        return results_tables.joined(tables)
    except UsvError:
        raise
    except Exception as exc:
        raise UsvError(f"usvtool metrics: {executor.failure(exc)}") from None


def _job_command(options: BatchOptions, capacity: int) -> Command:
    """The command the jobs run: each given the memory budget divided by the executor's
    capacity (the jobs that run at once; :func:`~usvtool.batch.worker.with_memory`)."""
    if options.max_memory is None and options.scheduler is not None:
        return options.command
    budget = options.max_memory or default_budget()
    return partial(with_memory, options.command, max(1, budget // capacity))


def run_batch(pipeline_path, options: BatchOptions) -> BatchResult:
    """Run every job of the pipeline not done yet in ``options.out``, then write
    ``metrics.csv``, ``timings.csv``, the pipeline's ``claims.json`` (and ``metrics.parquet``)
    there. Raises :class:`UsvError` for a bad pipeline, an executor that cannot start, or a
    table that cannot be made; failed jobs are in the result."""
    started = time.monotonic()
    pipeline = load(pipeline_path, options.names)
    check_expansion(pipeline, options.names, options.max_memory)
    jobs = expand(pipeline, options.names, options.scenario_files)
    out = Path(options.out).resolve()
    executor = _executor(_capped(options, len(jobs)))
    try:
        with _locked(out):
            _refuse_links(out, jobs)
            _remove_temporaries(out)
            damaged = _clear(jobs, out)  # a failed or damaged job runs again
            skipped = [j for j in jobs if _state(j, out)]  # a finished one is skipped
            todo = [j for j in jobs if not _state(j, out)]
            bar = options.progress if options.progress is not None else sys.stderr.isatty()
            progress = (Bar if bar else Lines)(len(jobs), len(skipped), executor.name)
            for job, problem in damaged:
                progress.say(f"batch: damaged, runs again: {job.label} ({job.key}): {problem}")
            run = _Run(todo, {j.key for j in skipped if j.kind == "grids"}, progress)
            try:
                _run_jobs(executor, run, out, _job_command(options, executor.capacity))
            finally:
                progress.close()
            if run.stopped is not None:
                _remove_temporaries(out)
                n = run.not_run
                raise UsvError(f"-o {out}: stopped: {run.stopped}; {n} job{'s' * (n != 1)} not "
                               "run (what is done is kept: run the batch again once it can "
                               "write there)")  # fmt: skip
            table_started = time.monotonic()
            done = [j for j in jobs if _state(j, out)]
            measured = [j for j in done if j.kind in results_tables.METHOD_COLUMN]
            table = _measure(executor, pipeline, out, measured, options.command) if measured else {}
            metrics, timings = results_tables.rows(done, table, out)
            parquet = results_tables.write(out / "metrics.csv", metrics, timings,
                                           pipeline.claims)  # fmt: skip
            run.stage_time["table"] = time.monotonic() - table_started
            _remove_temporaries(out)
    finally:
        executor.close()
    failed = run.failed
    failures = [{"kind": j.kind, "key": j.key, "case": j.case, "method": j.method,
                 "seed": j.seed, "error": run.errors[j.key]} for j in failed]  # fmt: skip
    figures = {
        "output": str(out),
        "metrics": str(out / "metrics.csv"),
        "timings": str(out / "timings.csv"),
        "parquet": None if parquet is None else str(parquet),
        "executor": executor.name,
        "jobs": len(jobs),
        "done": len(todo) - len(failed),
        "skipped": len(skipped),
        "failed": len(failed),
        "failures": failures,
        "wall_time_s": round(time.monotonic() - started, 3),
        "stage_time_s": {k: round(v, 3) for k, v in sorted(run.stage_time.items())},
    }
    return BatchResult(figures, failed)
