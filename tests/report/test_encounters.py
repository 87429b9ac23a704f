"""The report's encounter data (usvtool/report/sections/encounters.py): every ship's length, the map
and the wind field come from the events' ``run`` object as the simulator resolved them, never
from the scenario YAML."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from affine import Affine

from usvtool.errors import UsvError
from usvtool.grid import Grid, write_grid
from usvtool.report.data import JobResults, Results
from usvtool.report.runs import lengths, run_file, run_files
from usvtool.report.sections.encounters import scenario_section
from usvtool.trace import read_trace

#: Open water, 15 s: the own ship north, an unnamed 40 m target head-on (the simulator names
#: it target1), a named 5 m one far off.
SCENARIO = {
    "name": "s",
    "sim": {"dt": 0.1, "duration": 15, "goal_tolerance": 5},
    "map": "map.tif",
    "own": {"start": [100, 10], "goal": [100, 190], "heading": 0, "speed": 4},
    "targets": [{"start": [100, 170], "heading": 180, "speed": 3, "length": 40},
                {"name": "tug", "start": [180, 20], "heading": 0, "speed": 1, "length": 5}],
    "controller": {"name": "udwa"},
}  # fmt: skip


@pytest.fixture(scope="module")
def run(tmp_path_factory) -> JobResults:
    """The scenario simulated into a batch's run directory (``runs/<key>/``), the scenario's
    map a 200 m open grid beside it. The scenario file is then made unreadable: nothing may
    read it again."""
    from click.testing import CliRunner

    from usvtool.cli import cli

    tmp_path = tmp_path_factory.mktemp("run")
    write_grid(tmp_path / "map.tif", Grid(np.zeros((100, 100), np.uint8),
                                          Affine(2, 0, 0, 0, -2, 200)))  # fmt: skip
    (tmp_path / "s.yaml").write_text(yaml.safe_dump(SCENARIO, sort_keys=False))
    job = tmp_path / "batch" / "runs" / "k1"
    job.mkdir(parents=True)
    r = CliRunner().invoke(cli, ["simulate", str(tmp_path / "s.yaml"), "-o",
                                 str(job / "trace.csv"), "--events",
                                 str(job / "trace.events.json")])  # fmt: skip
    assert r.exit_code == 0, r.stderr
    (tmp_path / "s.yaml").write_text("not: [the scenario")
    config = {"scenario": str(tmp_path / "s.yaml")}
    return JobResults("k1", "runs", "s", "udwa", 1, job, config=config)


def test_an_unnamed_40_m_target_is_drawn_40_m_long(run):
    trace, events, where = run_files(run)
    own = events["run"]["own_length"]
    assert trace.ships == ("own", "target1", "tug")
    assert lengths(trace, events, where) == {"own": own, "target1": 40.0, "tug": 5.0}
    assert own != 40.0
    section = scenario_section(Results([run], []), "s")
    snapshots = next(f for f in section.figures() if f.id == "encounter-s-snapshots")
    lines = [line.split(",") for line in snapshots.data.splitlines()]
    header, rows = lines[0], lines[1:]
    drawn = {(r[header.index("ship")], r[header.index("domain_length_m")]) for r in rows}
    assert drawn == {("own", f"{7 * own:.3f}"), ("target1", "280.000"), ("tug", "35.000")}


def test_the_map_is_the_runs_and_a_map_gone_since_is_refused(run):
    _, events, where = run_files(run)
    scenario = Path(run.config["scenario"])
    assert run_file(events, "map", where) == scenario.with_name("map.tif").resolve()
    assert run_file(events, "wind_field", where) is None
    gone = {"run": {**events["run"], "map": str(scenario.with_name("moved.tif"))}}
    with pytest.raises(UsvError, match=f"^{where}: run.map {scenario.parent}/moved.tif: no such"):
        run_file(gone, "map", where)


@pytest.mark.parametrize("drop", [["ships"], ["ships", "map", "wind_field"], ["run"]])
def test_events_of_an_older_usvtool_are_refused_saying_to_rerun(run, drop):
    path = run.dir / "trace.events.json"
    events = json.loads(path.read_text())
    for key in drop:
        (events if key == "run" else events["run"]).pop(key)
    trace = read_trace(run.dir / "trace.csv")
    with pytest.raises(UsvError, match=f"^{path}: .*older usvtool.*simulate the run again"):
        lengths(trace, events, path)


def test_ships_that_are_not_the_traces_are_refused(run):
    trace, events, where = run_files(run)
    events = json.loads(Path(where).read_text())
    events["run"]["ships"] = events["run"]["ships"][:2]
    with pytest.raises(UsvError, match="run.ships name 2 ship"):
        lengths(trace, events, where)
    events["run"]["ships"] = [*events["run"]["ships"], {"name": "tug", "length": float("nan")}]
    with pytest.raises(UsvError, match="tug's length nan is not a number > 0"):
        lengths(trace, events, where)


# --- outcomes and COLREGs counts (issue 25 item 2) -------------------------------------------

#: Per run: (key, case, controller, arrived, collision, counts compliant / excused /
#: non-compliant / not judged, closest distance).
RUNS = [
    ("a0", "emergency/head-on/s000", "udwa", True, None, (2, 0, 0, 0), 40.0),
    ("a1", "emergency/head-on/s001", "udwa", True, None, (1, 1, 0, 0), 30.0),
    ("a2", "emergency/head-on/s002", "udwa", False, None, (0, 0, 0, 2), 20.0),
    ("a3", "emergency/head-on/s003", "udwa", False, "target", (0, 0, 0, 1), 0.5),
    ("b0", "emergency/head-on/s000", "ccdwa", True, None, (0, 0, 2, 0), 10.0),
    ("c0", "imazu/01/s000", "udwa", True, None, (1, 0, 0, 0), 50.0),  # the Imazu section's
    ("d0", "emergency-overtaking", "udwa", False, None, (0, 0, 0, 2), 35.0),
    ("d1", "emergency-overtaking", "udwa+", True, None, (1, 1, 0, 0), 45.0),
]  # fmt: skip


def results_of(tmp_path, runs=RUNS, split=True) -> Results:
    """A results table of ``runs`` (only the counts' columns without ``split``: a table
    written before them, where ``compliant`` still counted every passing encounter)."""
    from usvtool.report.data import load
    from usvtool.results import Row, write_results

    rows = []
    for key, case, c, arrived, collision, counts, closest in runs:
        values = {"arrived": str(arrived), "collision": collision, "closest_distance_m":
                  str(closest), "encounters": str(sum(counts)), "judged": str(sum(counts[:3]))}
        if split:
            values |= dict(zip(("compliant", "compliant_excused", "noncompliant",
                                "not_judged"), map(str, counts), strict=True))
        else:
            values["compliant"] = str(counts[0] + counts[1] + counts[3])
        values["failed_rules"] = "rule8-safe-distance" if counts[2] else None
        values["excused_rules"] = "rule14-starboard" if counts[1] else None
        rows += [Row(key, "runs", case, c, 1, m, v) for m, v in values.items() if v]
    table = tmp_path / "metrics.csv"
    write_results(table, rows)
    for key, case, *_ in runs:  # a family run's job.json names its family (the batch's)
        if "/" in case:
            (tmp_path / "runs" / key).mkdir(parents=True, exist_ok=True)
            scene = {"scene": {"family": case.split("/")[0]}}
            (tmp_path / "runs" / key / "job.json").write_text(json.dumps(scene), "utf-8")
    return load([table], ("dwa", "gdwa", "ccdwa", "udwa"))


def texts(table) -> list[list[str]]:
    return [[c.text for c in row] for row in table.rows]


def test_the_families_table_counts_failures_in_their_own_columns(tmp_path):
    from usvtool.report.sections.encounters import families_table

    table = families_table(results_of(tmp_path))
    assert table.columns[:4] == ["family/kind", "scenes", "controller", "arrived"]
    # scenes, arrived, collided, did not arrive, the four counts, closest median (IQR):
    # udwa's 40, 30, 20, 0.5: median 25, quartiles 15.125 and 32.5 (linear): IQR 17.375
    assert texts(table) == [
        ["emergency/head-on", "4", "ccdwa", "1", "0", "0", "0", "0", "2", "0",
         "10.0 (IQR 0.0)"],
        ["emergency/head-on", "4", "udwa", "2", "1", "1", "3", "1", "0", "3",
         "25.0 (IQR 17.4)"],
    ]  # fmt: skip
    fails = {table.columns[i] for i, c in enumerate(table.rows[1]) if "fails" in c.css}
    assert fails == {"collided", "did not arrive"}


def test_a_run_that_never_arrived_is_never_shown_compliant(tmp_path):
    from usvtool.report.sections.encounters import compliance_table

    table = compliance_table(results_of(tmp_path))
    rows = {r[1]: r for r in texts(table)}
    assert set(rows) == {"udwa", "udwa+"}  # the bundled scenario only
    heads = table.columns
    never = dict(zip(heads, rows["udwa"], strict=True))
    assert never["did not arrive"] == "1" and never["arrived"] == "0"
    assert never["compliant"] == "0" and never["not judged"] == "2"
    excused = dict(zip(heads, rows["udwa+"], strict=True))
    assert excused["compliant"] == excused["excused only"] == "1"
    assert excused["rules failed (excused)"] == "(excused: rule14-starboard)"


def test_a_table_before_the_split_shows_no_counts(tmp_path):
    from usvtool.report.sections.encounters import compliance_table, section

    results = results_of(tmp_path, split=False)
    row = dict(zip(compliance_table(results).columns, texts(compliance_table(results))[0],
                   strict=True))  # fmt: skip
    assert row["compliant"] == row["not judged"] == "-" and row["did not arrive"] == "1"
    assert any("predates" in p for p in section(results).paragraphs)


def test_family_runs_get_no_subsection_and_the_examples_go_to_the_appendix(tmp_path):
    from usvtool.report.document import APPENDIX
    from usvtool.report.sections.encounters import section

    top = section(results_of(tmp_path))
    assert [s.id for s in top.subsections] == ["encounter-emergency-overtaking"]
    assert {s.placement for s in top.subsections} == {APPENDIX}
    assert [b.id for b in top.blocks if b.id.startswith(("encounter-", "colregs-"))] == [
        "encounter-families", "colregs-compliance"]  # no events files: no thresholds


def write_events(path: Path, own_length: float, apparent: float, encounters=(), **run):
    path.mkdir(parents=True, exist_ok=True)
    facts = {"ships": [{"name": "own", "length": own_length},
                       {"name": "tanker", "length": 50.0}], "map": None, "wind_field": None,
             "own_length": own_length, "arrived": True, "collision": None, **run}
    thresholds = {"risk_distance_m": 3.5 * own_length, "horizon_s": 120.0,
                  "domain_axes_m": [7 * own_length, 3 * own_length],
                  "apparent": {"course_deg": apparent, "speed_reduction": 0.5},
                  "release_distance_m": None, "new_threshold_m": 4.0}
    (path / "trace.events.json").write_text(json.dumps(
        {"run": facts, "thresholds": thresholds, "encounters": list(encounters)}))


def test_the_thresholds_are_the_events_files(tmp_path):
    from usvtool.report.sections.encounters import thresholds_table

    results = results_of(tmp_path)
    write_events(tmp_path / "runs" / "d0", 15.0, 30.0)
    write_events(tmp_path / "runs" / "d1", 30.0, 25.0)  # not written in the report: read
    values = {r[2]: r[1] for r in texts(thresholds_table(results.select("runs")))}
    assert values == {"risk_distance_m": "3.5 L (52.5-105 m)", "horizon_s": "120 s",
                      "domain_axes_m": "7 L x 3 L (105-210 m x 45-90 m)",
                      "apparent": "course 25 deg / speed reduction 0.5; course 30 deg / "
                                  "speed reduction 0.5",
                      "release_distance_m": "none", "new_threshold_m": "4"}  # fmt: skip


def encounter(compliant, failed=(), excused=(), records=0, cls="head-on") -> dict:
    return {"target": 0, "class": cls, "onset_s": 10.0, "cpa_time_s": 42.5,
            "closest_distance_m": 31.25, "compliant": compliant, "failed_rules": list(failed),
            "excused_rules": list(excused),
            "rule2_departure": [{"t": 20.0, "target": 0}] * records or None}  # fmt: skip


def test_every_encounter_with_its_verdict_as_the_metrics_count_it(tmp_path):
    from usvtool.metrics.tabulate import verdict
    from usvtool.report.sections.encounters import (
        VERDICT_WORDS,
        encounter_table,
        encounter_verdict,
    )

    results = results_of(tmp_path)
    write_events(tmp_path / "runs" / "d0", 15.0, 30.0, [encounter(True)], arrived=False)
    write_events(tmp_path / "runs" / "d1", 15.0, 30.0, [
        encounter(True, excused=["rule14-starboard"], records=3),
        encounter(False, failed=["rule8-safe-distance"]), encounter(None, cls="none")])
    table = encounter_table(results, ["emergency-overtaking"])
    assert texts(table) == [
        ["emergency-overtaking", "udwa", "1", "tanker", "head-on", "10.0", "32.5", "31.2",
         "not judged: did not arrive", "", "", "0"],
        ["emergency-overtaking", "udwa+", "1", "tanker", "head-on", "10.0", "32.5", "31.2",
         "compliant only by an excused Rule 2 departure", "", "rule14-starboard", "3"],
        ["emergency-overtaking", "udwa+", "1", "tanker", "head-on", "10.0", "32.5", "31.2",
         "non-compliant", "rule8-safe-distance", "", "0"],
    ]  # fmt: skip
    # the report's words and the metrics' counts agree on every case
    for e in (encounter(True), encounter(True, excused=["x"]), encounter(False),
              encounter(None)):
        for run in ({"arrived": True}, {"arrived": False}, {"arrived": True, "collision": "map"}):
            mine = encounter_verdict(e, run)
            theirs = verdict(e, bool(run["arrived"]) and not run.get("collision"))
            assert mine == VERDICT_WORDS[theirs] or (theirs == "not_judged"
                                             and mine.startswith("not judged"))  # fmt: skip
