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
from usvtool.report.sections.encounters import lengths, run_file, run_files, scenario_section
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
