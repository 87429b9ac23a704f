"""The methods section (usvtool/report/sections/methods.py) on a hand-made batch: commands a
stranger runs from the repository's root (relative paths, each job's own seed), and parameter
tables read from the jobs' files."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from usvtool.report.data import load
from usvtool.report.document import APPENDIX, HTML
from usvtool.report.sections import methods
from usvtool.results import Row, write_results

ROOT = Path(__file__).resolve().parents[2]


def job(batch: Path, kind: str, key: str, config: dict, **files) -> Path:
    d = batch / kind / key
    d.mkdir(parents=True)
    names = {"files": {n: {} for n in config.pop("outputs", ())}}
    (d / "job.json").write_text(json.dumps({"kind": kind, "key": key, **config, **names}))
    for name, content in files.items():
        (d / name.replace("_", ".")).write_text(content)
    return d


@pytest.fixture
def results(tmp_path):
    batch = tmp_path / "batch"
    job(batch, "grids", "g1", {"case": "env1", "method": "preprocess", "seed": None, "args": [
        "preprocess", str(ROOT / "charts" / "env1.geojson"), "--cell-size", "1", "-o",
        "grid.tif", "--preview", "preview.png"], "outputs": ["grid.tif", "preview.png"]})
    rows = []
    for key, seed in (("r13", 13), ("r7", 7)):
        job(batch, "routes", key, {"case": "env1", "method": "iwso", "seed": seed, "grid": "g1",
            "matrix": "env", "args": ["plan", "../../grids/g1/grid.tif", "--algo", "iwso",
            "--seed", str(seed), "-o", "route.geojson"], "outputs": ["route.geojson"]},
            summary_json=json.dumps({"parameters": {"pop": 50, "iters": 300, "waypoints": 3}}))
        rows.append(Row(key, "routes", "env1", "iwso", seed, "length_m", "700"))
    # the run as it started (the trace's first step): own at (0, 0) at 7 m/s, a target 300 m
    # north at 3.5 m/s; a scenario file that says otherwise is never read
    trace = ("t,ship,x,y,heading,speed,yaw_rate\n0.000,own,0.000,0.000,0.000,7.0000,0.0000\n"
             "0.000,target1,0.000,300.000,180.000,3.5000,0.0000\n"
             "0.100,own,0.000,0.700,0.000,7.0000,0.0000\n"
             "0.100,target1,0.000,299.650,180.000,3.5000,0.0000\n")
    scenario = "own: {start: [9, 9], goal: [9, 9], speed: 1, vessel: iwso-dwa-usv}\n"
    vessel = {"length": 15.0, "max_speed": 10.0, "max_yaw_rate": 12.0}
    for key, controller, priority in (("f1", "udwa", 0.5), ("f2", "ccdwa", 0.0)):
        events = {"run": {"scenario_file": "scenario.yaml", "own_length": 15.0,
                          "parameters": {"w_heading": 0.2, "priority": priority},
                          "ships": [{"name": "own", "length": 15.0},
                                    {"name": "target1", "length": 10.0}],
                          "map": None, "wind_field": None, "goal": [0.0, 450.0],
                          "vessel_preset": "udwa-usv", "vessel": vessel}}
        job(batch, "runs", key, {"case": "emergency/head-on/s004", "method": controller,
            "seed": 4, "scene": {"family": "emergency", "kind": "head-on", "scene": 4,
                                 "options": {}},
            "args": ["simulate", "--family", "emergency", "--kind", "head-on", "--scene", "4",
                     "--controller", controller, "--seed", "4", "-o", "trace.csv", "--events",
                     "trace.events.json"], "outputs": ["trace.csv", "trace.events.json"]},
            scenario_yaml=scenario, trace_events_json=json.dumps(events), trace_csv=trace)
        rows.append(Row(key, "runs", "emergency/head-on/s004", controller, 4, "arrived", "True"))
    write_results(batch / "metrics.csv", rows)
    return load([batch / "metrics.csv"], ("iwso", "udwa", "ccdwa"))


def texts(table) -> list[list[str]]:
    return [[c.text for c in row] for row in table.rows]


def test_the_examples_run_from_the_repository_with_relative_paths_and_their_own_seed(results):
    section = methods.section(results)
    rerun = texts(next(b for b in section.blocks if b.id == "methods-rerun"))
    assert [r[1] for r in rerun] == [
        "mkdir -p rerun",
        "usvtool preprocess charts/env1.geojson --cell-size 1 -o rerun/env1-grid.tif --preview "
        "rerun/env1-preview.png",
        "usvtool plan rerun/env1-grid.tif --algo iwso --seed 7 -o rerun/env1-iwso-s7-route.geojson",
        "usvtool simulate --family emergency --kind head-on --scene 4 --controller ccdwa --seed 4 "
        "-o rerun/emergency-head-on-s004-ccdwa-s4-trace.csv --events "
        "rerun/emergency-head-on-s004-ccdwa-s4-trace.events.json",
    ]  # fmt: skip
    assert rerun[2][0] == "plan a route on it (env1, iwso, seed 7)"


def test_every_job_is_listed_in_the_html_only_with_its_own_seed(results):
    table = next(b for b in methods.section(results).blocks if b.id == "methods-jobs")
    assert table.placement == HTML
    rows = texts(table)
    assert [(r[0], r[3]) for r in rows] == [("grids", "-"), ("routes", "7"), ("routes", "13"),
                                            ("runs", "4"), ("runs", "4")]  # fmt: skip
    for *_, seed, cmd in rows:
        assert not re.search(r"(^| )/|\.\./", cmd), cmd  # no absolute path, no ../
        if seed != "-":
            assert f"--seed {seed} " in cmd and f"-s{seed}-" in cmd


def test_the_parameter_tables_come_from_the_jobs_files(results):
    blocks = {b.id: b for b in methods.section(results).blocks}
    assert texts(blocks["methods-optimizers"]) == [["iwso", "routes: env",
                                                    "pop 50, iters 300, waypoints 3"]]
    controllers = blocks["methods-controllers"]
    assert controllers.columns == ["parameter", "udwa", "ccdwa"]  # the registry's order
    assert texts(controllers) == [["priority", "0.5", "0"], ["w_heading", "0.2", "0.2"]]
    vessel = texts(blocks["methods-vessels"])
    assert vessel == [["udwa-usv", "15", "length 15, max_speed 10, max_yaw_rate 12",
                       "1: emergency/head-on"]]  # fmt: skip
    family = texts(blocks["methods-families"])
    # one scene (4), seed 4; own run 450 m at 7 m/s; one target 300 m off at 3.5 m/s
    assert family == [["emergency/head-on", "4", "4", "udwa, ccdwa", "450", "7.0", "1", "300",
                       "3.5", "{}"]]  # fmt: skip
    assert {b.placement for b in blocks.values() if b.id != "methods-jobs"} == {"main", APPENDIX}


def test_events_without_the_vessel_preset_are_refused(results):
    from usvtool.errors import UsvError

    for j in results.select("runs"):
        path = j.dir / "trace.events.json"
        events = json.loads(path.read_text())
        del events["run"]["vessel_preset"]
        path.write_text(json.dumps(events))
    with pytest.raises(UsvError, match="run has no vessel_preset .*simulate the run again"):
        methods.section(results)


def test_paths_outside_the_repository_and_inside_it(tmp_path):
    assert methods.shown_path(ROOT / "charts" / "x.yaml") == "charts/x.yaml"
    assert methods.shown_path(tmp_path / "x.yaml") == str(tmp_path / "x.yaml")
