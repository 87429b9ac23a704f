"""Writing the report (usvtool/report/build.py): all of it or nothing, whatever fails on the way.

The sections are two hand-made figures (real PNGs) so that only the writing is exercised."""

from __future__ import annotations

import errno
import json
import os
import re
import shutil
import subprocess
from pathlib import Path

import cv2
import numpy as np
import pytest

from usvtool.errors import UsvError
from usvtool.report import build
from usvtool.report.document import Figure, Section
from usvtool.results import Row, write_results


def figure(name: str, shade: int) -> Figure:
    ok, png = cv2.imencode(".png", np.full((8, 8), shade, np.uint8))
    assert ok
    return Figure(name, name, "a test figure", png.tobytes(), f"x,y\n{shade},1\n")


@pytest.fixture
def make(tmp_path, monkeypatch):
    """``make(out, shade)``: the report of a one-row table into ``out``, its two figures drawn
    in ``shade``."""
    table = tmp_path / "metrics.csv"
    write_results(table, [Row("0a", "routes", "env1", "iwso", 1, "length_m", "701.5")])

    def run(out: Path, shade: int = 0):
        monkeypatch.setattr(build, "sections", lambda results, workers=1: [
            Section("s", "S", blocks=[figure("f1", shade), figure("f2", shade)])])  # fmt: skip
        return build.make_report(build.ReportOptions((str(table),), str(out), pdf=False))

    return run


def full_disk_at(monkeypatch, name: str) -> None:
    """Writing the staged temporary of the file ``name`` fails: no space left on the device."""
    write_bytes = Path.write_bytes

    def failing(self, data):
        if self.name.startswith(f".{name}."):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return write_bytes(self, data)

    monkeypatch.setattr(Path, "write_bytes", failing)


def tree(root: Path) -> dict[str, bytes | None]:
    return {str(p.relative_to(root)): p.read_bytes() if p.is_file() else None
            for p in sorted(root.rglob("*"))}  # fmt: skip


@pytest.mark.parametrize("name, where", [("index.html", "index.html"), ("f1.png", "figures/f1.png"),
                                         ("f2.csv", "data/f2.csv")])  # fmt: skip
def test_a_full_disk_leaves_no_folder_and_names_the_file(make, tmp_path, monkeypatch, name, where):
    out = tmp_path / "report"
    full_disk_at(monkeypatch, name)
    with pytest.raises(UsvError, match=f"^{re.escape(str(out / where))}: cannot write it: No "
                                       "space left on device$"):  # fmt: skip
        make(out)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["metrics.csv"]  # no report/, data/


def test_a_failure_leaves_an_earlier_report_as_it_was(make, tmp_path, monkeypatch):
    out = tmp_path / "report"
    make(out, shade=10)
    before = tree(out)
    assert sorted(before) == ["data", "data/f1.csv", "data/f2.csv", "figures", "figures/f1.png",
                              "figures/f2.png", "index.html"]  # fmt: skip
    full_disk_at(monkeypatch, "f2.csv")
    with pytest.raises(UsvError, match="f2.csv: cannot write it"):
        make(out, shade=200)
    assert tree(out) == before  # no new figure, no temporary
    monkeypatch.undo()
    make(out, shade=200)
    assert tree(out)["data/f2.csv"] == b"x,y\n200,1\n"


def test_a_failure_in_an_output_directory_that_exists_removes_only_what_it_made(
        make, tmp_path, monkeypatch):  # fmt: skip
    out = tmp_path / "report"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    full_disk_at(monkeypatch, "f1.png")
    with pytest.raises(UsvError, match="f1.png: cannot write it"):
        make(out)
    assert tree(out) == {"notes.txt": b"mine"}


def test_the_summary_line_says_where_the_pages_and_the_verdicts():
    from usvtool.cli.report import summary_line

    claims = {"holds": 2, "does not hold": 1, "inconclusive": 4, "not testable": 1,
              "not tested": 0}  # fmt: skip
    summary = {"output": "r/index.html", "pdf": "r/report.pdf", "pdf_pages": 40,
               "main_pages": 29, "pdf_hint": None, "claims": claims}  # fmt: skip
    assert summary_line(summary) == (
        "report: r/index.html and r/report.pdf, 29 pages of main body, 40 in all; claims: "
        "2 holds, 1 does not hold, 4 inconclusive, 1 not testable, 0 not tested")
    summary.update(pdf=None, pdf_pages=None, main_pages=None)
    assert summary_line(summary).startswith("report: r/index.html, no PDF (--no-pdf); claims: 2")
    summary["pdf_hint"] = "install WeasyPrint"
    assert "no PDF (WeasyPrint cannot run: pdf_hint)" in summary_line(summary)


@pytest.mark.skipif(shutil.which("make") is None, reason="make is not installed")
def test_make_report_ends_with_the_summary_line(make, tmp_path):
    """The Makefile's report target on a report already made (``-o``: not remade): its last
    line is the summary's, from the report's ``--summary`` JSON."""
    (tmp_path / "build").mkdir()
    result = make(tmp_path / "build" / "report")
    summary = result.summary()
    (tmp_path / "build" / "report.json").write_text(json.dumps(summary))
    root = Path(__file__).resolve().parents[2]
    r = subprocess.run(["make", "-s", "-C", str(root), f"BUILD={tmp_path / 'build'}", "-o",
                        str(tmp_path / "build" / "report" / "index.html"), "report"],
                       capture_output=True, text=True, timeout=60)  # fmt: skip
    assert r.returncode == 0, r.stderr
    from usvtool.cli.report import summary_line

    assert r.stdout.splitlines()[-1] == summary_line(summary)
    assert summary_line(summary).startswith(f"report: {tmp_path}/build/report/index.html, no PDF")
