"""The report's encounter section: the scene families' outcomes and COLREGs counts per family
kind and controller (the claims rest on them), the thresholds the verdicts used, the bundled
scenarios' compliance per controller, and, in the appendix, every bundled run's encounters and
one illustrated subsection per bundled scenario (snapshots of the encounter with the ship
domains, the own ship's states against time, the distance to the nearest ship for every
controller, a table of the run metrics).

A run that did not arrive or collided is a failure, counted in its own columns; its encounters
are never compliant. The COLREGs counts are the results table's (``usvtool metrics``:
``compliant``, ``compliant_excused``, ``noncompliant``, ``not_judged``; docs/colregs.md,
"Counting"); the thresholds are those the events files record (``thresholds``).

The runs' files, the facts of their scenarios (the events' ``run`` object, never the scenario
YAML) and the outcome vocabulary are :mod:`usvtool.report.runs`'.
"""

from __future__ import annotations

import numpy as np

from usvtool.grid import read_grid
from usvtool.report import figures
from usvtool.report.data import JobResults, Results, stats
from usvtool.report.document import APPENDIX, Cell, Figure, Section, Table, number
from usvtool.report.papers import CLAIMS, UDWA_WIND
from usvtool.report.runs import (
    COUNTS,
    TALLY_COLUMNS,
    VERDICT_WORDS,
    RunTally,
    family_kind,
    is_family,
    job_events,
    lengths,
    median_iqr,
    own_section,
    run_facts,
    run_file,
    run_files,
)
from usvtool.report.sections import published

#: The run table: (metric, column, decimals).
COLUMNS = (("arrival_time_s", "arrival (s)", 1), ("closest_distance_m", "closest (m)", 1),
           ("average_distance_m", "average (m)", 1), ("domain_intrusion_s", "in domain (s)", 1),
           ("length_m", "length (m)", 1), ("turns", "turns", 0))  # fmt: skip


def primary(scenario: str, controllers: list[str]) -> str:
    """The controller whose snapshots a scenario shows: the one its paper runs there, i.e. that
    the papers' claims (:data:`usvtool.report.papers.CLAIMS`) test on the scenario's family
    (its name's first word, a scene family's entry: emergency and emergency/head-on udwa);
    for a family no claim tests, the first controller a claim tests (gdwa); the first of
    ``controllers`` when that one did not run. No controller's name is written here: a new
    controller is shown where it ran alone."""

    def family(case: str) -> str:
        return case.split("/")[0].split("-")[0]

    runs = [c for c in CLAIMS if c.kind == "runs"]
    here = [c.method for c in runs if any(family(case) == family(scenario) for case in c.cases)]
    want = (here or [c.method for c in runs] or controllers)[0]
    return want if want in controllers else controllers[0]


def scenario_section(results: Results, scenario: str) -> Section:
    controllers = results.methods("runs", scenario)
    section = Section(f"encounter-{scenario}", f"Scenario {scenario}", placement=APPENDIX)
    runs = {c: min(results.select("runs", scenario, c), key=lambda j: j.seed or 0)
            for c in controllers}  # fmt: skip
    main = primary(scenario, controllers)
    files = run_files(runs[main])
    if files is not None:
        trace, events, where = files
        grid_path = run_file(events, "map", where)
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
        rows.append(cells)
    columns = ["controller", "arrived (%)", "collisions", *(c for _, c, _ in COLUMNS)]
    return Table(f"encounter-{scenario}-table", f"Runs of {scenario}",
                 "Medians over seeds; the COLREGs counts are in the bundled scenarios' "
                 "compliance table.", columns, rows)


# --- outcomes and COLREGs counts ------------------------------------------------------------


def _controllers(results: Results, jobs: list[JobResults]) -> list[str]:
    """The controllers of ``jobs`` in the report's order."""
    return [c for c in results.methods("runs") if any(j.method == c for j in jobs)]


def families_table(results: Results) -> Table | None:
    """Per family kind (but :data:`OWN_SECTION`'s) and controller: the runs, their outcomes,
    their encounters' COLREGs counts and the median closest distance with its IQR."""
    jobs = [j for j in results.select("runs")
            if is_family(j.case) and not own_section(j)]
    if not jobs:
        return None
    rows = []
    for kind in sorted({family_kind(j.case) for j in jobs}):
        mine = [j for j in jobs if family_kind(j.case) == kind]
        scenes = len({j.case for j in mine})
        for c in _controllers(results, mine):
            runs = [j for j in mine if j.method == c]
            closest = [v for v in (j.number("closest_distance_m") for j in runs) if v is not None]
            rows.append([Cell(kind), Cell(str(scenes), "num"), Cell(c), *RunTally.of(runs).cells(),
                         median_iqr(closest)])  # fmt: skip
    return Table("encounter-families", "Scene families: outcomes and COLREGs per kind and "
                 "controller",
                 "Each kind's seeded scenes (docs/families.md), the same scenes for every "
                 "controller. Outcomes: runs (scenes x seeds); COLREGs: encounters summed "
                 "over the runs. " + COUNTS + " Closest: the smallest distance to any "
                 "ship (m), median (IQR width) over the runs, collided ones included. The "
                 "thresholds: the next table.",
                 ["family/kind", "scenes", "controller", *TALLY_COLUMNS, "closest (m)"], rows)


def compliance_table(results: Results) -> Table | None:
    """The bundled scenarios with encounters, per controller: the runs' outcomes, their
    encounters' COLREGs counts and the rules failed and excused."""
    scenarios = [s for s in results.cases("runs") if not is_family(s)
                 and any(n for c in results.methods("runs", s)
                         for n in results.values("runs", s, c, "encounters"))]  # fmt: skip
    if not scenarios:
        return None
    rows = []
    for s in scenarios:
        for c in results.methods("runs", s):
            jobs = results.select("runs", s, c)
            failed, excused = (
                sorted({r for j in jobs for r in (j.text(m) or "").split(";") if r})
                for m in ("failed_rules", "excused_rules"))  # fmt: skip
            rules = ", ".join(failed) + (f" (excused: {', '.join(excused)})" if excused else "")
            rows.append([Cell(s), Cell(c), *RunTally.of(jobs).cells(), Cell(rules.strip())])
    return Table("colregs-compliance", "Bundled scenarios: outcomes and COLREGs per controller",
                 "The bundled scenarios with encounters (illustrated examples: one run per "
                 "seed; the claims rest on the scene families). " + COUNTS + " Rules failed and "
                 "(excused): in the judged encounters (docs/colregs.md). The thresholds: the "
                 "main body's table.",
                 ["scenario", "controller", *TALLY_COLUMNS, "rules failed (excused)"], rows,
                 placement=APPENDIX)


# --- the thresholds the verdicts used --------------------------------------------------------

#: What each threshold of the events' ``thresholds`` (written by the simulation's verdicts)
#: is: its label, its unit, and whether it scales with the own ship's length (then shown in
#: own lengths L beside the metres). A key not listed here is shown under its own name.
THRESHOLDS = {
    "risk_distance_m": ("onset: predicted CPA closer than", "m", True),
    "horizon_s": ("onset: TCPA within", "s", False),
    "clear_distance_m": ("release: opening and range beyond", "m", True),
    "release_distance_m": ("release: range beyond", "m", True),
    "head_on_bearing_deg": ("head-on: both relative bearings within", "deg", False),
    "stern_sector_deg": ("overtaking: stern sector (relative bearing)", "deg", False),
    "domain_axes_m": ("ship domain: ellipse's full axes, along x across", "m", True),
    "critical_range_m": ("critical range r_crit (Rules 16, 17)", "m", True),
    "manoeuvre": ("a manoeuvre: within the window, a change of at least", "", False),
    "apparent": ("Rule 8 readily apparent: a course change or a speed reduction of at "
                 "least", "", False),
    "timely_range_fraction": ("Rule 16 in time: starts at a range of at least (x onset "
                              "range)", "", False),
    "stand_on": ("Rule 17 stand-on: heading and speed kept within", "", False),
}  # fmt: skip


#: The unit of a threshold object's entry, by its name's suffix (``course_deg``: deg).
SUFFIXES = {"_deg": "deg", "_s": "s", "_m": "m"}


def _value(value) -> str:
    """A threshold's value as the events file gives it: numbers as written, null as none, a
    list joined by ' - ' (a sector), an object's entries by ' / ' with their units."""
    if value is None:
        return "none"
    if isinstance(value, dict):
        return " / ".join(_entry(k, v) for k, v in value.items())
    if isinstance(value, list):
        return " - ".join(map(_value, value))
    return f"{value:g}" if isinstance(value, float) else str(value)


def _entry(name: str, value) -> str:
    """``course 30 deg`` of an object's entry ``course_deg: 30``."""
    for suffix, unit in SUFFIXES.items():
        if name.endswith(suffix):
            return f"{name.removesuffix(suffix).replace('_', ' ')} {_value(value)} {unit}"
    return f"{name.replace('_', ' ')} {_value(value)}"


def _scaled(values: list[tuple[object, float | None]]) -> str:
    """A length-scaled threshold over runs (``(value, own length)`` pairs): in own lengths L
    with the metres it came to, ``3.5 L (52.5 m)``, ``3.5 L (8.75-52.5 m)``, ``7 L x 3 L
    (17.5-105 m x 7.5-45 m)``; a value that is not a number as it is."""
    texts = []
    for factor in sorted({_factors(v, length) for v, length in values}, key=str):
        mine = [v for v, length in values if _factors(v, length) == factor]
        if factor is None:
            texts.append(", ".join(sorted({_value(v) for v in mine})))
            continue
        axes = list(zip(*(v if isinstance(v, list) else [v] for v in mine), strict=True))
        spans = [f"{min(a):g}" if min(a) == max(a) else f"{min(a):g}-{max(a):g}" for a in axes]
        texts.append(" x ".join(f"{f:g} L" for f in factor) + f" ({' m x '.join(spans)} m)")
    return "; ".join(texts)


def _factors(value, length: float | None) -> tuple[float, ...] | None:
    """The value (a number or a list of them) in own lengths, to 4 decimals; None when it is
    not a number or the length is unknown."""
    parts = value if isinstance(value, list) else [value]
    if not length or not all(isinstance(x, int | float) for x in parts):
        return None
    return tuple(round(x / length, 4) for x in parts)


def thresholds_table(jobs: list[JobResults]) -> Table | None:
    """The thresholds the verdicts of ``jobs`` used, read from their events files
    (``thresholds``; the own ship's length from ``run.own_length``): every value found."""
    found: dict[str, list[tuple[object, float | None]]] = {}
    for job in jobs:
        files = job_events(job)
        if files is None:
            continue
        run = files[0].get("run") or {}
        for key, value in (files[0].get("thresholds") or {}).items():
            found.setdefault(key, []).append((value, run.get("own_length")))
    if not found:
        return None
    rows = []
    for key in [*(k for k in THRESHOLDS if k in found), *sorted(set(found) - set(THRESHOLDS))]:
        label, unit, scaled = THRESHOLDS.get(key, (key, "", False))
        values = found[key]
        text = (_scaled(values) if scaled else
                "; ".join(sorted({_value(v) for v, _ in values})))  # fmt: skip
        rows.append([Cell(label), Cell(text + (f" {unit}" if unit and not scaled else "")),
                     Cell(key)])  # fmt: skip
    return Table("colregs-thresholds", "The thresholds of the encounters and verdicts",
                 f"As the events files of the {len(jobs)} runs of the tables beside record them "
                 "(trace.events.json's thresholds; every distinct value; L = the own ship's "
                 "length). The rules and their sources: docs/colregs.md.",
                 ["threshold", "value", "events key"], rows)


# --- every encounter of the bundled runs -----------------------------------------------------


def encounter_verdict(encounter: dict, run: dict) -> str:
    """An encounter's count, in words, as ``usvtool metrics`` counts it (its ``verdict``;
    docs/colregs.md, "Counting"): not judged when the run did not arrive or collided (saying
    which) or the encounter has no verdict."""
    if run.get("collision"):
        return "not judged: collided"
    if not run.get("arrived"):
        return "not judged: did not arrive"
    if encounter.get("compliant") is None:
        return "not judged: no verdict"
    if not encounter["compliant"]:
        return VERDICT_WORDS["noncompliant"]
    return VERDICT_WORDS["compliant_excused" if encounter.get("excused_rules") else "compliant"]


def encounter_table(results: Results, scenarios: list[str]) -> Table | None:
    """Every encounter of the bundled scenarios' runs: the target, the class, onset, TCPA,
    CPA, the verdict, the rules failed and excused and the Rule 2 records, from the events."""
    rows = []
    for s in scenarios:
        for c in results.methods("runs", s):
            for job in sorted(results.select("runs", s, c), key=lambda j: j.seed or 0):
                found = job_events(job)
                if found is None:
                    continue
                run = run_facts(*found)
                names = [ship.get("name") for ship in run["ships"][1:]]
                for e in found[0].get("encounters") or []:
                    if e.get("class", "none") == "none":
                        continue
                    onset, cpa = e.get("onset_s"), e.get("cpa_time_s")
                    rows.append([
                        Cell(s), Cell(c), Cell(str(job.seed)), Cell(str(names[e["target"]])),
                        Cell(e["class"]), number(onset, 1),
                        number(None if None in (onset, cpa) else cpa - onset, 1),
                        number(e.get("closest_distance_m"), 1),
                        Cell(encounter_verdict(e, run),
                             "fails" if e.get("compliant") is False else ""),
                        Cell(", ".join(e.get("failed_rules") or [])),
                        Cell(", ".join(e.get("excused_rules") or [])),
                        Cell(str(len(e.get("rule2_departure") or [])), "num"),
                    ])  # fmt: skip
    if not rows:
        return None
    return Table("colregs-encounters", "Every encounter of the bundled scenarios' runs",
                 "From each run's events file: onset (s), TCPA = the time from the onset to "
                 "the CPA (s), CPA = the distance at the closest point of approach (m), the "
                 "verdict as the tables count it, the rules the evaluator found failed and "
                 "excused (shown for a run not judged too), and the Rule 2 departure records "
                 "the controller made in the encounter.",
                 ["scenario", "controller", "seed", "target", "class", "onset (s)", "TCPA (s)",
                  "CPA (m)", "verdict", "rules failed", "rules excused", "Rule 2 records"],
                 rows, placement=APPENDIX)  # fmt: skip


def section(results: Results) -> Section | None:
    cases = results.cases("runs")
    if not cases:
        return None
    scenarios = [s for s in cases if not is_family(s)]
    top = Section("encounters", "Collision avoidance in encounters")
    top.paragraphs.append(
        "The claims rest on the scene families: seeded scenes of each kind, the same scenes "
        "for every controller (docs/families.md). The bundled scenarios are illustrated "
        "examples, every controller once each: DWA toward the goal, the route-guided DWA of "
        "IWSO-DWA (gdwa), CCDWA and UDWA; their plots are in the appendix. A run that did not "
        "arrive or collided is a failure in its own column, and its encounters are never "
        "counted compliant.")
    top.blocks += published.tables(results, "runs", exclude=(UDWA_WIND.id,))
    counted = [j for j in results.select("runs") if not own_section(j)]
    if any(j.number("not_judged") is None for j in counted):
        top.paragraphs.append(
            "The results table predates the split COLREGs counts (compliant, excused, "
            "non-compliant, not judged): they show as '-'. usvtool batch writes them again "
            "over the same runs (docs/batch.md).")
    for table in (families_table(results), thresholds_table(counted),
                  compliance_table(results), encounter_table(results, scenarios)):
        if table is not None:
            top.blocks.append(table)
    top.subsections = [scenario_section(results, s) for s in scenarios]
    return top
