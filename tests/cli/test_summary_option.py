"""``--summary FILE`` (preprocess, plan, simulate, metrics): the file holds exactly the JSON
printed on stdout; a failing command (bad input, or a writer failing while the outputs are
staged) writes no summary and leaves an earlier one as it was, with no temporary left."""

from __future__ import annotations

import json

import pytest
import yaml

OLD = b"an earlier summary \x00\xff"
SCENARIO = {
    "name": "tiny-head-on",
    "sim": {"dt": 0.2, "duration": 10, "goal_tolerance": 5},
    "own": {"start": [0, 0], "goal": [0, 200], "heading": 0, "speed": 4},
    "targets": [{"name": "target", "start": [5, 200], "heading": 180, "speed": 3,
                 "length": 2.5}],
    "controller": {"name": "dwa"},
}  # fmt: skip


def boom(*args, **kwargs):
    raise OSError("disk full")


@pytest.fixture
def out(tmp_path):
    d = tmp_path / "out"
    d.mkdir()
    return d


def assert_written(r, summary) -> None:
    assert r.exit_code == 0, r.stderr
    assert summary.read_text(encoding="utf-8") == r.stdout
    assert json.loads(summary.read_text(encoding="utf-8")) == json.loads(r.stdout)


def assert_failed_untouched(r, out, summary) -> None:
    assert r.exit_code != 0
    assert summary.read_bytes() == OLD
    assert [p.name for p in out.iterdir()] == [summary.name]  # no output, no temporary


def test_preprocess(charts, out, usv, monkeypatch):
    args = ["--cell-size", 1, "--no-swell", "--occupancy", 0.5]
    summary = out / "grid.json"
    r = usv("preprocess", charts / "grid20.geojson", "-o", out / "grid.tif", "--preview",
            out / "grid.png", "--summary", summary, *args)  # fmt: skip
    assert_written(r, summary)
    assert sorted(p.name for p in out.iterdir()) == ["grid.json", "grid.png", "grid.tif"]
    for p in out.iterdir():
        p.unlink()
    summary.write_bytes(OLD)
    r = usv("preprocess", charts / "missing.geojson", "-o", out / "grid.tif", "--summary",
            summary, *args)  # fmt: skip
    assert_failed_untouched(r, out, summary)
    monkeypatch.setattr("usvtool.grid.write_grid", boom)  # fails inside the staging
    r = usv("preprocess", charts / "grid20.geojson", "-o", out / "grid.tif", "--summary",
            summary, *args)  # fmt: skip
    assert_failed_untouched(r, out, summary)


def test_plan(charts, out, usv, monkeypatch):
    def plan(*extra):
        return usv("plan", charts / "grid20.tif", "--start", 0.5, 0.5, "--algo", "astar",
                   "-o", out / "path.geojson", "--summary", out / "path.json", *extra)  # fmt: skip

    summary = out / "path.json"
    assert_written(plan("--goal", 19.5, 19.5), summary)
    (out / "path.geojson").unlink()
    summary.write_bytes(OLD)
    assert_failed_untouched(plan("--goal", 1e6, 1e6), out, summary)  # goal off the grid
    monkeypatch.setattr("usvtool.route.write_path_geojson", boom)
    assert_failed_untouched(plan("--goal", 19.5, 19.5), out, summary)


def test_simulate(tmp_path, out, usv, monkeypatch):
    scenario = tmp_path / "s.yaml"
    scenario.write_text(yaml.safe_dump(SCENARIO, sort_keys=False))

    def simulate(*extra):
        return usv("simulate", scenario, "-o", out / "trace.csv", "--events", out / "events.json",
                   "--summary", out / "summary.json", *extra)  # fmt: skip

    summary = out / "summary.json"
    assert_written(simulate(), summary)
    (out / "trace.csv").unlink()
    (out / "events.json").unlink()
    summary.write_bytes(OLD)
    assert_failed_untouched(simulate("--param", "no_such_parameter=1"), out, summary)
    monkeypatch.setattr("usvtool.trace.write_events", boom)
    assert_failed_untouched(simulate(), out, summary)


def test_metrics(charts, tmp_path, out, usv, monkeypatch):
    route = tmp_path / "astar.geojson"
    r = usv("plan", charts / "grid20.tif", "--start", 0.5, 0.5, "--goal", 19.5, 19.5, "--algo",
            "astar", "-o", route)  # fmt: skip
    assert r.exit_code == 0, r.stderr
    summary = out / "summary.json"
    assert_written(usv("metrics", route, "-o", out / "summary.csv", "--summary", summary), summary)
    (out / "summary.csv").unlink()
    summary.write_bytes(OLD)
    r = usv("metrics", tmp_path / "missing.geojson", "-o", out / "summary.csv", "--summary",
            summary)  # fmt: skip
    assert_failed_untouched(r, out, summary)
    monkeypatch.setattr("usvtool.cli.metrics.write_summary", boom)  # inside the staging
    assert_failed_untouched(
        usv("metrics", route, "-o", out / "summary.csv", "--summary", summary), out, summary
    )
    r = usv("metrics", route, "--summary", summary)  # the table goes to stdout: refused
    assert r.exit_code == 2 and "--summary" in r.stderr
