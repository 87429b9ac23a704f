"""usvtool.pipeline: the bundled pipeline reads, its route matrix expands, bad files give one
line naming the file and the field, and the Make fragment names every route target."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from usvtool.errors import UsvError
from usvtool.pipeline import BUNDLED, load, make_fragment
from usvtool.plan.optimizers import OPTIMIZERS

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def bundled():
    return load(BUNDLED)


def test_the_bundled_pipeline_reads(bundled):
    assert BUNDLED == ROOT / "pipelines" / "report.yaml"
    assert bundled.root == ROOT
    assert all((ROOT / c.source).is_file() for c in bundled.charts.values())
    assert set(bundled.routes.ends) <= set(bundled.charts)
    assert bundled.routes.seed >= 0 and bundled.routes.attempts >= 1
    # every algorithm is one the planner knows (the reader itself imports no stage)
    known = {*OPTIMIZERS, "anyangle", "astar"}
    assert all(a.removesuffix("+s") in known for a in bundled.routes.algorithms)
    assert dict(bundled.charts["env1"].options) == {"cell-size": 1, "margin": 3}
    assert bundled.charts["grid20"].args() == [
        "--cell-size",
        "1",
        "--no-swell",
        "--occupancy",
        "0.5",
    ]


def test_the_route_matrix_expands_into_charts_x_algorithms(bundled):
    jobs = bundled.route_jobs()
    routes = bundled.routes
    assert len(jobs) == len(routes.ends) * len(routes.algorithms)
    assert len({(j.chart, j.algorithm) for j in jobs}) == len(jobs)
    job = next(j for j in jobs if j.chart == "us5ma12m" and j.algorithm == "iwso")
    assert job.frame == "lonlat" and job.start == routes.ends["us5ma12m"].start
    assert job.args()[0] == "--start-lonlat" and job.args()[3] == "--goal-lonlat"
    assert job.args()[6:] == ["--algo", "iwso", "--seed", str(routes.seed), "--attempts",
                              str(routes.attempts)]  # fmt: skip


def test_the_simulation_matrix_is_scenarios_x_controllers(bundled):
    sim = bundled.simulation
    assert set(sim.controllers) == {"dwa", "gdwa", "ccdwa", "udwa"}
    expected = sorted(
        p.relative_to(ROOT).as_posix() for p in (ROOT / "charts/scenarios").glob("*.yaml")
    )
    assert list(sim.scenarios) == expected
    assert len(bundled.simulation_jobs()) == len(expected) * 4


def test_the_make_fragment_names_every_route_target(bundled):
    text = make_fragment(bundled)
    for job in bundled.route_jobs():
        assert f"build/paths/{job.chart}/{job.algorithm}.geojson" in text
    for name, chart in bundled.charts.items():
        assert f"CHART_SOURCE_{name} := {chart.source}\n" in text
    assert "ENDS_grid20 := --start 0.5 0.5 --goal 19.5 19.5\n" in text
    assert f"GRIDS := {' '.join(bundled.charts)}\n" in text


def test_the_module_writes_the_fragment(tmp_path, bundled):
    out = tmp_path / "pipeline.mk"
    subprocess.run([sys.executable, "-m", "usvtool.pipeline", "make", str(BUNDLED), "-o", str(out)],
                   check=True)  # fmt: skip
    assert out.read_text() == make_fragment(bundled)


def write(tmp_path: Path, data: dict) -> Path:
    """A pipeline in tmp_path with one chart file, from the bundled one edited by the test."""
    (tmp_path / "map.geojson").write_text("{}")
    path = tmp_path / "p.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def minimal() -> dict:
    return {
        "charts": {"m": {"source": "map.geojson", "options": {"cell-size": 1}}},
        "routes": {
            "algorithms": ["iwso"],
            "seed": 1,
            "ends": {"m": {"start": [1, 1], "goal": [5, 5]}},
        },
    }


def test_a_minimal_pipeline_reads(tmp_path):
    p = load(write(tmp_path, minimal()))
    assert [(j.chart, j.algorithm) for j in p.route_jobs()] == [("m", "iwso")]
    assert p.simulation is None and p.routes.attempts == 1


def edit(data: dict, dotted: str, value) -> dict:
    *parents, last = dotted.split(".")
    node = data
    for key in parents:
        node = node[key]
    if value is KeyError:
        del node[last]
    else:
        node[last] = value
    return data


@pytest.mark.parametrize(
    "dotted, value, field, words",
    [
        ("charts.m.source", KeyError, "charts.m.source", "missing"),
        ("routes.seed", KeyError, "routes.seed", "missing"),
        ("charts.m.source", "nowhere.geojson", "charts.m.source", "nowhere.geojson: no such file"),
        ("routes.ends.m.start", [1], "routes.ends.m.start", "two numbers"),
        ("routes.ends.m.start", ["a", 2], "routes.ends.m.start", "two numbers"),
        ("routes.ends.m.frame", "lonlat", "routes.ends.m.start", "lon, lat"),  # start [1, 1] ok
        ("routes.ends.x", {"start": [1, 1], "goal": [2, 2]}, "routes.ends.x", "unknown chart"),
        ("routes.seed", -1, "routes.seed", "integer >= 0"),
        ("routes.attempts", 0, "routes.attempts", "integer >= 1"),
        ("routes.algorithms", ["iwso", "iwso"], "routes.algorithms", "named twice"),
        ("routes.options", {"seed": 2}, "routes.options.seed", "set by the matrix"),
        ("routes.colour", "red", "routes.colour", "unknown field"),
        ("charts.m.options", {"cell-size": [1]}, "charts.m.options.cell-size", "expected a number"),
    ],
)
def test_errors_name_the_file_and_the_field(tmp_path, dotted, value, field, words):
    data = minimal()
    if dotted == "routes.ends.m.frame":
        data["routes"]["ends"]["m"]["start"] = [200, 1]
    path = write(tmp_path, edit(data, dotted, value))
    with pytest.raises(UsvError) as info:
        load(path)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"{path}: {field}: ")
    assert words in message


def test_a_scenario_glob_matching_nothing_is_refused(tmp_path):
    data = minimal()
    data["simulation"] = {"scenarios": ["none/*.yaml"], "controllers": ["dwa"]}
    with pytest.raises(
        UsvError, match=r"p\.yaml: simulation\.scenarios\[0\]: none/\*\.yaml: matches no file$"
    ):
        load(write(tmp_path, data))


def test_bad_yaml_and_a_missing_file_are_one_line(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("charts: [\n")
    with pytest.raises(UsvError) as info:
        load(path)
    assert str(info.value).startswith(f"{path}: not valid YAML") and "\n" not in str(info.value)
    with pytest.raises(UsvError, match="no such file"):
        load(tmp_path / "absent.yaml")


def test_the_module_exits_1_with_one_line(tmp_path):
    path = write(tmp_path, edit(minimal(), "routes.seed", "one"))
    run = subprocess.run([sys.executable, "-m", "usvtool.pipeline", "make", str(path)],
                         capture_output=True, text=True)  # fmt: skip
    assert run.returncode == 1 and run.stdout == ""
    assert (
        run.stderr
        == f"usvtool.pipeline: {path}: routes.seed: expected an integer >= 0, got 'one'\n"
    )
