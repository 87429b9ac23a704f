"""A simulated run as the report's sections read it: its files, the facts of its scenario, its
state at the start and the words for how it ended.

A run job's files are ``trace.csv`` and ``trace.events.json`` in its directory (the
:mod:`usvtool.trace` contract). The events' ``run`` object holds the scenario as the simulator
resolved it (``usvtool/sim/run.py``, docs/simulate.md): every ship's name and length in the
trace's order (``ships``; an unnamed target is ``target1``, ...), the goal, the scenario's
duration (``duration_s``), the own ship's vessel preset (``vessel_preset``) and figures
(``vessel``, ``own_length``), the absolute paths of the ``map`` and the ``wind_field``. The
ships' positions, headings and speeds at the start are the trace's first step
(:func:`first_step`). The sections read these and never the scenario YAML, which may have
changed since the run; events without a key a section needs (written by an older usvtool) are
refused in one line saying to simulate the run again (:func:`run_facts`).

The outcome vocabulary the encounter, Imazu, traffic and wind sections share: a run
**collided** (whatever else), **arrived**, or **did not arrive** (:func:`outcome`); the last
two are failures, and a failed run's encounters are never compliant (:data:`COUNTS`). The
results table's COLREGs counts are :data:`VERDICTS`; :class:`RunTally` sums both over runs.
"""

from __future__ import annotations

import csv
import math
from functools import cache
from pathlib import Path
from typing import NamedTuple

from usvtool.errors import UsvError
from usvtool.report import inference
from usvtool.report.data import JobResults, Results
from usvtool.report.document import Cell
from usvtool.trace import HEADER, OWN, Trace, read_events, read_trace

#: The keys of the events' ``run`` object every section that reads a run's files needs
#: (docs/simulate.md); :func:`run_facts` refuses events without them or the ones asked for.
RUN_FACTS = ("ships", "map", "wind_field")
RERUN = "simulate the run again (usvtool batch reruns it when its directory is removed)"
TRACE, EVENTS = "trace.csv", "trace.events.json"


@cache
def _trace(path: Path) -> Trace:
    return read_trace(path)


@cache
def _events(path: Path) -> dict:
    return read_events(path)


class RunFiles(NamedTuple):
    """A run's trace and events, and the events' file (named in errors)."""

    trace: Trace
    events: dict
    path: Path


def run_files(job: JobResults) -> RunFiles | None:
    """The run's trace and events, each read once per report; None without them."""
    trace, events = job.dir / TRACE, job.dir / EVENTS
    if not (trace.is_file() and events.is_file()):
        return None
    return RunFiles(_trace(trace), _events(events), events)


def job_events(job: JobResults) -> tuple[dict, Path] | None:
    """The run's events (read once per report) and their file; None without it."""
    path = job.dir / EVENTS
    return (_events(path), path) if path.is_file() else None


def run_facts(events: dict, where: Path | str, keys: tuple[str, ...] = ()) -> dict:
    """The events' ``run`` object, refused (naming ``where``) when it lacks :data:`RUN_FACTS`
    or one of ``keys``."""
    run = events.get("run")
    if not isinstance(run, dict):
        raise UsvError(f"{where}: the events hold no 'run' object (an older usvtool): {RERUN}")
    missing = [k for k in (*RUN_FACTS, *keys) if k not in run]
    if missing:
        raise UsvError(f"{where}: run has no {', '.join(missing)} (written by an older usvtool, "
                       f"before the run held the scenario's facts): {RERUN}")  # fmt: skip
    return run


def job_facts(job: JobResults, keys: tuple[str, ...] = ()) -> dict | None:
    """The ``run`` object of the job's events (:func:`run_facts`); None without events."""
    found = job_events(job)
    return None if found is None else run_facts(*found, keys)


def lengths(trace: Trace, events: dict, where: Path | str) -> dict[str, float]:
    """Every ship's length by name, from the events' ``run.ships`` (the trace's ships, in its
    order, each with a length > 0 m)."""
    return dict(zip(trace.ships, ship_lengths(events, where, trace.ships), strict=True))


def ship_lengths(events: dict, where: Path | str, names: tuple[str, ...] | None = None) -> tuple:
    """Every ship's length from the events' ``run.ships`` (each > 0 m), in their order; with
    ``names``, refused unless they are those ships (the trace's)."""
    ships = run_facts(events, where)["ships"]
    if not isinstance(ships, list) or not all(isinstance(s, dict) for s in ships):
        raise UsvError(f"{where}: run.ships must be a list of {{name, length}}")
    found = tuple(s.get("name") for s in ships)
    if names is not None and found != names:
        raise UsvError(f"{where}: run.ships name {len(found)} ship(s), not the trace's "
                       f"{', '.join(names)}: {RERUN}")  # fmt: skip
    for s in ships:
        length = s.get("length")
        if (isinstance(length, bool) or not isinstance(length, int | float)
                or not math.isfinite(length) or length <= 0):  # fmt: skip
            raise UsvError(f"{where}: run.ships: {s.get('name')}'s length {length!r} is not a "
                           "number > 0")  # fmt: skip
    return tuple(float(s["length"]) for s in ships)


def run_file(events: dict, key: str, where: Path | str) -> Path | None:
    """The run's ``map`` or ``wind_field`` (``key``) as the run resolved it (a relative path
    is relative to the events file ``where``'s folder); None when it had none. Refused when
    the file is gone since."""
    value = run_facts(events, where)[key]
    if value is None:
        return None
    if not isinstance(value, str):
        raise UsvError(f"{where}: run.{key} must be a path or null")
    path = Path(where).parent / value  # a relative path is the events file's folder's
    if not path.is_file():
        raise UsvError(f"{where}: run.{key} {value}: no such file (moved or removed since the "
                       "run?)")  # fmt: skip
    return path


class State(NamedTuple):
    """A ship at the trace's first step: map metres, compass degrees, m/s."""

    x: float
    y: float
    heading: float
    speed: float


@cache
def first_step(path: Path) -> dict[str, State]:
    """Every ship's state at a trace's first step, by name in the trace's order (the own ship
    first), reading only that step's rows (a trace of recorded traffic runs to megabytes)."""
    states: dict[str, State] = {}
    try:
        with open(path, encoding="utf-8", newline="") as f:
            rows = csv.reader(f)
            if next(rows, None) != list(HEADER):
                raise UsvError(f"{path}: line 1: not a trace (its header must be "
                               f"{','.join(HEADER)})")  # fmt: skip
            first = None
            for line, row in enumerate(rows, start=2):
                if len(row) != len(HEADER):
                    raise UsvError(f"{path}: line {line}: {len(row)} fields, expected "
                                   f"{len(HEADER)}")  # fmt: skip
                if first is None:
                    first = row[0]
                elif row[0] != first:
                    break
                try:
                    x, y, heading, speed = (float(v) for v in row[2:6])
                except ValueError:
                    raise UsvError(f"{path}: line {line}: not numbers: {','.join(row[2:6])}"
                                   ) from None  # fmt: skip
                states[row[1]] = State(x, y, heading, speed)
    except UnicodeDecodeError:
        raise UsvError(f"{path}: not UTF-8 text") from None
    if next(iter(states), None) != OWN:
        raise UsvError(f"{path}: the first step does not start with the own ship ({OWN!r})")
    return states


def start(job: JobResults) -> dict[str, State] | None:
    """The run's ships at its start (:func:`first_step` of its trace); None without it."""
    path = job.dir / TRACE
    return first_step(path) if path.is_file() else None


# --- outcomes and COLREGs counts ------------------------------------------------------------

#: The results table's COLREGs counts (docs/colregs.md, "Counting"): every encounter of a run in
#: exactly one; what each says of an encounter, and its column's heading.
VERDICTS = ("compliant", "compliant_excused", "noncompliant", "not_judged")
VERDICT_WORDS = dict(zip(VERDICTS, ("compliant", "compliant only by an excused Rule 2 departure",
                                    "non-compliant", "not judged"), strict=True))  # fmt: skip
VERDICT_HEADINGS = ("compliant", "excused only", "non-compliant", "not judged")
#: A run's outcomes, each in its own column: a run that did not arrive is a failure.
OUTCOMES = ("arrived", "collided", "did not arrive")
#: Scene families with a section of their own (the Imazu problem, recorded traffic), left out of
#: the encounters' families table; a run's family is its ``job.json``'s ``scene.family``.
OWN_SECTION = ("imazu", "ais")
COUNTS = ("A run that did not arrive or collided is a failure: its encounters are all 'not "
          "judged', never compliant (docs/colregs.md, 'Counting'). Excused only: compliant "
          "only through an excused Rule 2 departure, i.e. because the controller's Rule 2 "
          "record excused a failed side or stand-on rule.")  # fmt: skip
#: How a count above 0 is marked.
MARKS = {"noncompliant": " fails", "not_judged": " untested"}
TALLY_COLUMNS = [*OUTCOMES, *VERDICT_HEADINGS]


def is_family(case: str) -> bool:
    """Whether a run's case is a scene of a scene family (``ENTRY/KIND/sNNN``)."""
    return "/" in case


def family(job: JobResults) -> str | None:
    """The scene family of the run (its ``job.json``'s ``scene.family``); None for a bundled
    scenario's."""
    return (job.config.get("scene") or {}).get("family")


def own_section(job: JobResults) -> bool:
    """Whether the run is a scene of a family with a section of its own (:data:`OWN_SECTION`)."""
    return family(job) in OWN_SECTION


def family_kind(case: str) -> str:
    """A family scene's ``ENTRY/KIND`` (``emergency/head-on`` of ``emergency/head-on/s007``)."""
    return case.rsplit("/", 1)[0]


def family_runs(results: Results, name: str) -> dict[str, dict[str, JobResults]]:
    """The runs of the scene family ``name`` (:func:`family`), whatever the pipeline's entry is
    called: case (``ENTRY/KIND/sNNN``) -> controller -> the run of its lowest seed."""
    runs: dict[str, dict[str, JobResults]] = {}
    for job in results.select("runs"):
        if family(job) != name or not is_family(job.case):
            continue
        mine = runs.setdefault(job.case, {})
        if job.method not in mine or (job.seed or 0) < (mine[job.method].seed or 0):
            mine[job.method] = job
    return dict(sorted(runs.items()))


def outcome(job: JobResults) -> str:
    """The run's :data:`OUTCOMES`: collided (whatever else), arrived, or did not arrive."""
    if job.text("collision"):
        return "collided"
    return "arrived" if job.number("arrived") == 1.0 else "did not arrive"


class RunTally(NamedTuple):
    """The outcomes of some runs and the sum of their COLREGs counts (None when a run's row
    lacks them: a table written before the counts were split)."""

    outcomes: dict[str, int]
    verdicts: dict[str, int] | None

    @classmethod
    def of(cls, jobs: list[JobResults]) -> RunTally:
        outcomes = dict.fromkeys(OUTCOMES, 0)
        for j in jobs:
            outcomes[outcome(j)] += 1
        counts = [[j.number(v) for v in VERDICTS] for j in jobs]
        split = None if any(None in c for c in counts) else {
            v: int(sum(c[i] for c in counts)) for i, v in enumerate(VERDICTS)}  # fmt: skip
        return cls(outcomes, split)

    def cells(self) -> list[Cell]:
        """The outcomes (failures marked) and the four counts (``-`` when unknown)."""
        cells = []
        for name, n in self.outcomes.items():
            cells.append(Cell(str(n), "num" + (" fails" if n and name != "arrived" else "")))
        for v in VERDICTS:
            n = None if self.verdicts is None else self.verdicts[v]
            css = MARKS.get(v, "") if n else ""
            cells.append(Cell("-" if n is None else str(n), "num" + css))
        return cells


def median_iqr(values: list[float], digits: int = 1) -> Cell:
    """``median (IQR width)`` of the values, as the claims table gives them
    (:func:`usvtool.report.inference.median` and :func:`~usvtool.report.inference.iqr`)."""
    if not values:
        return Cell("-", "num")
    med, spread = inference.median(values), inference.iqr(values)
    return Cell(f"{med:.{digits}f} (IQR {spread:.{digits}f})", "num")


def controller_failed(job: JobResults) -> bool:
    """Whether the run's controller failed and ended it: its ``controller_failed`` row (``usvtool
    metrics`` writes one, ``True``, only then; docs/metrics.md). Such a run has not arrived, so
    :func:`outcome` counts it as did not arrive: a failure. A row saying it arrived all the same
    (no ``usvtool metrics`` writes that) is refused, so that it never counts as a success."""
    if job.text("controller_failed") in (None, "", "False"):
        return False
    if job.number("arrived") == 1.0 and not job.text("collision"):
        raise UsvError(f"job {job.key} ({job.case}, {job.method}): its controller failed, yet "
                       "its arrived row says True: usvtool metrics never writes that; run the "
                       "batch again")  # fmt: skip
    return True
