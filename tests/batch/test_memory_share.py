"""``usvtool batch --max-memory`` (issue 22 item 6): each job gets its share of the budget (the
budget over the jobs that run at once) as ``--max-memory`` on its command line when it runs;
the share is not part of the job's arguments, so its key and ``job.json`` do not change."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from usvtool.batch.engine import BatchOptions, _job_command
from usvtool.batch.worker import with_memory
from usvtool.budget import default_budget

ROOT = Path(__file__).resolve().parents[2]


def recorder(calls: list):
    def command(args):
        calls.append(list(args))
        return 0, "", ""

    return command


def test_the_commands_that_take_a_budget_get_the_share_appended():
    calls: list = []
    for args in (["preprocess", "c.tif", "-o", "g.tif"], ["plan", "g.tif"], ["simulate", "s.yaml"],
                 ["functions", "--function", "F1"], ["metrics", "DIR"]):  # fmt: skip
        with_memory(recorder(calls), 1234, args)
    assert [c[-2:] for c in calls[:3]] == [["--max-memory", "1234"]] * 3
    assert calls[3:] == [["functions", "--function", "F1"], ["metrics", "DIR"]]


def test_the_share_is_the_budget_over_the_executors_capacity():
    calls: list = []
    options = BatchOptions(recorder(calls), None, max_memory=10_000)
    _job_command(options, 4)(["plan", "g.tif"])
    assert calls[-1] == ["plan", "g.tif", "--max-memory", "2500"]
    _job_command(BatchOptions(recorder(calls), None), 2)(["plan", "g.tif"])
    assert calls[-1][-1] == str(default_budget() // 2)
    # on a cluster, without a budget given, each job keeps its own machine's default
    command = recorder(calls)
    assert _job_command(BatchOptions(command, None, scheduler="tcp://h:1"), 8) is command
    _job_command(BatchOptions(command, None, scheduler="tcp://h:1", max_memory=800), 8)(["plan"])
    assert calls[-1] == ["plan", "--max-memory", "100"]


def test_a_job_over_its_share_fails_alone_and_keeps_its_key(tmp_path, inline_batch):
    shutil.copy(ROOT / "charts" / "grid20.geojson", tmp_path / "grid20.geojson")
    shutil.copy(ROOT / "tests" / "batch" / "scenarios" / "open-head-on.yaml", tmp_path / "s.yaml")
    (tmp_path / "p.yaml").write_text(
        "root: .\ncharts:\n  grid20: {source: grid20.geojson, options: {cell-size: 1},\n"
        "           start: [0.5, 0.5], goal: [19.5, 19.5]}\n"
        "routes:\n  r: {charts: [grid20], algorithms: [astar], seeds: [1]}\n"
        "simulation: {scenarios: [s.yaml], controllers: [dwa], seeds: [1]}\n")  # fmt: skip
    out = tmp_path / "out"
    # 250 MiB: under preprocess's 256 MiB for its process alone, over a short run's 246 MiB
    ran = inline_batch(tmp_path / "p.yaml", out, "--max-memory", "250M")
    assert ran.exit_code == 1 and ran.counts() == (1, 0, 2)
    errors = {f["kind"]: f["error"] for f in ran.summary["failures"]}
    assert "more than the budget of 0.24 GiB (--max-memory)" in errors["grids"]
    assert "its grid" in errors["routes"]
    (run_dir,) = (out / "runs").iterdir()
    assert "--max-memory" not in json.loads((run_dir / "job.json").read_text())["args"]
    # the default budget: the grid and its route run, the run is the same job and is skipped
    ran = inline_batch(tmp_path / "p.yaml", out)
    assert ran.exit_code == 0 and ran.counts() == (2, 1, 0)
    assert [p.name for p in (out / "runs").iterdir()] == [run_dir.name]
