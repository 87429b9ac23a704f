"""``usvtool batch`` (docs/batch.md): the tables, job.json, -j 1 / -j 2 / Dask bytes, failures,
a worker killed in a job, a killed batch resumed, bad pipelines refused before anything runs."""

from __future__ import annotations

import csv
import importlib.util
import io
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from usvtool.batch.jobs import expand
from usvtool.batch.progress import Bar, Lines
from usvtool.cli import cli
from usvtool.cli.batch import scenario_files, stage_names
from usvtool.pipeline import load
from usvtool.results import TIMING_METRICS, read_results

pytestmark = pytest.mark.slow  # whole pipelines through usvtool batch

ROOT = Path(__file__).resolve().parent.parent
TINY = ROOT / "tests" / "batch" / "tiny.yaml"
SCENARIO = ROOT / "tests" / "batch" / "scenarios" / "open-head-on.yaml"
# the tiny pipeline: 1 grid; astar (exact: 1 route) and pso at seeds 1, 2; 1 scenario x dwa, gdwa;
# F1 x pso, gwo at seeds 1, 2
JOBS = 1 + (1 + 2) + 2 + 4
PYARROW = importlib.util.find_spec("pyarrow") is not None
TABLES = ("metrics.csv", "metrics.parquet") if PYARROW else ("metrics.csv",)


def batch(*args, cwd=ROOT, env=None):
    cmd = [sys.executable, "-m", "usvtool.cli", "batch", *map(str, args)]
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, env=env)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """An uninterrupted -j 1 run of the tiny pipeline: its directory."""
    out = tmp_path_factory.mktemp("ref")
    r = batch(TINY, "-j", 1, "-o", out)
    assert r.returncode == 0, r.stderr
    return out


def test_j2_killed_and_resumed_gives_the_bytes_of_j1_and_a_rerun_skips_all(reference, tmp_path):
    cmd = [sys.executable, "-m", "usvtool.cli", "batch", str(TINY), "-j", "2", "-o", str(tmp_path)]
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)  # fmt: skip
    deadline = time.monotonic() + 30

    def done():  # results renamed into place (not the temporaries of the jobs running)
        return [p for p in tmp_path.glob("runs/*/trace.csv") if p.parent.name[0] != "."]

    while not done() and time.monotonic() < deadline:
        time.sleep(0.02)
    os.killpg(proc.pid, signal.SIGKILL)  # the batch and its workers, with no warning
    proc.wait()
    assert done() and not (tmp_path / "metrics.csv").exists()
    # the jobs whose results were renamed into place before the kill (how many depends on
    # timing): exactly these are skipped
    finished = [p for p in tmp_path.glob("*/*") if p.is_dir() and p.name[0] != "."]
    r = batch(TINY, "-j", 2, "-o", tmp_path)
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout)
    assert summary["jobs"] == JOBS and summary["failed"] == 0
    assert summary["skipped"] == len(finished) >= 1
    assert summary["done"] + summary["skipped"] == JOBS
    assert set(summary["stage_time_s"]) <= {"grids", "routes", "runs", "functions", "table"}
    assert not list(tmp_path.glob("*/.tmp-*"))
    for name in TABLES:
        assert (tmp_path / name).read_bytes() == (reference / name).read_bytes()
    again = batch(TINY, "-o", tmp_path, "--summary", tmp_path / "summary.json")
    assert again.returncode == 0, again.stderr
    assert json.loads(again.stdout)["skipped"] == JOBS and json.loads(again.stdout)["done"] == 0
    assert (tmp_path / "summary.json").read_text() == again.stdout
    assert (tmp_path / "metrics.csv").read_bytes() == (reference / "metrics.csv").read_bytes()
    assert f"batch: {JOBS} jobs: 0 done, {JOBS} skipped, 0 failed in " in again.stderr


def test_the_table_holds_every_job_but_the_grid_and_no_timing(reference):
    rows = read_results(reference / "metrics.csv")
    jobs = {(r.kind, r.case, r.method, r.seed) for r in rows}
    assert jobs == {("routes", "grid20", "astar", None), ("routes", "grid20", "pso", 1),
                    ("routes", "grid20", "pso", 2), ("runs", "open-head-on", "dwa", 1),
                    ("runs", "open-head-on", "gdwa", 1), ("functions", "F1", "pso", 1),
                    ("functions", "F1", "pso", 2), ("functions", "F1", "gwo", 1),
                    ("functions", "F1", "gwo", 2)}  # fmt: skip
    assert not {r.metric for r in rows} & set(TIMING_METRICS)
    assert [r.key for r in rows] == sorted(r.key for r in rows)
    timings = read_results(reference / "timings.csv")
    walls = {r.key for r in timings if r.metric == "wall_time_s"}
    assert walls == {r.key for r in rows} and all(r.number >= 0 for r in timings)
    assert sum(r.metric == "planning_time_s" for r in timings) == 3  # the routes
    if PYARROW:  # the same rows, seeds as integers (null for the exact planner)
        import pyarrow.parquet as pq

        table = pq.read_table(reference / "metrics.parquet").to_pylist()
        assert [tuple(r.values()) for r in table] == [
            (r.key, r.kind, r.case, r.method, r.seed, r.metric, r.value) for r in rows]
    else:
        assert not (reference / "metrics.parquet").exists()
    # the figures are those of the commands run on their own
    pso = next(r for r in rows if r.method == "pso" and r.kind == "functions" and r.seed == 1)
    alone = subprocess.run([sys.executable, "-m", "usvtool.cli", "functions", "--function", "F1",
                            "--algo", "pso", "--runs", "1", "--seed", "1", "--pop", "10",
                            "--iters", "20", "--dim", "5", "--format", "csv"],
                           capture_output=True, text=True, check=True)  # fmt: skip
    assert float(pso.value) == float(next(csv.DictReader(io.StringIO(alone.stdout)))["best"])
    route = next(r for r in rows if r.method == "astar" and r.metric == "length_m")
    measured = subprocess.run([sys.executable, "-m", "usvtool.cli", "metrics",
                               reference / "routes" / route.key / "route.geojson"],
                              capture_output=True, text=True, check=True)  # fmt: skip
    assert route.value == next(csv.DictReader(io.StringIO(measured.stdout)))["length_m"]


def _without_timing(route: Path) -> dict:
    data = json.loads(route.read_text())
    for feature in data["features"]:
        feature["properties"].pop("planning_time_s")
    return data


def test_a_job_run_in_process_gives_the_files_of_a_command_of_its_own(reference, tmp_path):
    key = next(r.key for r in read_results(reference / "metrics.csv") if r.seed == 2
               and r.method == "pso" and r.kind == "routes")  # fmt: skip
    job = json.loads((reference / "routes" / key / "job.json").read_text())
    grid = str(reference / "grids" / job["grid"] / "grid.tif")
    args = [grid if a.endswith("/grid.tif") else a for a in job["args"][:-1]]
    subprocess.run([sys.executable, "-m", "usvtool.cli", *args, tmp_path / "alone.geojson"],
                   check=True, capture_output=True)  # fmt: skip
    assert _without_timing(tmp_path / "alone.geojson") == _without_timing(
        reference / "routes" / key / "route.geojson")


def test_job_json_says_what_ran_and_where_its_inputs_are(reference):
    rows = read_results(reference / "metrics.csv")
    route = next(r for r in rows if r.kind == "routes" and r.method == "pso" and r.seed == 2)
    job = json.loads((reference / "routes" / route.key / "job.json").read_text())
    assert (job["kind"], job["case"], job["method"], job["seed"]) == ("routes", "grid20", "pso", 2)
    assert (job["start"], job["goal"], job["frame"]) == ([0.5, 0.5], [19.5, 19.5], "map")
    grid = reference / "grids" / job["grid"]
    assert {"grid.tif", "preview.png", "summary.json", "job.json"} <= {p.name for p in
                                                                       grid.iterdir()}
    assert job["args"][:2] == ["plan", f"../../grids/{job['grid']}/grid.tif"]
    assert job["args"][job["args"].index("--seed") + 1] == "2" and job["wall_time_s"] > 0
    run = next(r for r in rows if r.kind == "runs" and r.method == "gdwa")
    job = json.loads((reference / "runs" / run.key / "job.json").read_text())
    assert Path(job["scenario"]) == SCENARIO and job["args"][0] == "simulate"
    assert (reference / "runs" / run.key / "trace.csv").is_file()
    fn = next(r for r in rows if r.kind == "functions" and r.method == "gwo" and r.seed == 2)
    job = json.loads((reference / "functions" / fn.key / "job.json").read_text())
    assert (job["pop"], job["iters"], job["dim"]) == (10, 20, 5)
    assert job["args"][job["args"].index("--runs") + 1] == "1"


def _pipeline(tmp_path: Path, scenarios: dict[str, str]) -> Path:
    """The tiny pipeline's runs and functions in tmp_path, its runs those of these scenario files
    (name: YAML text). No grid and no routes: the tests that use it are about runs, and the
    functions' jobs, after the runs in a batch's order, stand by them (a job that must still
    run after a worker died)."""
    (tmp_path / "s").mkdir()
    for name, text in scenarios.items():
        (tmp_path / "s" / f"{name}.yaml").write_text(text)
    tiny = TINY.read_text()
    pipeline = "root: .\n" + tiny[tiny.index("simulation:"):]
    (tmp_path / "p.yaml").write_text(pipeline.replace("tests/batch/scenarios/*.yaml", "s/*.yaml"))
    return tmp_path / "p.yaml"


#: The jobs of :func:`_pipeline` but its runs: the function runs (F1 x pso, gwo at seeds 1, 2).
FUNCTION_JOBS = 4


#: The failpoints a worker is killed at (usvtool.batch.failpoint.POINTS).
KILL_POINTS = ("before", "during", "written", "sending")
DIED = "its worker process died (killed by SIGKILL)"


@pytest.fixture(scope="module")
def killed(tmp_path_factory):
    """One ``batch -j 2`` of the tiny pipeline's runs and functions, with scenarios "good",
    "bad" (its command fails) and "killed-POINT" for each failpoint, whose runs' workers are
    killed at POINT (SIGKILL); then the same batch again without failpoints. What the first
    batch left (before the second touched it) and what the second said."""
    tmp_path = tmp_path_factory.mktemp("killed")
    good = SCENARIO.read_text()
    scenarios = {"good": good, "bad": good.replace("speed: 4}", "speed: 4, max_speed: 0}")}
    for i, point in enumerate(KILL_POINTS):  # other durations: each scenario a run of its own
        scenarios[f"killed-{point}"] = good.replace("duration: 6", f"duration: {7 + i}")
    path = _pipeline(tmp_path, scenarios)
    names = stage_names()
    armed = [f"{j.case.removeprefix('killed-')}:{j.key}" for j in expand(load(path, names), names)
             if j.case.startswith("killed-")]  # fmt: skip
    assert len(armed) == 2 * len(KILL_POINTS)
    out = tmp_path / "out"
    env = {**os.environ, "USVTOOL_FAILPOINT": ",".join(armed)}
    proc = subprocess.run([sys.executable, "-m", "usvtool.cli", "batch", str(path), "-j", "2",
                           "-o", str(out)], cwd=ROOT, capture_output=True, text=True, env=env,
                          timeout=480)  # fmt: skip
    left = {
        "proc": proc,
        "summary": json.loads(proc.stdout),
        "run_cases": {r.case for r in read_results(out / "metrics.csv") if r.kind == "runs"},
        "kinds": {r.kind for r in read_results(out / "metrics.csv")},
        "recorded": sorted(p.read_text() for p in out.glob("runs/*/error.txt")),
        "temporaries": list(out.glob("*/.tmp-*")),
    }
    # a failed job runs again (no failpoint now), a done one not
    left["again"] = batch(path, "-o", out)
    return left


@pytest.mark.parametrize("point", KILL_POINTS)
def test_a_worker_killed_at_any_point_of_a_job_fails_that_job_alone(killed, point):
    """USVTOOL_FAILPOINT kills the worker of each "killed-POINT" run at POINT (SIGKILL): the
    batch settles every job and ends; a job whose result was complete and in place before its
    worker died ("written", "sending": the reply cut short in the pipe) is done, the others
    fail alone with the cause, and run again next time. One batch kills at every point (the
    fixture's); each test checks the whole batch's outcome and its own point's jobs."""
    proc, summary = killed["proc"], killed["summary"]
    errors = {(f["case"], f["method"]): f["error"] for f in summary["failures"]}
    assert all("max_speed must be > 0" in errors.pop(("bad", c)) for c in ("dwa", "gdwa"))
    mine = {c: errors.get((f"killed-{point}", c)) for c in ("dwa", "gdwa")}
    if point in ("written", "sending"):
        assert mine == {"dwa": None, "gdwa": None}
        assert f"killed-{point}" in killed["run_cases"]
    else:
        assert mine == {"dwa": DIED, "gdwa": DIED}
        assert f"killed-{point}" not in killed["run_cases"]
    # the whole batch: the runs killed before their result was in place failed, nothing else
    assert errors == {(f"killed-{p}", c): DIED for p in ("before", "during")
                      for c in ("dwa", "gdwa")}  # fmt: skip
    jobs = FUNCTION_JOBS + (2 + len(KILL_POINTS)) * 2  # and the runs: good, bad, killed-*
    assert summary["jobs"] == jobs
    assert (summary["done"], summary["failed"]) == (jobs - 6, 6)
    assert f"6 of {jobs} jobs failed" in proc.stderr
    assert killed["kinds"] == {"runs", "functions"}
    assert killed["run_cases"] == {"good", "killed-written", "killed-sending"}
    recorded = killed["recorded"]
    assert len(recorded) == summary["failed"] and all(t.count("\n") == 1 for t in recorded)
    assert proc.returncode == 1 and not killed["temporaries"]
    again = killed["again"]
    assert again.returncode == 1 and json.loads(again.stdout)["skipped"] == summary["done"]


def test_a_dask_cluster_gives_the_same_bytes(reference, tmp_path):
    distributed = pytest.importorskip("distributed", reason="dask[distributed] is not installed "
                                      "(pip install 'usvtool[dask]')")  # fmt: skip
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                                  dashboard_address=None) as cluster:  # fmt: skip
        r = batch(TINY, "--scheduler", cluster.scheduler_address, "-o", tmp_path)
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout)
    assert summary["executor"].startswith("dask ") and summary["done"] == JOBS
    for name in TABLES:
        assert (tmp_path / name).read_bytes() == (reference / name).read_bytes()


def invoke(*args):
    return CliRunner().invoke(cli, ["batch", *map(str, args)])


@pytest.mark.parametrize(
    "old, new, field",
    [
        ("algorithms: [astar, pso]", "algorithms: [astar, psoo]", "routes.tiny.algorithms[1]: "
         "unknown algorithm 'psoo'"),
        ("charts: [grid20]", "charts: [grid20, grid21]", "routes.tiny.charts[1]: unknown chart "
         "'grid21'"),
        ("source: charts/grid20.geojson", "source: charts/grid21.geojson", "charts.grid20.source: "
         "charts/grid21.geojson: no such file"),
        ("seeds: {first: 1, count: 2}", "seeds: {first: 1, count: 0}", "routes.tiny.seeds.count: "
         "expected an integer >= 1, got 0"),
        ("simulation:", "routes:\n  tiny: {charts: [grid20], algorithms: [pso], seeds: [3]}\n"
         "simulation:", "line 14: 'routes' named twice"),
        ("routes:\n  tiny:", "routes:\n  tiny2: {charts: [grid20], algorithms: [pso], seeds: [1],"
         " attempts: 3}\n  tiny:", "routes.tiny: grid20 pso seed 1 is also in routes.tiny2 with "
         "other options"),
        ("controllers: [dwa, gdwa]", "controllers: [dwa, gdwa, dwa]", "simulation.controllers: "
         "named twice: dwa"),
        # an option naming an output: the grid job would write it outside -o DIR
        ("occupancy: 0.5}", "occupancy: 0.5, summary: ../../../x.json}",
         "charts.grid20.options.summary: names an output file"),
        ("options: {pop: 10, iters: 10}", "options: {pop: 10, iters: 10, summary: /tmp/x.json}",
         "routes.tiny.options.summary: names an output file"),
    ],
)  # fmt: skip
def test_a_bad_pipeline_is_one_line_exit_1_and_nothing_runs(tmp_path, old, new, field):
    text = TINY.read_text()
    assert old in text
    path = tmp_path / "bad.yaml"
    path.write_text(text.replace("root: ../..", f"root: {ROOT}").replace(old, new, 1))
    r = invoke(path, "-o", tmp_path / "out")
    assert r.exit_code == 1
    assert r.output == f"Error: {path}: {field}" + r.output.split(field, 1)[1]
    assert r.output.count("\n") == 1
    assert not (tmp_path / "out").exists()


def test_scheduler_errors_are_one_line(tmp_path, monkeypatch):
    r = invoke(TINY, "--scheduler", "tcp://127.0.0.1:1", "-o", tmp_path / "out")
    assert r.exit_code == 1 and r.output.count("\n") == 1
    assert "--scheduler tcp://127.0.0.1:1: cannot reach the scheduler" in r.output
    assert not (tmp_path / "out").exists()
    r = invoke(TINY, "--scheduler", "localhost", "-o", tmp_path / "out")
    assert r.exit_code == 1 and "not a scheduler address" in r.output
    assert invoke(TINY, "-j", "2", "--scheduler", "tcp://127.0.0.1:1").exit_code == 2
    fake = tmp_path / "fake"  # an environment without dask: its import fails
    (fake / "distributed").mkdir(parents=True)
    (fake / "distributed" / "__init__.py").write_text("raise ImportError('no dask here')\n")
    env = {**os.environ, "PYTHONPATH": str(fake)}
    r = batch(TINY, "--scheduler", "tcp://127.0.0.1:1", "-o", tmp_path / "out", env=env)
    assert r.returncode == 1
    assert r.stderr == ("Error: --scheduler: dask.distributed is not installed (pip install "
                        "'usvtool[dask]')\n")  # fmt: skip


def test_progress_lines_and_bar(capsys, monkeypatch):
    stream = io.StringIO()
    lines = Lines(3, 1, "here", stream)
    lines.advance("runs a dwa seed 1", None)
    lines.advance("runs b dwa seed 1", "Error: boom")
    lines.close()
    text = stream.getvalue().splitlines()
    assert text[0] == "batch: 3 jobs, 1 already done, on here"
    assert text[1] == "batch: FAILED runs b dwa seed 1: Error: boom"
    assert text[-1].startswith("batch: 3 jobs: 1 done, 1 skipped, 1 failed in ")
    bar = Bar(2, 0, "there")
    bar.advance("x", None)
    bar.advance("y", None)
    bar.close()
    assert "batch: 2 jobs: 2 done, 0 skipped, 0 failed in " in capsys.readouterr().err


def test_a_run_key_covers_the_files_its_scenario_names(tmp_path):
    """Changing a target's track file (or any file a scenario names) gives the run a new key,
    so a resumed batch reruns it; changing a file it does not name keeps the key."""
    track = "t,x,y\n0,100,90\n10,100,60\n"
    scenario = (SCENARIO.read_text().replace("{name: t1, start: [100, 90], heading: 180, ",
                                             "{name: t1, track: t1.csv, "))  # fmt: skip
    assert "track: t1.csv" in scenario
    path = _pipeline(tmp_path, {"tracked": scenario})
    (tmp_path / "s" / "t1.csv").write_text(track)
    (tmp_path / "s" / "other.csv").write_text(track)
    names = stage_names()

    def run_keys() -> set[str]:
        jobs = expand(load(path, names), names, scenario_files)
        return {j.key for j in jobs if j.kind == "runs"}

    before = run_keys()
    assert len(before) == 2  # dwa, gdwa
    (tmp_path / "s" / "other.csv").write_text(track + "20,100,30\n")
    assert run_keys() == before
    (tmp_path / "s" / "t1.csv").write_text(track + "20,100,30\n")
    after = run_keys()
    assert len(after) == 2 and not after & before
    # and the run itself reads the track: the batch runs it
    r = batch(path, "-j", 1, "-o", tmp_path / "out")
    assert r.returncode == 0, r.stderr


def test_a_job_over_the_timeout_is_stopped_and_fails_alone(tmp_path):
    """--timeout 12: the run the failpoint ``hang`` makes sleep for ever is stopped and fails
    with the reason; the other run (well under a second; 3.7 s on a machine at a load of 11,
    a third of the limit) completes, and no temporary is left."""
    good = SCENARIO.read_text()
    (tmp_path / "s").mkdir()
    (tmp_path / "s" / "good.yaml").write_text(good)
    (tmp_path / "s" / "far.yaml").write_text(good.replace("duration: 6", "duration: 7"))
    path = tmp_path / "p.yaml"
    path.write_text("root: .\nsimulation: {scenarios: [s/*.yaml], controllers: [dwa], "
                    "seeds: [1]}\n")  # fmt: skip
    names = stage_names()
    far = [j.key for j in expand(load(path, names), names) if j.case == "far"]
    out = tmp_path / "out"
    env = {**os.environ, "USVTOOL_FAILPOINT": ",".join(f"hang:{k}" for k in far)}
    r = subprocess.run([sys.executable, "-m", "usvtool.cli", "batch", str(path), "-j", "2",
                        "--timeout", "12", "-o", str(out)], cwd=ROOT, capture_output=True,
                       text=True, env=env, timeout=240)  # fmt: skip
    assert r.returncode == 1 and "1 of 2 jobs failed" in r.stderr, r.stderr
    summary = json.loads(r.stdout)
    assert [(f["case"], f["error"]) for f in summary["failures"]] == [
        ("far", "it ran longer than --timeout 12 s and was stopped")]
    assert summary["done"] == 1 and (out / "runs").is_dir()
    assert not list(out.glob("*/.tmp-*"))
    refused = batch(path, "--timeout", 4, "--scheduler", "tcp://127.0.0.1:1", "-o", out)
    assert refused.returncode == 2 and "--timeout: not with --scheduler" in refused.stderr
