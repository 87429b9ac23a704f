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
def table(tmp_path) -> Path:
    """A one-row table in ``batch/`` whose job's folder holds its record (and no other file)."""
    job = tmp_path / "batch" / "routes" / "0a"
    job.mkdir(parents=True)
    (job / "job.json").write_text(json.dumps({"kind": "routes", "key": "0a", "files": {}}))
    write_results(tmp_path / "batch" / "metrics.csv",
                  [Row("0a", "routes", "env1", "iwso", 1, "length_m", "701.5")])  # fmt: skip
    return tmp_path / "batch" / "metrics.csv"


@pytest.fixture
def draw(monkeypatch):
    """``draw(shade, names)``: the report's one section holds the figures ``names`` drawn in
    ``shade``."""

    def patch(shade: int = 0, names=("f1", "f2")) -> None:
        monkeypatch.setattr(build, "sections", lambda results, workers=1: [
            Section("s", "S", blocks=[figure(n, shade) for n in names])])  # fmt: skip

    return patch


@pytest.fixture
def make(table, draw):
    """``make(out, shade, names)``: the report of the table into ``out``, its figures
    ``names`` drawn in ``shade``."""

    def run(out: Path, shade: int = 0, names=("f1", "f2")):
        draw(shade, names)
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
    assert sorted(p.name for p in tmp_path.iterdir()) == ["batch"]  # no report/, data/


def test_a_failure_leaves_an_earlier_report_as_it_was(make, tmp_path, monkeypatch):
    out = tmp_path / "report"
    make(out, shade=10)
    before = tree(out)
    assert sorted(before) == [".usvtool-report.json", "data", "data/f1.csv", "data/f2.csv",
                              "figures", "figures/f1.png", "figures/f2.png", "index.html"]
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
    assert summary_line(summary).startswith(f"report: {tmp_path}/build/report/index.html (")
    assert " kB), no PDF (--no-pdf); claims: " in summary_line(summary)


#: A user's own files in the report's folder, its figures/ and its data/.
USERS = {"notes.txt": b"mine", "readme.md": b"# mine", "data/mydata.csv": b"a,b\n1,2\n",
         "figures/holiday.png": b"\x89PNG holiday", "data/f3.csv.bak": b"kept"}  # fmt: skip


def test_user_files_survive_and_only_the_reports_own_files_it_no_longer_writes_go(make, tmp_path):
    out = tmp_path / "report"
    for name, content in USERS.items():
        (out / name).parent.mkdir(parents=True, exist_ok=True)
        (out / name).write_bytes(content)
    make(out, names=("f1", "f2", "f3"))
    assert {n: tree(out)[n] for n in USERS} == USERS
    make(out, names=("f1", "f2"))  # f3 no longer drawn
    make(out, names=("f2",))  # nor f1
    after = tree(out)
    assert {n: after[n] for n in USERS} == USERS  # every file of the user's, as it was
    assert sorted(set(after) - set(USERS)) == [".usvtool-report.json", "data", "data/f2.csv",
                                               "figures", "figures/f2.png", "index.html"]
    assert json.loads(after[".usvtool-report.json"]) == {
        "files": ["data/f2.csv", "figures/f2.png", "index.html"]}


def test_a_report_without_a_list_of_its_files_before_it_removes_nothing(make, tmp_path):
    """An older usvtool's report left no list: its figures stay (not provably the report's)."""
    out = tmp_path / "report"
    make(out, names=("f1", "f2"))
    (out / ".usvtool-report.json").unlink()
    make(out, names=("f2",))
    assert sorted(p.name for p in (out / "figures").iterdir()) == ["f1.png", "f2.png"]
    make(out, names=())  # this one's list names f2 only: f2 goes, f1 stays
    assert sorted(p.name for p in (out / "figures").iterdir()) == ["f1.png"]


@pytest.mark.parametrize("listed", [["../outside.txt"], ["figures/../../outside.txt"],
                                    ["data/x/../../../outside.txt"], ["notes.txt"], "x"])
def test_a_list_naming_a_file_the_report_never_writes_is_refused(make, tmp_path, listed):
    out = tmp_path / "report"
    make(out, names=("f1",))
    (tmp_path / "outside.txt").write_text("precious")
    (out / "notes.txt").write_text("mine")
    (out / ".usvtool-report.json").write_text(json.dumps({"files": listed}))
    before = tree(tmp_path)
    with pytest.raises(UsvError, match=rf"^{re.escape(str(out / '.usvtool-report.json'))}: not "
                                       r"the list of a report's files \("):  # fmt: skip
        make(out, names=("f2",))
    assert tree(tmp_path) == before


@pytest.mark.parametrize("link", ["data", "figures"])
def test_a_link_below_the_output_folder_is_refused_in_one_line(usv, table, draw, tmp_path, link):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "precious.csv").write_text("precious")
    out = tmp_path / "report"
    draw(names=("f1",))
    assert usv("report", table, "-o", out, "--no-pdf").exit_code == 0
    draw(names=("f2",))  # the report of f1 is stale: f1.png and f1.csv would go
    shutil.rmtree(out / link)
    (out / link).symlink_to(elsewhere, target_is_directory=True)
    before = tree(tmp_path)
    r = usv("report", table, "-o", out, "--no-pdf")
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr.splitlines() == [
        f"Error: {out / link}: a symbolic link (to {elsewhere}) in the output directory {out}: "
        "nothing is written or removed through a link below it; remove the link or choose "
        "another directory"]
    assert tree(tmp_path) == before  # precious.csv and the report as they were


def test_a_file_of_the_report_replaced_by_a_link_is_refused(make, tmp_path):
    out = tmp_path / "report"
    make(out, names=("f1",))
    (tmp_path / "precious.html").write_text("precious")
    (out / "index.html").unlink()
    (out / "index.html").symlink_to(tmp_path / "precious.html")
    with pytest.raises(UsvError, match="index.html: a symbolic link"):
        make(out, names=("f1",))
    assert (tmp_path / "precious.html").read_text() == "precious"


def test_an_output_folder_that_is_a_link_is_written_through(make, tmp_path):
    """-o names the link: the user chose where it points."""
    (tmp_path / "real").mkdir()
    (tmp_path / "link").symlink_to(tmp_path / "real", target_is_directory=True)
    make(tmp_path / "link", names=("f1",))
    assert sorted(tree(tmp_path / "real")) == [".usvtool-report.json", "data", "data/f1.csv",
                                               "figures", "figures/f1.png", "index.html"]


@pytest.mark.parametrize("value, said", [("701.5", "line 3 repeats line 2"),
                                         ("99999", "line 2 says '701.5', line 3 says '99999'")])
def test_a_table_giving_a_jobs_metric_twice_is_refused_naming_the_lines(make, table, tmp_path,
                                                                       value, said):  # fmt: skip
    with open(table, "a") as f:
        f.write(f"0a,routes,env1,iwso,1,length_m,{value}\n")
    message = f"{table}: job 0a, metric length_m: {said} (a job has one row a metric)"
    with pytest.raises(UsvError, match=f"^{re.escape(message)}$"):
        make(tmp_path / "report")
    assert not (tmp_path / "report").exists()


@pytest.mark.parametrize("record, why", [
    (None, "missing (job 0a): run the batch again"),
    ({"kind": "routes", "key": "0a"}, "lists no files with their size and SHA-256 (an older "
                                      "usvtool's batch) (job 0a): run the batch again"),
    ({"kind": "routes", "key": "0b", "files": {}}, "not the record of job 0a (job 0a): run the "
                                                   "batch again"),
    ({"key": "0a", "files": {"../../metrics.csv": {"size": 1, "sha256": "00"}}},
     "lists '../../metrics.csv', not a file of its folder (job 0a): run the batch again"),
])  # fmt: skip
def test_a_job_folder_whose_files_cannot_be_checked_is_refused_even_with_allow_missing(
        table, draw, tmp_path, record, why):  # fmt: skip
    path = table.parent / "routes" / "0a" / "job.json"
    if record is None:
        path.unlink()
    else:
        path.write_text(json.dumps(record))
    draw()
    with pytest.raises(UsvError, match=f"^{re.escape(f'{path}: {why}')}$"):
        build.make_report(build.ReportOptions((str(table),), str(tmp_path / "r"), pdf=False,
                                              allow_missing=True))  # fmt: skip
    assert not (tmp_path / "r").exists()


def test_a_file_in_a_job_folder_its_record_does_not_list_is_refused(make, table, tmp_path):
    extra = table.parent / "routes" / "0a" / "route.geojson"
    extra.write_text("{}")
    with pytest.raises(UsvError, match=f"^{re.escape(str(extra))}: a file job.json does not list "
                                       "\\(job 0a\\): run the batch again$"):  # fmt: skip
        make(tmp_path / "r")
    extra.unlink()
    make(tmp_path / "r")  # the folder as its record lists it
