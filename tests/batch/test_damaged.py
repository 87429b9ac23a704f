"""A result is read only when its files are the bytes its job wrote: ``job.json`` records the
size and SHA-256 of every other file of the job's directory; a rerun that finds one cut short,
changed or gone, or a ``job.json`` that does not parse, names the job on one line and runs it
again (docs/batch.md, "Resume")."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "tests" / "batch" / "scenarios" / "open-head-on.yaml"


@pytest.fixture
def done(tmp_path, inline_batch):
    """One run (open-head-on, dwa) and one function run, done in ``out``: (pipeline, out,
    the run's directory, metrics.csv's bytes)."""
    (tmp_path / "s.yaml").write_text(SCENARIO.read_text())
    pipeline = tmp_path / "p.yaml"
    pipeline.write_text("root: .\nsimulation: {scenarios: [s.yaml], controllers: [dwa], seeds: "
                        "[1]}\nfunctions: {functions: [F1], algorithms: [pso], seeds: [1], "
                        "pop: 4, iters: 3, dim: 2}\n")  # fmt: skip
    out = tmp_path / "out"
    first = inline_batch(pipeline, out)
    assert first.counts() == (2, 0, 0), first.stderr
    (run,) = (out / "runs").iterdir()
    return pipeline, out, run, (out / "metrics.csv").read_bytes()


def test_job_json_records_the_size_and_sha256_of_every_file(done):
    _, out, run, _ = done
    record = json.loads((run / "job.json").read_text())
    names = sorted(p.name for p in run.iterdir() if p.name != "job.json")
    assert names == ["summary.json", "trace.csv", "trace.events.json"]
    expected = {}
    for name in names:
        data = (run / name).read_bytes()
        expected[name] = {"size": len(data), "sha256": hashlib.sha256(data).hexdigest()}
    assert record["files"] == expected


def damaged_lines(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if "damaged" in line]


def test_a_trace_cut_at_a_line_boundary_is_named_and_run_again(done, inline_batch):
    pipeline, out, run, metrics = done
    trace = run / "trace.csv"
    lines = trace.read_text().splitlines(keepends=True)
    full = trace.stat().st_size
    trace.write_text("".join(lines[: len(lines) // 2]))  # a valid, shorter trace
    cut = trace.stat().st_size
    again = inline_batch(pipeline, out)
    assert again.exit_code == 0 and again.counts() == (1, 1, 0), again.stderr
    assert damaged_lines(again.stderr) == [
        f"batch: damaged, runs again: runs s dwa seed 1 ({run.name}): {trace}: {cut} bytes, "
        f"job.json records {full}"]  # fmt: skip
    assert (out / "metrics.csv").read_bytes() == metrics  # the run's own figures, not the cut's
    assert trace.stat().st_size == full
    clean = inline_batch(pipeline, out)
    assert clean.counts() == (0, 2, 0) and not damaged_lines(clean.stderr)


def test_a_changed_byte_of_the_same_size_is_found_by_its_sha256(done, inline_batch):
    pipeline, out, run, metrics = done
    events = run / "trace.events.json"
    data = bytearray(events.read_bytes())
    data[data.index(b"dwa")] = ord("x")
    events.write_bytes(bytes(data))
    again = inline_batch(pipeline, out)
    assert again.counts() == (1, 1, 0)
    assert damaged_lines(again.stderr) == [
        f"batch: damaged, runs again: runs s dwa seed 1 ({run.name}): {events}: its SHA-256 is "
        "not the one job.json records"]  # fmt: skip
    assert (out / "metrics.csv").read_bytes() == metrics


@pytest.mark.parametrize("damage, reason", [
    (lambda p: p.write_text(p.read_text()[:40]), "unreadable (not JSON)"),
    (lambda p: p.unlink(), "missing"),
    (lambda p: p.write_text(json.dumps({**json.loads(p.read_text()), "key": "0" * 16})),
     "not the record of job"),
    (lambda p: p.write_text(json.dumps({**json.loads(p.read_text()), "files": {
        "../../metrics.csv": {"size": 1, "sha256": "00"}}})),
     "lists '../../metrics.csv', not a file of its folder"),  # never read outside the folder
])  # fmt: skip
def test_a_job_json_cut_short_or_gone_is_named_and_run_again(done, inline_batch, damage, reason):
    pipeline, out, run, metrics = done
    damage(run / "job.json")
    again = inline_batch(pipeline, out)
    assert again.exit_code == 0 and again.counts() == (1, 1, 0), again.stderr
    (line,) = damaged_lines(again.stderr)
    assert line.startswith(f"batch: damaged, runs again: runs s dwa seed 1 ({run.name}): "
                           f"{run / 'job.json'}: {reason}")  # fmt: skip
    assert (out / "metrics.csv").read_bytes() == metrics


def test_a_missing_output_is_named_and_run_again(done, inline_batch):
    pipeline, out, run, metrics = done
    (run / "trace.csv").unlink()
    again = inline_batch(pipeline, out)
    assert again.counts() == (1, 1, 0)
    assert damaged_lines(again.stderr)[0].endswith(f"{run / 'trace.csv'}: missing")
    assert (out / "metrics.csv").read_bytes() == metrics
