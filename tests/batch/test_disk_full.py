"""A full disk under ``-o DIR``: every error names the file; a failure the batch can still
write is recorded (``error.txt``) and the batch goes on; one it cannot write stops the batch
with one line saying why and where (docs/batch.md, "Failures"). The disk is filled by making
the writes fail with ENOSPC, as ``write(2)`` does (its error names no file)."""

from __future__ import annotations

import builtins
import errno
import io
import json
import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "tests" / "batch" / "scenarios" / "open-head-on.yaml"
NO_SPACE = os.strerror(errno.ENOSPC)


class _Full:
    """A file open for writing on a full disk: every write fails."""

    def __init__(self, f):
        self._f = f

    def write(self, data):
        raise OSError(errno.ENOSPC, NO_SPACE)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self._f.close()

    def __getattr__(self, name):
        return getattr(self._f, name)


def fill(monkeypatch, under: Path, mkdir: bool, names: set[str] | None = None) -> None:
    """From now on writing a file under ``under`` (named in ``names``, when given) fails with
    ENOSPC; with ``mkdir``, making a directory there fails too (mkdir's error names it)."""

    def inside(path) -> bool:
        if isinstance(path, int):
            return False
        p = Path(os.path.abspath(path))
        return p.is_relative_to(under) and (names is None or p.name in names)

    real_open, real_mkdir = io.open, os.mkdir

    def full_open(file, mode="r", *args, **kwargs):
        f = real_open(file, mode, *args, **kwargs)
        return _Full(f) if set(mode) & set("wax+") and inside(file) else f

    def full_mkdir(path, mode=0o777, *, dir_fd=None):
        if inside(path) and not os.path.exists(path):
            raise OSError(errno.ENOSPC, NO_SPACE, os.fspath(path))
        return real_mkdir(path, mode, dir_fd=dir_fd)

    monkeypatch.setattr(io, "open", full_open)
    monkeypatch.setattr(builtins, "open", full_open)
    if mkdir:
        monkeypatch.setattr(os, "mkdir", full_mkdir)


@pytest.fixture
def earlier(tmp_path, inline_batch):
    """A batch of one run done in ``out``, then a pipeline of three more jobs (a run, two
    function runs): (pipeline, out, the earlier run's directory)."""
    (tmp_path / "s").mkdir()
    (tmp_path / "s" / "a.yaml").write_text(SCENARIO.read_text())
    pipeline = tmp_path / "p.yaml"
    pipeline.write_text("root: .\nsimulation: {scenarios: [s/*.yaml], controllers: [dwa], "
                        "seeds: [1]}\n")  # fmt: skip
    out = tmp_path / "out"
    assert inline_batch(pipeline, out).counts() == (1, 0, 0)
    other = SCENARIO.read_text().replace("duration: 6", "duration: 5")
    (tmp_path / "s" / "b.yaml").write_text(other)
    with open(pipeline, "a") as f:
        f.write("functions: {functions: [F1], algorithms: [pso], seeds: [1, 2], pop: 4, "
                "iters: 3, dim: 2}\n")  # fmt: skip
    (run,) = (out / "runs").iterdir()
    return pipeline, out, run


@pytest.mark.parametrize("mkdir", [True, False], ids=["no-room-for-a-folder", "writes-only"])
def test_at_zero_bytes_free_the_batch_stops_with_one_line_saying_why_and_where(
    earlier, inline_batch, monkeypatch, mkdir
):
    pipeline, out, run = earlier
    before = {p.name: p.read_bytes() for p in run.iterdir()}
    fill(monkeypatch, out, mkdir)
    r = inline_batch(pipeline, out)
    assert r.exit_code == 1 and r.summary is None and "Traceback" not in r.stderr, r.stderr
    errors = [line for line in r.stderr.splitlines() if line.startswith("Error:")]
    assert len(errors) == 1, r.stderr
    assert errors[0].startswith(f"Error: -o {out}: stopped: cannot record the failure of runs b "
                                f"dwa seed 1 ({out / 'runs'}/"), r.stderr  # fmt: skip
    # the inline executor has run the next job (two in flight), the third is not started
    assert f": cannot write: {NO_SPACE}); 1 job not run (what is done is kept" in errors[0]
    # each failure said on its line as it happened, naming the file (the run's own outputs,
    # writes-only: by the command, relative to the job's directory)
    failed = [line for line in r.stderr.splitlines() if line.startswith("batch: FAILED")]
    assert len(failed) == 2 and all(line.endswith(NO_SPACE) for line in failed), r.stderr
    assert failed[1].startswith(f"batch: FAILED functions F1 pso seed 1: {out}/functions")
    assert not list(out.glob("*/.tmp-*")) and not list(out.glob(".tmp-*"))
    assert {p.name: p.read_bytes() for p in run.iterdir()} == before  # what was done is kept
    assert [p.name for p in (out / "runs").iterdir()] == [run.name]


def test_with_room_for_the_records_the_failures_are_recorded_naming_the_file(
    earlier, inline_batch, monkeypatch
):
    """A disk with a little room: the jobs' summaries cannot be written, their error.txt and
    job.json can. Each new job fails naming its file, is recorded, and the batch goes on."""
    pipeline, out, _ = earlier
    fill(monkeypatch, out, mkdir=False, names={"summary.json"})
    r = inline_batch(pipeline, out)
    assert r.exit_code == 1 and r.counts() == (0, 1, 3), r.stderr
    assert "Error: 3 of 4 jobs failed" in r.stderr
    for failure in r.summary["failures"]:
        where = out / failure["kind"]
        assert failure["error"].startswith(f"{where}/.tmp-{failure['key']}-")
        assert failure["error"].endswith(f"/summary.json: cannot write: {NO_SPACE}")
        recorded = out / failure["kind"] / failure["key"]
        assert (recorded / "error.txt").read_text() == failure["error"] + "\n"
        assert json.loads((recorded / "job.json").read_text())["error"] == failure["error"]
    monkeypatch.undo()  # room again: the failed jobs run again, the others are kept
    again = inline_batch(pipeline, out)
    assert again.exit_code == 0 and again.counts() == (3, 1, 0), again.stderr
