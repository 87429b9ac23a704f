"""A tiny family pipeline (tests/batch/families.yaml) through ``usvtool batch``: the expected
runs, the same table and the same scene bytes at -j 1 and -j 2, a rerun skips them all; a
family that cannot keep its promise fails its job alone, in one line."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from usvtool.batch.jobs import expand
from usvtool.cli.batch import stage_names
from usvtool.pipeline import load
from usvtool.results import read_results

pytestmark = pytest.mark.slow  # two batches in worker processes

ROOT = Path(__file__).resolve().parent.parent.parent
TINY = ROOT / "tests" / "batch" / "families.yaml"
CASES = {"emergency/head-on/s004", "emergency/crossing/s004", "emergency/overtaking/s004",
         "iwso/static/s002", "imazu/01/s000", "imazu/13/s000", "wind/halves/s001"}  # fmt: skip


def batch(*args):
    cmd = [sys.executable, "-m", "usvtool.cli", "batch", *map(str, args)]
    return subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The tiny pipeline at -j 1 and at -j 2: their directories."""
    out = {}
    for workers in (1, 2):
        out[workers] = tmp_path_factory.mktemp(f"j{workers}")
        r = batch(TINY, "-j", workers, "-o", out[workers])
        assert r.returncode == 0, r.stderr
    return out


def test_the_tiny_pipeline_expands_into_its_runs():
    names = stage_names()
    jobs = expand(load(TINY, names), names)
    assert len(jobs) == 3 * 2 + 1 + 2 + 1 == 10
    assert {j.case for j in jobs} == CASES and {j.kind for j in jobs} == {"runs"}
    emergency = {(j.case, j.method) for j in jobs if j.case.startswith("emergency/")}
    assert len(emergency) == 6 and {m for _, m in emergency} == {"dwa", "udwa"}


def test_j1_and_j2_give_the_same_table_and_the_same_scenes(runs):
    one, two = runs[1], runs[2]
    assert (one / "metrics.csv").read_bytes() == (two / "metrics.csv").read_bytes()
    rows = read_results(one / "metrics.csv")
    assert {r.case for r in rows} == CASES
    assert {r.metric for r in rows} >= {"arrived", "closest_distance_m"}
    for job in (one / "runs").iterdir():
        scene = sorted(p.name for p in job.glob("scenario*"))
        assert scene[-1] == "scenario.yaml", job
        for name in scene:
            assert (job / name).read_bytes() == (two / "runs" / job.name / name).read_bytes()
        record = json.loads((job / "job.json").read_text())
        summary = json.loads((job / "summary.json").read_text())
        assert summary["scene"]["draws"] >= 1 and summary["time_s"] == 3.0
        assert record["scene"]["family"] == summary["scene"]["family"]


def test_a_rerun_skips_every_run(runs):
    r = batch(TINY, "-j", 1, "-o", runs[1])
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout)
    assert (summary["done"], summary["skipped"], summary["failed"]) == (0, 10, 0)


def test_a_family_that_cannot_keep_its_promise_fails_its_job_alone(tmp_path):
    pipeline = tmp_path / "p.yaml"
    entry = {"family": "wind", "kinds": ["halves"], "scenes": [0], "controllers": ["udwa"],
             "seeds": [1]}  # fmt: skip
    pipeline.write_text(yaml.safe_dump({"root": str(ROOT), "families": [
        {**entry, "options": {"duration": 1}},
        {**entry, "name": "bad", "options": {"duration": 1, "ramp": 300}}]}))  # fmt: skip
    r = batch(pipeline, "-j", 1, "-o", tmp_path / "out")
    assert r.returncode == 1
    summary = json.loads(r.stdout)
    assert (summary["done"], summary["failed"]) == (1, 1)
    (failure,) = summary["failures"]
    assert failure["case"] == "bad/halves/s000"
    assert failure["error"] == (
        "Error: family wind, kind halves, scene 0: no draw of 100 keeps its promise (100 forces "
        "[2, 3] off the line, not 1 and 4)"
    )
