"""``usvtool batch`` (docs/batch.md): the local pool, resume, failures, a killed batch."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
TINY = ROOT / "tests" / "batch" / "tiny.yaml"


def batch(*args, cwd=ROOT):
    cmd = [sys.executable, "-m", "usvtool.cli", "batch", *map(str, args)]
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """An uninterrupted -j 1 run of the tiny pipeline: its directory."""
    out = tmp_path_factory.mktemp("ref")
    r = batch(TINY, "-j", 1, "-o", out)
    assert r.returncode == 0, r.stderr
    return out


def test_j1_and_j2_give_the_same_table_and_a_rerun_skips_everything(reference, tmp_path):
    table = (reference / "metrics.csv").read_bytes()
    assert table.startswith(b"key,kind,job,metric,value\n")
    r = batch(TINY, "-j", 2, "-o", tmp_path)
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout)
    assert (summary["jobs"], summary["done"], summary["skipped"], summary["failed"]) == (5, 5, 0, 0)
    assert (tmp_path / "metrics.csv").read_bytes() == table
    again = batch(TINY, "-o", tmp_path)
    assert again.returncode == 0, again.stderr
    assert json.loads(again.stdout)["skipped"] == 5 and json.loads(again.stdout)["done"] == 0
    assert (tmp_path / "metrics.csv").read_bytes() == table


def test_a_failing_job_is_recorded_and_the_others_complete(tmp_path):
    (tmp_path / "charts").mkdir()
    shutil.copy(ROOT / "charts" / "grid20.geojson", tmp_path / "charts")
    (tmp_path / "s").mkdir()
    good = (ROOT / "tests" / "batch" / "scenarios" / "open-head-on.yaml").read_text()
    (tmp_path / "s" / "good.yaml").write_text(good)
    (tmp_path / "s" / "bad.yaml").write_text(good.replace("speed: 4}", "speed: 4, max_speed: 0}"))
    pipeline = TINY.read_text().replace("root: ../..", "root: .")
    pipeline = pipeline.replace("tests/batch/scenarios/*.yaml", "s/*.yaml")
    (tmp_path / "p.yaml").write_text(pipeline)
    out = tmp_path / "out"
    r = batch(tmp_path / "p.yaml", "-j", 2, "-o", out)
    assert r.returncode == 1
    assert "2 of 7 jobs failed" in r.stderr
    summary = json.loads(r.stdout)
    assert (summary["done"], summary["failed"]) == (5, 2)
    errors = sorted(out.glob("runs/*/error.txt"))
    assert len(errors) == 2
    assert all("max_speed must be > 0" in e.read_text() for e in errors)
    assert len(errors[0].read_text().splitlines()) == 1
    table = (out / "metrics.csv").read_text()
    assert table.count("routes,route grid20 astar,length_m") == 1
    assert "good.yaml" in table and "bad.yaml" not in table
    again = batch(tmp_path / "p.yaml", "-o", out)  # a failed job is tried again
    assert again.returncode == 1 and json.loads(again.stdout)["skipped"] == 5


def test_a_killed_batch_rerun_gives_the_table_of_an_uninterrupted_run(reference, tmp_path):
    cmd = [sys.executable, "-m", "usvtool.cli", "batch", str(TINY), "-j", "1", "-o", str(tmp_path)]
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)  # fmt: skip
    deadline = time.monotonic() + 20

    def done():  # results renamed into place (not the temporaries of the jobs running)
        return [p for p in tmp_path.glob("routes/*/route.geojson") if p.parent.name[0] != "."]

    while not done() and time.monotonic() < deadline:
        time.sleep(0.02)
    os.killpg(proc.pid, signal.SIGKILL)  # the batch and the job it is running
    proc.wait()
    assert not (tmp_path / "metrics.csv").exists()
    r = batch(TINY, "-o", tmp_path)
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["skipped"] >= 2
    assert not list(tmp_path.glob("*/.tmp-*"))
    assert (tmp_path / "metrics.csv").read_bytes() == (reference / "metrics.csv").read_bytes()
