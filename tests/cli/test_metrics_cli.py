"""``usvtool metrics`` through click's CliRunner: routes planned on a bundled grid, a real short
simulation, the outputs' formats and bytes, and bad inputs failing in one line."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import pytest
import yaml

SCENARIO = {
    "name": "tiny-head-on",
    "sim": {"dt": 0.1, "duration": 60, "goal_tolerance": 5},
    "own": {"start": [0, 0], "goal": [0, 200], "heading": 0, "speed": 4},
    "targets": [{"name": "target", "start": [5, 200], "heading": 180, "speed": 3,
                 "length": 2.5}],
    "controller": {"name": "dwa"},
}  # fmt: skip


def table(text: str) -> list[dict]:
    return list(csv.DictReader(io.StringIO(text)))


@pytest.fixture(scope="module")
def routes(tmp_path_factory, charts):
    from click.testing import CliRunner

    from usvtool.cli import cli

    d = tmp_path_factory.mktemp("paths") / "grid20"
    d.mkdir()
    for algo in ("astar", "anyangle"):
        result = CliRunner().invoke(cli, ["plan", str(charts / "grid20.tif"), "--start", "0.5",
                                          "0.5", "--goal", "19.5", "19.5", "--algo", algo,
                                          "-o", str(d / f"{algo}.geojson")])  # fmt: skip
        assert result.exit_code == 0, result.output
    return d


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    from click.testing import CliRunner

    from usvtool.cli import cli

    d = tmp_path_factory.mktemp("run")
    (d / "s.yaml").write_text(yaml.safe_dump(SCENARIO, sort_keys=False))
    summaries = {}
    for controller in ("dwa", "udwa"):
        result = CliRunner().invoke(
            cli, ["simulate", str(d / "s.yaml"), "--controller", controller,
                  "-o", str(d / f"{controller}.csv"), "--events", str(d / f"{controller}.json")]
        )  # fmt: skip
        assert result.exit_code == 0, result.output
        summaries[controller] = json.loads(result.stdout)
    return d, summaries


def test_routes_give_the_plan_figures(usv, routes):
    result = usv("metrics", routes / "astar.geojson", routes / "anyangle.geojson")
    assert result.exit_code == 0, result.stderr
    rows = table(result.stdout)
    assert [r["algorithm"] for r in rows] == ["anyangle", "astar"]  # sorted by path
    props = json.loads((routes / "astar.geojson").read_text())["features"][0]["properties"]
    astar = rows[1]
    assert astar["chart"] == "grid20"
    assert float(astar["length_m"]) == round(props["length_m"], 2)
    assert int(astar["turns"]) == props["turns"]
    assert float(astar["mot"]) == round(props["mot"], 4)
    assert float(astar["length_ratio"]) >= 1.0 and rows[0]["length_ratio"] == "1.0"


def test_an_explicit_reference_and_json_output(usv, routes, tmp_path):
    out = tmp_path / "m.json"
    result = usv("metrics", routes / "astar.geojson", "--reference",
                 routes / "anyangle.geojson", "-o", out)  # fmt: skip
    assert result.exit_code == 0, result.stderr
    summary = json.loads(result.stdout)
    assert summary["rows"] == 1 and summary["format"] == "json"
    data = json.loads(out.read_text())
    assert data["rows"][0]["length_ratio"] >= 1.0
    alone = table(usv("metrics", routes / "astar.geojson").stdout)
    assert alone[0]["length_ratio"] == ""  # no reference


def test_a_real_run_matches_the_simulate_summary(usv, run):
    d, summaries = run
    out = d / "m.csv"
    result = usv("metrics", d / "udwa.csv", d / "dwa.csv", "--reference-controller", "dwa",
                 "-o", out)  # fmt: skip
    assert result.exit_code == 0, result.stderr
    rows = {r["controller"]: r for r in table(out.read_text())}
    for name, s in summaries.items():
        r = rows[name]
        assert float(r["closest_distance_m"]) == pytest.approx(s["closest_distance_m"], abs=1.5e-3)
        assert float(r["average_distance_m"]) == pytest.approx(s["average_distance_m"], abs=1.5e-3)
        assert float(r["length_m"]) == pytest.approx(s["path_length_m"], abs=0.01)
        assert int(r["turns"]) == s["turns"]
        assert float(r["mot"]) == pytest.approx(s["mot"], abs=1e-3)
        assert r["arrived"] == str(s["arrived"])
        assert float(r["domain_intrusion_s"]) == s["domain_intrusion_s"]
        if s["arrived"]:
            assert float(r["arrival_time_s"]) == s["time_s"]
    assert rows["dwa"]["average_distance_rate"] == "0.0"
    expected = (summaries["udwa"]["average_distance_m"] - summaries["dwa"]["average_distance_m"]) \
        / summaries["dwa"]["average_distance_m"]  # fmt: skip
    assert float(rows["udwa"]["average_distance_rate"]) == pytest.approx(expected, abs=1e-3)
    # the same inputs in another order: the same bytes
    again = d / "again.csv"
    usv("metrics", d / "dwa.csv", d / "udwa.csv", "--reference-controller", "dwa", "-o", again)
    assert again.read_bytes() == out.read_bytes()


def test_events_given_explicitly(usv, run, tmp_path):
    d, _ = run
    trace = tmp_path / "trace.csv"
    trace.write_bytes((d / "dwa.csv").read_bytes())
    assert usv("metrics", trace).exit_code == 1
    result = usv("metrics", trace, "--events", d / "dwa.json")
    assert result.exit_code == 0, result.stderr
    assert table(result.stdout)[0]["controller"] == "dwa"


def errors(result) -> str:
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    return lines[0]


def test_bad_inputs_fail_in_one_line(usv, run, tmp_path):
    d, _ = run
    missing = tmp_path / "nope.geojson"
    result = usv("metrics", missing)
    assert result.exit_code == 1 and str(missing) in errors(result)
    not_trace = tmp_path / "table.csv"
    not_trace.write_text("a,b\n1,2\n")
    (tmp_path / "table.json").write_text("{}")
    result = usv("metrics", not_trace)
    assert result.exit_code == 1 and str(not_trace) in errors(result)
    lone = tmp_path / "lone.csv"
    lone.write_bytes((d / "dwa.csv").read_bytes())
    result = usv("metrics", lone)
    assert result.exit_code == 1 and str(lone) in errors(result) and "events" in errors(result)
    old = tmp_path / "old.csv"
    old.write_bytes((d / "dwa.csv").read_bytes())
    events = json.loads((d / "dwa.json").read_text())
    del events["run"]
    (tmp_path / "old.json").write_text(json.dumps(events))
    result = usv("metrics", old)
    assert result.exit_code == 1 and "old.json" in errors(result)
    other = tmp_path / "x.txt"
    other.write_text("x")
    result = usv("metrics", other)
    assert result.exit_code == 1 and str(other) in errors(result)
    out = tmp_path / "missing-dir" / "m.csv"
    result = usv("metrics", d / "dwa.csv", "-o", out)
    assert result.exit_code == 1 and not out.exists()


def test_usage_errors_exit_2(usv):
    assert usv("metrics").exit_code == 2
    assert usv("metrics", "a.csv", "--bogus").exit_code == 2


def test_listed_in_the_help(usv):
    assert "metrics" in usv("--help").stdout


def test_the_events_json_describes_its_run(run):
    d, summaries = run
    events = json.loads(Path(d / "dwa.json").read_text())
    r = events["run"]
    s = summaries["dwa"]
    for key in ("scenario", "controller", "parameters", "seed", "arrived", "collision",
                "time_s", "domain_intrusion_s"):  # fmt: skip
        assert r[key] == s[key]
    assert r["goal"] == [0.0, 200.0] and r["goal_tolerance"] == 5.0 and r["dt"] == 0.1
    assert r["own_length"] > 0
    assert {"encounters", "steps", "thresholds", "scenario", "controller"} <= set(events)
