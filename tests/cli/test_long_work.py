"""Long work says when it ends (issue 35, item 4): the batch's plain progress lines give the time
left at the pace so far, and ``usvtool report`` ends with where the report is and its size."""

from __future__ import annotations

import io

from click.testing import CliRunner

from usvtool.batch import progress
from usvtool.cli import cli


class Clock:
    """A monotonic clock the test moves."""

    def __init__(self):
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def test_plain_progress_lines_estimate_the_time_left(monkeypatch):
    clock = Clock()
    monkeypatch.setattr(progress.time, "monotonic", clock)
    stream = io.StringIO()
    # 10 jobs, 2 already done (no time); 4 run in 20 s: 5 s a job, 4 left: about 20 s
    lines = progress.Lines(10, 2, "here", stream)
    for _ in range(3):
        lines.advance("a job", None)
    clock.now += 20.0
    lines.advance("a job", None)
    said = stream.getvalue().splitlines()
    assert said[-1] == "batch: 6/10 (4 done, 2 skipped, 0 failed) after 20 s, about 20 s left"
    # a failed job ran too: 5 run in 30 s, 3 left: about 18 s
    clock.now += 10.0
    lines.advance("another", "Error: boom")
    assert stream.getvalue().splitlines()[-1].endswith("after 30 s, about 18 s left")


def test_usvtool_report_ends_with_where_the_report_is_and_its_size(monkeypatch, tmp_path):
    from usvtool.report import build

    class Done:
        hint, missing = None, []

        def summary(self):
            return {"output": str(tmp_path / "index.html"), "pdf": None, "pdf_hint": None,
                    "html_bytes": 3_456_789, "pdf_bytes": None, "claims": {"holds": 2}}

    monkeypatch.setattr(build, "make_report", lambda options: Done())
    table = tmp_path / "metrics.csv"
    table.write_text("")
    r = CliRunner().invoke(cli, ["report", str(table), "-o", str(tmp_path / "r"), "--no-pdf"])
    assert r.exit_code == 0, r.output
    assert r.stderr.splitlines()[-1] == (
        f"report: {tmp_path / 'index.html'} (3.5 MB), no PDF (--no-pdf); claims: 2 holds")
