"""``usvtool simulate`` through click's CliRunner (and a subprocess for the signals): outputs,
summary, seeds, and every bad input failing in one line with nothing written."""

from __future__ import annotations

import copy
import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from affine import Affine

from usvtool.grid import Grid, write_grid
from usvtool.trace import read_events, read_trace

OLD = b"an earlier trace \x00\xff"

# Open water, 40 s: own north up x = 100; a noisy target head-on, one crossing on waypoints
# from starboard, one replaying a track far off to port.
BASE = {
    "name": "head-on-open",
    "sim": {"dt": 0.1, "duration": 40, "goal_tolerance": 5},
    "own": {"start": [100, 10], "goal": [100, 190], "heading": 0, "speed": 4},
    "targets": [
        {"name": "t1", "start": [100, 170], "heading": 180, "speed": 3, "length": 2.5,
         "noise": {"heading_sd": 0.5, "speed_sd": 0.05}},
        {"name": "t2", "start": [190, 120], "waypoints": [[150, 120], [60, 130]], "speed": 2,
         "length": 3},
        {"name": "t3", "track": "track.csv", "speed": 0, "length": 2},
    ],
    "controller": {"name": "udwa"},
}  # fmt: skip
TRACK = "t,x,y\n0,10,150\n20,10,110\n60,15,40\n"


def write_scenario(directory: Path, data: dict, name: str = "s.yaml") -> Path:
    path = directory / name
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


@pytest.fixture
def case(tmp_path):
    """A scenario directory (the base scenario, its track, a 200 m grid with an island at x
    20..50, y 80..120, a route, a raster that is not one) and an output directory holding an
    earlier trace."""
    (tmp_path / "track.csv").write_text(TRACK)
    cells = np.zeros((100, 100), np.uint8)
    cells[40:60, 10:25] = 1  # rows from the top: y 120..80; columns: x 20..50
    write_grid(tmp_path / "map.tif", Grid(cells, Affine(2, 0, 0, 0, -2, 200)))
    route = {
        "type": "Feature",
        "properties": {},
        "geometry": {"type": "LineString", "coordinates": [[100, 10], [100, 190]]},
    }
    (tmp_path / "route.geojson").write_text(json.dumps(route))
    (tmp_path / "far-route.geojson").write_text(json.dumps(
        {**route, "geometry": {"type": "LineString", "coordinates": [[160, 10], [100, 190]]}}
    ))  # fmt: skip
    (tmp_path / "wind.tif").write_text("not a raster\n")
    (tmp_path / "bad-track.csv").write_text("t,x,y\n0,10,150\n20,ten,110\n")
    (tmp_path / "long-line.csv").write_text("t,x,y\n0,10,150\n\"" + "9" * 200_000)  # one field
    out = tmp_path / "out"
    out.mkdir()
    (out / "trace.csv").write_bytes(OLD)
    return tmp_path, out


def simulate(usv, scenario, out, *args):
    return usv("simulate", scenario, "-o", out / "trace.csv", "--events", out / "events.json",
               "--tracks", out / "tracks.geojson", *args)  # fmt: skip


def test_a_run_writes_trace_events_and_tracks_and_prints_the_summary(case, usv):
    directory, out = case
    r = simulate(usv, write_scenario(directory, BASE), out, "--seed", 7)
    assert r.exit_code == 0, r.stderr
    assert sorted(p.name for p in out.iterdir()) == ["events.json", "trace.csv", "tracks.geojson"]
    summary = json.loads(r.stdout)
    assert summary["output"] == str(out / "trace.csv")
    assert summary["events"] == str(out / "events.json")
    assert summary["scenario"] == "head-on-open" and summary["controller"] == "udwa"
    assert summary["seed"] == 7 and summary["collision"] is None
    trace = read_trace(out / "trace.csv")
    assert trace.ships == ("own", "t1", "t2", "t3")
    assert trace.t[0] == 0 and trace.t[-1] == pytest.approx(summary["time_s"])
    assert np.allclose(np.diff(trace.t), 0.1)
    assert trace.x[0, 0] == 100 and trace.y[0, 0] == 10
    # the independent check: the smallest centre distance, from the trace
    d = np.hypot(trace.x[:, 1:] - trace.x[:, :1], trace.y[:, 1:] - trace.y[:, :1])
    assert summary["closest_distance_m"] == pytest.approx(d.min(), abs=2e-3)
    assert summary["closest_distance_m"] > (2.5 + 2.5) / 2
    events = read_events(out / "events.json")
    assert events["scenario"] == "head-on-open" and events["controller"] == "udwa"
    assert {"steps", "encounters", "thresholds", "unmatched_rule2"} <= set(events)
    head_on = [e for e in events["encounters"] if e["target"] == 0]
    assert head_on and head_on[0]["class"] == "head-on"
    tracks = json.loads((out / "tracks.geojson").read_text())
    assert tracks["frame"] == "local"
    assert [f["properties"]["ship"] for f in tracks["features"]] == list(trace.ships)
    own = np.array(tracks["features"][0]["geometry"]["coordinates"])
    assert np.allclose(own, np.column_stack([trace.x[:, 0], trace.y[:, 0]]), atol=1e-3)
    # t3 replays its track: at t 20 at (10, 110)
    i = int(np.argmin(np.abs(trace.t - 20)))
    assert (trace.x[i, 3], trace.y[i, 3]) == pytest.approx((10, 110), abs=1e-3)


def test_the_seed_decides_the_noise(case, usv):
    directory, out = case
    scenario = write_scenario(directory, BASE)
    texts = []
    for seed in (3, 3, 4):
        r = usv("simulate", scenario, "--seed", seed, "-o", out / "trace.csv")
        assert r.exit_code == 0, r.stderr
        texts.append((out / "trace.csv").read_bytes())
    assert texts[0] == texts[1]
    assert texts[0] != texts[2]


def test_controller_and_params_override_the_scenario(case, usv):
    directory, out = case
    data = {**copy.deepcopy(BASE), "map": "map.tif", "route": "route.geojson",
            "controller": {"name": "udwa", "priority": 0.8}}  # fmt: skip
    data["sim"]["duration"] = 5
    scenario = write_scenario(directory, data)
    r = usv("simulate", scenario, "-o", out / "trace.csv", "--param", "w_heading=0.1",
            "--param", "sides=colregs")  # fmt: skip
    assert r.exit_code == 0, r.stderr
    params = json.loads(r.stdout)["parameters"]
    assert params["priority"] == 0.8 and params["w_heading"] == 0.1
    assert params["sides"] == "colregs"
    r = usv("-v", "simulate", scenario, "-o", out / "trace.csv", "--controller", "gdwa",
            "--param", "reach=null", "--param", "w_path=1e-1")  # fmt: skip
    assert r.exit_code == 0, r.stderr
    summary = json.loads(r.stdout)
    assert summary["controller"] == "gdwa" and "events" not in summary
    assert summary["parameters"]["priority"] == 0.5  # gdwa's own, not the scenario's udwa one
    assert summary["parameters"]["reach"] is None and summary["parameters"]["w_path"] == 0.1
    assert "are not used" in r.stderr
    assert sorted(p.name for p in out.iterdir()) == ["trace.csv"]


def edit(path: str, value):
    """A change to the base scenario: set the field at ``path`` (dots; ``-`` deletes it)."""

    def apply(data):
        *parents, last = path.split(".")
        node = data
        for key in parents:
            node = node[int(key)] if isinstance(node, list) else node[key]
        if value == "-":
            del node[last]
        elif isinstance(node, list):
            node[int(last)] = value
        else:
            node[last] = value

    return apply


ON_MAP = edit("map", "map.tif")
BAD = [  # (id, changes to the scenario, extra arguments, exit status, words of the message)
    # a message on a file the scenario names (a raster, a track) names both, and the field
    ("missing-field", [edit("own.goal", "-")], [], 1, "s.yaml: own.goal is missing"),
    ("mistyped-field", [edit("own.speed", "fast")], [], 1,
     "s.yaml: own.speed must be a number, not 'fast'"),
    ("unknown-field", [edit("own.sped", 3)], [], 1, "s.yaml: own.sped is not a field"),
    ("bad-point", [edit("own.start", [1, 2, 3])], [], 1, "s.yaml: own.start must be [x, y]"),
    ("unknown-controller", [edit("controller.name", "apf")], [], 1,
     "s.yaml: controller.name must be one of dwa, gdwa, ccdwa, udwa, udwa+, vo, sbmpc, exec, "
     "policy, not 'apf'"),
    ("unknown-scenario-param", [edit("controller.gain", 2)], [], 1,
     "s.yaml: controller.gain is not a parameter of udwa"),
    ("bad-scenario-param", [edit("controller.horizon", 0)], [], 1,
     "s.yaml: controller.horizon must be > 0 for udwa, not 0"),
    ("unknown-preset", [edit("own.vessel", "tanker")], [], 1,
     "s.yaml: own.vessel must be a vessel preset (iwso-dwa-usv, udwa-usv), not 'tanker'"),
    ("start-on-land", [ON_MAP, edit("own.start", [30, 100])], [], 1,
     "s.yaml: own.start (30, 100) is on an obstacle"),
    ("goal-outside", [ON_MAP, edit("own.goal", [100, 250])], [], 1,
     "s.yaml: own.goal (100, 250) is outside the grid"),
    ("far-route", [edit("route", "far-route.geojson")], [], 1,
     "s.yaml: route far-route.geojson starts 60.0 m from own.start"),
    ("zero-limit", [edit("own.max_speed", 0)], [], 1, "s.yaml: own.max_speed must be > 0, not 0"),
    ("negative-length", [edit("own.length", -2.5)], [], 1, "s.yaml: own.length must be > 0"),
    ("slow-max-speed", [edit("own.max_speed", 0.5)], [], 1,
     "s.yaml: own: min_speed (1.0) must not exceed max_speed (0.5)"),
    ("lonlat-without-crs", [edit("own.goal", {"lon": 10, "lat": 50})], [], 1,
     "s.yaml: own.goal: lon/lat needs a map with a CRS"),
    ("negative-limit", [edit("sim.dt", -0.1)], [], 1, "s.yaml: sim.dt must be > 0, not -0.1"),
    ("nan-limit", [edit("own.max_accel", float("nan"))], [], 1,
     "s.yaml: own.max_accel must be finite, not nan"),
    ("nan-duration", [edit("sim.duration", float("nan"))], [], 1,
     "s.yaml: sim.duration must be finite"),
    ("tiny-dt", [edit("sim.dt", 1e-4)], [], 1, "s.yaml: sim.dt must be at least 0.001 s"),
    ("unreadable-weather", [edit("weather", {"field": "wind.tif"})], [], 1,
     ("s.yaml: weather.field: ", "wind.tif: not a readable raster")),
    ("windless-weather", [edit("weather", {"field": "map.tif"})], [], 1,
     ("s.yaml: weather.field: ", "map.tif: no wind bands")),
    ("missing-map", [edit("map", "nowhere.tif")], [], 1,
     "s.yaml: map names 'nowhere.tif', which is not a file"),
    ("bad-track-row", [edit("targets.2.track", "bad-track.csv")], [], 1,
     ("s.yaml: targets[2].track: ", "bad-track.csv: line 3: three numbers expected")),
    ("track-line-too-long", [edit("targets.2.track", "long-line.csv")], [], 1,
     ("s.yaml: targets[2].track: ", "long-line.csv: line 3: not a track's CSV (field larger")),
    ("duplicate-name", [edit("targets.1.name", "own")], [], 1,
     "s.yaml: targets[1].name 'own' is taken"),
    ("cli-unknown-controller", [], ["--controller", "apf"], 2, "'apf' is not one of"),
    ("cli-unknown-param", [], ["--param", "gain=2"], 1, "--param gain is not a parameter of udwa"),
    ("cli-mistyped-param", [], ["--param", "horizon=far"], 1,
     "--param horizon must be a finite number, not 'far'"),
    ("cli-bad-param", [], ["--param", "horizon=-1"], 1,
     "--param horizon must be > 0 for udwa, not -1"),
    ("cli-not-a-pair", [], ["--param", "horizon"], 2, "'horizon' is not NAME=VALUE"),
    ("cli-negative-samples", [], ["--param", "v_samples=1"], 1,
     "--param v_samples must be >= 2 for udwa, not 1"),
    ("cli-fractional-samples", [], ["--param", "v_samples=20.5"], 1,
     "--param v_samples must be an integer, not 20.5"),
    ("cli-label-of-a-controller", [], ["--label", "dwa"], 2,
     "'dwa' is a controller's name: a variant needs a name of its own"),
    ("cli-label-not-a-name", [], ["--label", "udwa calm"], 2, "'udwa calm' is not a name"),
    ("cli-label-of-a-program", [], ["--controller", "exec:python3", "--label", "c"], 2,
     "an exec controller is named by --param label=NAME"),
]  # fmt: skip


@pytest.mark.parametrize("changes, args, code, words", [b[1:] for b in BAD],
                         ids=[b[0] for b in BAD])  # fmt: skip
def test_bad_input_fails_in_one_line_and_writes_nothing(case, usv, changes, args, code, words):
    directory, out = case
    data = copy.deepcopy(BASE)
    for change in changes:
        change(data)
    r = simulate(usv, write_scenario(directory, data), out, *args)
    assert_failed(r, code, *((words,) if isinstance(words, str) else words))
    assert_untouched(out)


def test_malformed_yaml_and_missing_scenario(case, usv):
    directory, out = case
    bad = directory / "bad.yaml"
    bad.write_text("name: x\nown: {start: [0, 0], goal: [0, 1]\n")
    assert_failed(simulate(usv, bad, out), 1, "bad.yaml: not valid YAML (line 3: ")
    bad.write_text("- a list\n")
    assert_failed(simulate(usv, bad, out), 1, "bad.yaml: must be a mapping, not a list")
    assert_failed(simulate(usv, directory / "none.yaml", out), 1, "none.yaml: no such file")
    assert_untouched(out)


def test_outputs_refused_before_the_run(case, usv):
    directory, out = case
    scenario = write_scenario(directory, BASE)
    r = usv("simulate", scenario, "-o", out / "trace.csv", "--events", out / "trace.csv")
    assert_failed(r, 1, "--events", "same file as -o")
    r = usv("simulate", scenario, "-o", out / "no" / "trace.csv")
    assert_failed(r, 1, "does not exist")
    text = scenario.read_text()
    r = usv("simulate", scenario, "-o", out / "trace.csv", "--tracks", scenario)
    assert_failed(r, 1, "--tracks", "the same file as the input SCENARIO.yaml")
    assert scenario.read_text() == text
    assert_untouched(out)


def test_sigterm_while_the_outputs_are_staged(case, usv, monkeypatch):
    import usvtool.trace

    directory, out = case

    def write_then_signal(path, events):
        Path(path).write_text('{"half": ')
        os.kill(os.getpid(), signal.SIGTERM)

    monkeypatch.setattr(usvtool.trace, "write_events", write_then_signal)
    r = simulate(usv, write_scenario(directory, {**BASE, "sim": {"duration": 2}}), out)
    assert r.exit_code == 143 and r.stdout == ""
    assert r.stderr.strip() == "Error: interrupted by SIGTERM"
    assert_untouched(out)


@pytest.mark.parametrize("signum, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_to_a_running_simulation(case, signum, status):
    directory, out = case
    # minutes of work: a goal 20 km away (with BASE's goal the ship arrives after 590 steps, in
    # well under a second, and a signal sent from a busy machine could come after the end)
    own = {**BASE["own"], "goal": [100, 20000]}
    scenario = write_scenario(directory, {**BASE, "own": own, "sim": {"duration": 3600}})
    proc = subprocess.Popen(
        [sys.executable, "-m", "usvtool.cli", "-v", "simulate", scenario, "-o", out / "trace.csv",
         "--events", out / "events.json", "--tracks", out / "tracks.geojson"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),  # even if we ignore it
    )  # fmt: skip
    try:
        first = proc.stderr.readline()  # "running udwa for 3600 s": the run starts
        assert "running udwa" in first, first
        proc.send_signal(signum)
        stdout, stderr = proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == status, stderr
    assert stderr.splitlines() == [f"Error: interrupted by {signal.Signals(signum).name}"]
    assert stdout == ""
    assert_untouched(out)


def assert_failed(result, code, *words):
    assert result.exit_code == code, (result.stdout, result.stderr)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    if code == 1:
        assert len(lines) == 1, result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr
    for w in words:
        assert w in result.stderr, result.stderr
    assert result.stdout == ""


def assert_untouched(out: Path) -> None:
    assert sorted(p.name for p in out.iterdir()) == ["trace.csv"]  # no temporary left
    assert (out / "trace.csv").read_bytes() == OLD


def test_the_events_run_object_holds_the_scenario_as_resolved(case, usv):
    """Readers of a run (batch, report) take its ships, lengths and files from here, not from
    the YAML: an unnamed target is ``target<i>`` with the YAML's length."""
    directory, out = case
    data = copy.deepcopy(BASE)
    del data["targets"][1]["name"]  # the second target, unnamed, 3 m long
    data["map"], data["route"] = "map.tif", "route.geojson"
    data["sim"]["duration"] = 2
    r = simulate(usv, write_scenario(directory, data), out)
    assert r.exit_code == 0, r.stderr
    run = read_events(out / "events.json")["run"]
    assert run["ships"] == [{"name": "own", "length": run["own_length"]},
                            {"name": "t1", "length": 2.5}, {"name": "target2", "length": 3.0},
                            {"name": "t3", "length": 2.0}]  # fmt: skip
    assert [s["name"] for s in run["ships"]] == list(read_trace(out / "trace.csv").ships)
    assert run["scenario_file"] == str((directory / "s.yaml").resolve())
    assert run["map"] == str((directory / "map.tif").resolve())
    assert run["route"] == str((directory / "route.geojson").resolve())
    assert run["tracks"] == [None, None, str((directory / "track.csv").resolve())]
    assert run["wind_field"] is None


def test_files_beside_the_events_are_named_relative_to_them(case, usv):
    """A run written with its scenario (a batch job's directory, renamed when done) names the
    files below the events' folder relative to it, the others absolute."""
    directory, out = case
    (out / "map.tif").write_bytes((directory / "map.tif").read_bytes())
    data = {**copy.deepcopy(BASE), "map": "map.tif", "sim": {"duration": 1}}
    data["targets"][2]["track"] = "../track.csv"
    r = simulate(usv, write_scenario(out, data), out)
    assert r.exit_code == 0, r.stderr
    run = read_events(out / "events.json")["run"]
    assert (run["scenario_file"], run["map"]) == ("s.yaml", "map.tif")
    assert run["tracks"][2] == str((directory / "track.csv").resolve())


def test_a_label_names_the_run_s_controller_in_its_summary_and_events(case, usv):
    directory, out = case
    data = copy.deepcopy(BASE)
    data["sim"]["duration"] = 3
    r = simulate(usv, write_scenario(directory, data), out, "--param", "weather=false",
                 "--label", "udwa-calm")  # fmt: skip
    assert r.exit_code == 0, r.stderr
    summary = json.loads(r.stdout)
    events = json.loads((out / "events.json").read_text())
    assert summary["controller"] == events["controller"] == events["run"]["controller"]
    assert summary["controller"] == "udwa-calm"
    assert events["run"]["parameters"]["weather"] is False
