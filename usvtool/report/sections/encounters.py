"""The report's encounter section: per scenario, snapshots of the encounter with the ship
domains, the own ship's states against time, the distance to the nearest ship for every
controller, and a table of the run metrics; then COLREGs compliance per encounter.

A run job's files are ``trace.csv`` and ``trace.events.json`` in its directory. The events'
``run`` object holds the scenario as the simulator resolved it (docs/simulate.md): every ship's
name and length in the trace's order (``ships``; an unnamed target is ``target1``, ...), the
absolute paths of the ``map`` and the ``wind_field``. The report reads them there and never
the scenario YAML; events without them (written by an older usvtool) are refused, one line
saying to simulate the run again.
"""

from __future__ import annotations

import math
from functools import cache
from pathlib import Path
from typing import NamedTuple

import numpy as np

from usvtool.errors import UsvError
from usvtool.grid import read_grid
from usvtool.report import figures
from usvtool.report.data import JobResults, Results, stats
from usvtool.report.document import Cell, Figure, Section, Table, number
from usvtool.report.papers import CLAIMS
from usvtool.report.sections import published
from usvtool.trace import Trace, read_events, read_trace
from usvtool.wind import read_wind_field

#: The run table: (metric, column, decimals).
COLUMNS = (("arrival_time_s", "arrival (s)", 1), ("closest_distance_m", "closest (m)", 1),
           ("average_distance_m", "average (m)", 1), ("domain_intrusion_s", "in domain (s)", 1),
           ("length_m", "length (m)", 1), ("turns", "turns", 0))  # fmt: skip


@cache
def _trace(path: Path) -> Trace:
    return read_trace(path)


#: The keys of the events' ``run`` object the report reads (docs/simulate.md).
RUN_FACTS = ("ships", "map", "wind_field")
RERUN = "simulate the run again (usvtool batch reruns it when its directory is removed)"


@cache
def _events(path: Path) -> dict:
    return read_events(path)


class RunFiles(NamedTuple):
    """A run's trace and events, and the events' file (named in errors)."""

    trace: Trace
    events: dict
    path: Path


def run_files(job: JobResults) -> RunFiles | None:
    trace, events = job.dir / "trace.csv", job.dir / "trace.events.json"
    if not (trace.is_file() and events.is_file()):
        return None
    return RunFiles(_trace(trace), _events(events), events)


def run_facts(events: dict, where: Path | str) -> dict:
    """The events' ``run`` object, refused (naming ``where``) when it lacks :data:`RUN_FACTS`."""
    run = events.get("run")
    if not isinstance(run, dict):
        raise UsvError(f"{where}: the events hold no 'run' object (an older usvtool): {RERUN}")
    missing = [k for k in RUN_FACTS if k not in run]
    if missing:
        raise UsvError(f"{where}: run has no {', '.join(missing)} (written by an older usvtool, "
                       f"before the run held the scenario's facts): {RERUN}")  # fmt: skip
    return run


def lengths(trace: Trace, events: dict, where: Path | str) -> dict[str, float]:
    """Every ship's length by name, from the events' ``run.ships`` (the trace's ships, in its
    order, each with a length > 0 m)."""
    ships = run_facts(events, where)["ships"]
    if not isinstance(ships, list) or not all(isinstance(s, dict) for s in ships):
        raise UsvError(f"{where}: run.ships must be a list of {{name, length}}")
    names = tuple(s.get("name") for s in ships)
    if names != trace.ships:
        raise UsvError(f"{where}: run.ships name {len(names)} ship(s), not the trace's "
                       f"{', '.join(trace.ships)}: {RERUN}")  # fmt: skip
    for s in ships:
        length = s.get("length")
        if (isinstance(length, bool) or not isinstance(length, int | float)
                or not math.isfinite(length) or length <= 0):  # fmt: skip
            raise UsvError(f"{where}: run.ships: {s['name']}'s length {length!r} is not a "
                           "number > 0")  # fmt: skip
    return {s["name"]: float(s["length"]) for s in ships}


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


def primary(scenario: str, controllers: list[str]) -> str:
    """The controller whose snapshots a scenario shows: the one its paper runs there, i.e. that
    the papers' claims (:data:`usvtool.report.papers.CLAIMS`) test on the scenario's family
    (its name's first word: env1 gdwa, emergency udwa); for a family no claim tests, the first
    controller a claim tests (gdwa); the first of ``controllers`` when that one did not run.
    No controller's name is written here: a new controller is shown where it ran alone."""
    family = scenario.split("-")[0]
    runs = [c for c in CLAIMS if c.kind == "runs"]
    here = [c.method for c in runs if any(case.split("-")[0] == family for case in c.cases)]
    want = (here or [c.method for c in runs] or controllers)[0]
    return want if want in controllers else controllers[0]


def scenario_section(results: Results, scenario: str) -> Section:
    controllers = results.methods("runs", scenario)
    section = Section(f"encounter-{scenario}", f"Scenario {scenario}")
    runs = {c: min(results.select("runs", scenario, c), key=lambda j: j.seed or 0)
            for c in controllers}  # fmt: skip
    main = primary(scenario, controllers)
    files = run_files(runs[main])
    field_path = None
    if files is not None:
        trace, events, where = files
        grid_path = run_file(events, "map", where)
        field_path = run_file(events, "wind_field", where)
        grid = read_grid(grid_path) if grid_path else None
        times = figures.snapshot_times(trace, events)
        sizes = lengths(trace, events, where)
        plot = figures.encounter_snapshots(trace, times, sizes, grid=grid,
                                           title=f"{scenario}: {main}",
                                           goal=events.get("run", {}).get("goal"))  # fmt: skip
        section.blocks.append(Figure(
            f"encounter-{scenario}-snapshots", f"{scenario} with {main}",
            "The ships at the preparatory, meeting and completion states, with their tracks so "
            "far and their ship domains (7 L x 3 L ellipses).", plot.png, plot.data))
        plot = figures.states_against_time(trace)
        section.blocks.append(Figure(
            f"encounter-{scenario}-states", f"{scenario} with {main}: states",
            "The own ship's x, y and heading against time.", plot.png, plot.data))
    traces = {c: f.trace for c, f in ((c, run_files(j)) for c, j in runs.items()) if f}
    if field_path is not None and traces:
        field = read_wind_field(field_path)
        plot = figures.wind_runs(field.layers[0], field.layers[1], field.extent, traces,
                                 f"{scenario}: tracks over the wind field")  # fmt: skip
        section.blocks.append(Figure(
            f"encounter-{scenario}-wind", f"{scenario}: tracks over the wind field",
            "Wind speed (colour) and direction (arrows, where it blows) of the scenario's "
            "field, with each controller's track (UDWA paper, Figs. 19-20).", plot.png,
            plot.data))
    if traces and any(len(t.ships) > 1 for t in traces.values()):
        plot = figures.nearest_distance(traces, f"{scenario}: distance to the nearest ship")
        section.blocks.append(Figure(
            f"encounter-{scenario}-distance", f"{scenario}: distance to the nearest ship",
            "Centre distance from the own ship to the nearest other ship, per controller.",
            plot.png, plot.data))
    section.blocks.append(run_table(results, scenario, controllers))
    return section


def run_table(results: Results, scenario: str, controllers: list[str]) -> Table:
    rows = []
    for c in controllers:
        jobs = results.select("runs", scenario, c)
        arrived = results.values("runs", scenario, c, "arrived")
        collided = sum(1 for j in jobs if j.text("collision"))
        cells = [Cell(c), number(100 * float(np.mean(arrived)) if arrived else None, 0),
                 Cell(str(collided), "num" + (" fails" if collided else ""))]  # fmt: skip
        for metric, _, digits in COLUMNS:
            cells.append(number(stats(results.values("runs", scenario, c, metric))["median"],
                                digits))  # fmt: skip
        judged = sum(results.values("runs", scenario, c, "judged"))
        compliant = sum(results.values("runs", scenario, c, "compliant"))
        cells.append(Cell(f"{compliant:.0f} / {judged:.0f}", "num"))
        rows.append(cells)
    columns = ["controller", "arrived (%)", "collisions", *(c for _, c, _ in COLUMNS),
               "COLREGs compliant"]  # fmt: skip
    return Table(f"encounter-{scenario}-table", f"Runs of {scenario}",
                 "Medians over seeds; compliant / judged counts the encounters whose COLREGs "
                 "verdict holds (docs/colregs.md).", columns, rows)


def compliance_table(results: Results) -> Table:
    """Every scenario's encounters x controllers: compliant / judged, failed rules."""
    scenarios = [s for s in results.cases("runs")
                 if any(results.values("runs", s, c, "judged")
                        for c in results.methods("runs", s))]  # fmt: skip
    controllers = sorted({c for s in scenarios for c in results.methods("runs", s)},
                         key=lambda c: results.methods("runs").index(c))  # fmt: skip
    rows = []
    for s in scenarios:
        cells = [Cell(s)]
        for c in controllers:
            judged = sum(results.values("runs", s, c, "judged"))
            compliant = sum(results.values("runs", s, c, "compliant"))
            failed = sorted({r for j in results.select("runs", s, c)
                             for r in (j.text("failed_rules") or "").split(";") if r})  # fmt: skip
            text = f"{compliant:.0f}/{judged:.0f}" + (f" ({', '.join(failed)})" if failed else "")
            css = "holds" if judged and compliant == judged else "fails" if judged else ""
            cells.append(Cell(text, css))
        rows.append(cells)
    return Table("colregs-compliance", "COLREGs compliance per encounter and controller",
                 "Compliant / judged encounters over seeds, with the rules failed "
                 "(docs/colregs.md).", ["scenario", *controllers], rows)


def section(results: Results) -> Section | None:
    scenarios = results.cases("runs")
    if not scenarios:
        return None
    top = Section("encounters", "Collision avoidance in encounters")
    top.paragraphs.append(
        "Every bundled scenario with every controller: DWA toward the goal, the route-guided "
        "DWA of IWSO-DWA (gdwa), CCDWA and UDWA. Snapshots show the controller the scenario's "
        "paper uses.")
    top.blocks += published.tables(results, "runs")
    top.blocks.append(compliance_table(results))
    top.subsections = [scenario_section(results, s) for s in scenarios]
    return top
