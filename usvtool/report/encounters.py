"""The report's encounter section: per scenario, snapshots of the encounter with the ship
domains, the own ship's states against time, the distance to the nearest ship for every
controller, and a table of the run metrics; then COLREGs compliance per encounter.

A run job's files are ``trace.csv`` and ``trace.events.json`` in its directory; the events'
``run`` object gives the own ship's length, and the scenario file named by the job's
``job.json`` the targets' lengths, the map and the weather field.
"""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path

import numpy as np

from usvtool.errors import UsvError
from usvtool.grid import read_grid
from usvtool.report import figures, published
from usvtool.report.data import Job, Results, stats
from usvtool.report.document import Cell, Figure, Section, Table, number
from usvtool.trace import Trace, read_trace
from usvtool.wind import read_wind_field

#: The controller whose snapshots are shown, by the scenario's family (its name's first word):
#: the one its paper runs there.
PRIMARY = {"env1": "gdwa", "env2": "gdwa", "emergency": "udwa", "wind": "udwa"}
#: The run table: (metric, column, decimals).
COLUMNS = (("arrival_time_s", "arrival (s)", 1), ("closest_distance_m", "closest (m)", 1),
           ("average_distance_m", "average (m)", 1), ("domain_intrusion_s", "in domain (s)", 1),
           ("length_m", "length (m)", 1), ("turns", "turns", 0))  # fmt: skip


@cache
def _trace(path: Path) -> Trace:
    return read_trace(path)


@cache
def _events(path: Path) -> dict:
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as e:
        raise UsvError(f"{path}: cannot read the events JSON ({e})") from None


def run_files(job: Job) -> tuple[Trace, dict] | None:
    trace, events = job.dir / "trace.csv", job.dir / "trace.events.json"
    if not (trace.is_file() and events.is_file()):
        return None
    return _trace(trace), _events(events)


@cache
def _scenario(path: str) -> dict:
    import yaml

    try:
        data = yaml.safe_load(Path(path).read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError) as e:
        raise UsvError(f"{path}: cannot read the scenario ({' '.join(str(e).split())})") from None
    return data if isinstance(data, dict) else {}


def scenario_file(job: Job, *keys: str) -> Path | None:
    """A file the run's scenario names (``map``; ``weather``, ``field``), resolved against the
    scenario file of the job's ``job.json`` (docs/scenario.md: paths are relative to it)."""
    scenario = job.config.get("scenario")
    value = _scenario(scenario) if scenario and Path(scenario).is_file() else {}
    for key in keys:
        value = value.get(key) if isinstance(value, dict) else None
    if not isinstance(value, str):
        return None
    path = (Path(scenario).parent / value).resolve()
    return path if path.is_file() else None


def lengths(job: Job, trace: Trace, events: dict) -> dict[str, float]:
    """Every ship's length: the own ship's from the events' ``run.own_length``, each target's
    from its entry in the scenario file (``targets[].length``, required there; matched by
    ``name``); a ship found in neither takes the own ship's."""
    own = float(events.get("run", {}).get("own_length", 1.0))
    scenario = job.config.get("scenario")
    data = _scenario(scenario) if scenario and Path(scenario).is_file() else {}
    known = {str(t.get("name")): float(t["length"]) for t in data.get("targets") or []
             if isinstance(t, dict) and isinstance(t.get("length"), int | float)}  # fmt: skip
    return {s: own if s == "own" else known.get(s, own) for s in trace.ships}


def primary(scenario: str, controllers: list[str]) -> str:
    want = PRIMARY.get(scenario.split("-")[0], "gdwa")
    return want if want in controllers else controllers[0]


def scenario_section(results: Results, scenario: str) -> Section:
    controllers = results.methods("runs", scenario)
    section = Section(f"encounter-{scenario}", f"Scenario {scenario}")
    runs = {c: min(results.select("runs", scenario, c), key=lambda j: j.seed or 0)
            for c in controllers}  # fmt: skip
    main = primary(scenario, controllers)
    files = run_files(runs[main])
    grid_path = scenario_file(runs[main], "map")
    field_path = scenario_file(runs[main], "weather", "field")
    if files is not None:
        trace, events = files
        grid = read_grid(grid_path) if grid_path else None
        times = figures.snapshot_times(trace, events)
        sizes = lengths(runs[main], trace, events)
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
    traces = {c: f[0] for c, f in ((c, run_files(j)) for c, j in runs.items()) if f}
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
