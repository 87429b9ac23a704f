"""The batch writes only inside ``-o DIR``: a link in its tree is refused or replaced in one
line, never written through; a folder it cannot remove is named with its job (docs/batch.md,
"Resume")."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "tests" / "batch" / "scenarios" / "open-head-on.yaml"


@pytest.fixture
def pipeline(tmp_path):
    """One run (open-head-on, dwa) and one function run."""
    (tmp_path / "s.yaml").write_text(SCENARIO.read_text())
    path = tmp_path / "p.yaml"
    path.write_text("root: .\nsimulation: {scenarios: [s.yaml], controllers: [dwa], seeds: [1]}\n"
                    "functions: {functions: [F1], algorithms: [pso], seeds: [1], pop: 4, "
                    "iters: 3, dim: 2}\n")  # fmt: skip
    return path


@pytest.fixture
def outside(tmp_path):
    """A folder outside the batch's, holding a file of the user's."""
    d = tmp_path / "outside"
    d.mkdir()
    (d / "precious.csv").write_text("mine\n")
    return d


def _refused(ran, *words):
    assert ran.exit_code == 1 and ran.summary is None, ran.stderr
    lines = ran.stderr.splitlines()
    assert len(lines) == 1 and "Traceback" not in ran.stderr, ran.stderr
    assert all(w in lines[0] for w in words), lines[0]


def test_a_lock_that_is_a_link_is_refused_and_its_target_kept(pipeline, outside, inline_batch):
    out = pipeline.parent / "out"
    out.mkdir()
    (out / ".lock").symlink_to(outside / "precious.csv")
    _refused(inline_batch(pipeline, out), f"{out / '.lock'}", "a link", "remove it")
    assert (outside / "precious.csv").read_text() == "mine\n"  # it used to be truncated
    assert sorted(p.name for p in out.iterdir()) == [".lock"]


def test_a_kind_folder_that_is_a_link_is_refused_and_nothing_lands_outside(pipeline, outside,
                                                                         inline_batch):  # fmt: skip
    out = pipeline.parent / "out"
    out.mkdir()
    (out / "runs").symlink_to(outside, target_is_directory=True)
    _refused(inline_batch(pipeline, out), f"{out / 'runs'} is a link", "only inside -o")
    assert sorted(p.name for p in outside.iterdir()) == ["precious.csv"]


def test_a_job_folder_that_is_a_link_is_replaced_by_its_result(pipeline, outside, inline_batch):
    """It used to stop every later batch with a traceback (rmtree of a link)."""
    out = pipeline.parent / "out"
    assert inline_batch(pipeline, out).counts() == (2, 0, 0)
    (run,) = (out / "runs").iterdir()
    shutil.copytree(run, outside / "copy")
    shutil.rmtree(run)
    run.symlink_to(outside / "copy", target_is_directory=True)
    again = inline_batch(pipeline, out)
    assert again.exit_code == 0 and again.counts() == (1, 1, 0), again.stderr
    assert f"{run}: a link, not the folder its job wrote (the link removed)" in again.stderr
    assert run.is_dir() and not run.is_symlink() and (run / "trace.csv").is_file()
    assert sorted(p.name for p in (outside / "copy").iterdir()) == sorted(
        p.name for p in run.iterdir())  # the link's target untouched


def test_a_failed_job_folder_that_cannot_be_removed_is_named_with_its_job(pipeline, inline_batch):
    out = pipeline.parent / "out"
    assert inline_batch(pipeline, out).counts() == (2, 0, 0)
    (run,) = (out / "runs").iterdir()
    (run / "error.txt").write_text("it failed\n")  # as a failed job leaves it: runs again
    if subprocess.run(["chattr", "+i", str(run)], capture_output=True).returncode != 0:
        pytest.skip("chattr +i is not supported here (not root, or the filesystem)")
    try:
        ran = inline_batch(pipeline, out)
    finally:
        subprocess.run(["chattr", "-i", str(run)], check=True)
    _refused(ran, f"{run}: cannot remove the folder of runs s dwa seed 1 (failed) to run it again",
             "Operation not permitted")  # fmt: skip
