"""``usvtool report`` (docs/report.md) on a real small results set: tests/report/pipeline.yaml run
by ``usvtool batch``, then the report, read back as HTML, PDF and in headless Chromium."""

from __future__ import annotations

import base64
import json
import re
import shutil
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

from usvtool.report import build
from usvtool.report.page import PDF_HINT
from usvtool.report.papers import CLAIMS, TABLES

pytestmark = pytest.mark.slow  # the report built from a batch, with its PDF

ROOT = Path(__file__).resolve().parents[2]
PIPELINE = ROOT / "tests" / "report" / "pipeline.yaml"


def usvtool(*args, cwd=ROOT):
    cmd = [sys.executable, "-m", "usvtool.cli", *map(str, args)]
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)


def in_process(*args) -> subprocess.CompletedProcess:
    """``usvtool ARGS`` run in this process (click's runner; the console script is nothing but
    the group, usvtool.cli.main), as :func:`usvtool` gives it: exit status, stdout and stderr
    apart. An exception the command does not turn into its error line propagates and fails the
    test (where a process would print a traceback), so no traceback passes unseen. For the
    tests about the report's refusals and what it writes, not about the process: each saves the
    interpreter's start and the report stack's imports (about 1.3 CPU s)."""
    from click.testing import CliRunner

    from usvtool.cli import cli

    r = CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)
    return subprocess.CompletedProcess(args, r.exit_code, r.stdout, r.stderr)


@pytest.fixture(scope="module")
def batch(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("batch")
    r = usvtool("batch", PIPELINE, "-j", 2, "-o", out)
    assert r.returncode == 0, r.stderr
    return out / "metrics.csv"


@pytest.fixture(scope="module")
def report(batch, tmp_path_factory) -> tuple[Path, dict]:
    out = tmp_path_factory.mktemp("report") / "report"
    r = usvtool("report", batch, "-o", out)
    assert r.returncode == 0, r.stderr
    return out, json.loads(r.stdout)


class Page(HTMLParser):
    """Every element's attributes, the ids, and the tables' texts by id."""

    def __init__(self, text: str):
        super().__init__()
        self.attrs: list[tuple[str, str, str]] = []  # tag, attribute, value
        self.ids: list[str] = []
        self.images: list[str] = []
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            self.attrs.append((tag, name, value or ""))
            if name == "id":
                self.ids.append(value)
        if tag == "img":
            self.images.append(dict(attrs)["src"])


def _table_html(page: str, table_id: str) -> str:
    start = page.index(f'id="{table_id}"')
    return page[start:page.index("</table>", start)]


def test_the_page_references_nothing_outside_itself(report):
    out, _ = report
    page = Page((out / "index.html").read_text(encoding="utf-8"))
    for tag, name, value in page.attrs:
        if name in ("src", "href", "srcset", "action", "data", "poster"):
            assert value.startswith(("data:", "#")), (tag, name, value[:80])
    assert not any(tag in ("link", "script", "iframe", "object") for tag, _, _ in page.attrs)
    assert "url(" not in (out / "index.html").read_text(encoding="utf-8").split("</style>")[0]


def test_every_table_the_report_promises_is_there_with_the_papers_numbers(report):
    out, summary = report
    text = (out / "index.html").read_text(encoding="utf-8")
    ids = Page(text).ids
    for t in ("claims-table", "colregs-compliance", "functions-table", "charts-table",
              "methods-software", "routes-env1-table", "routes-grid20-table",
              "encounter-emergency-head-on-table", "encounter-emergency-head-on-snapshots",
              "encounter-emergency-head-on-distance",
              "routes-env1-map", "routes-env1-convergence", "routes-env1-boxes"):  # fmt: skip
        assert t in ids, t
    for paper_table in ("iwso-dwa-table-1", "iwso-dwa-table-2", "issa-table-3", "udwa-table-1"):
        html = _table_html(text, f"paper-{paper_table}")
        printed = {p for r in TABLES[paper_table].rows for p in r.printed if p}
        missing = [p for p in printed if f">{p}<" not in html]
        assert not missing, (paper_table, missing[:5])
    # the pipeline's claims before the papers'; anyangle, no paper's method, has its part
    assert summary["sections"] == ["summary", "your-claims", "claims", "planning", "functions",
                                   "encounters", "wind", "other-methods", "preprocessing",
                                   "methods"]  # fmt: skip
    for t in ("your-claims-table", "summary-your-verdicts", "other-anyangle-routes"):
        assert t in ids, t
    assert sum(summary["your_claims"].values()) == 2
    assert sum(summary["claims"].values()) == len(CLAIMS)  # the papers' counted apart


def test_each_figure_is_embedded_written_and_its_data_beside_it(report):
    out, summary = report
    text = (out / "index.html").read_text(encoding="utf-8")
    page = Page(text)
    assert len(page.images) == summary["figures"] >= 8
    pngs = sorted((out / "figures").glob("*.png"))
    assert len(pngs) == summary["figures"]
    embedded = {base64.b64decode(src.split(",", 1)[1]) for src in page.images}
    assert embedded == {p.read_bytes() for p in pngs}
    for p in pngs:
        data = (out / "data" / f"{p.stem}.csv").read_text(encoding="utf-8")
        link = re.search(rf'href="data:text/csv;base64,([^"]+)" download="{p.stem}.csv"', text)
        assert link and base64.b64decode(link.group(1)).decode("utf-8") == data
        assert data.count("\n") >= 2  # a header and data


def test_the_pdf_main_body_then_the_appendix_and_the_html_only_parts_left_out(report):
    pdfium = pytest.importorskip("pypdfium2")
    out, summary = report
    pdf = pdfium.PdfDocument(str(out / "report.pdf"))
    text = [pdf[i].get_textpage().get_text_range() for i in range(len(pdf))]
    assert len(pdf) == summary["pdf_pages"] > summary["main_pages"] >= 1
    # the appendix starts the page after the main body's last (style.css), and only there
    assert text[summary["main_pages"]].startswith("Appendix")
    assert not any(t.startswith("Appendix") for t in text[:summary["main_pages"]])
    assert text[0].startswith("usvtool: path planning")
    if "summary" in summary["sections"]:  # page 1 is the summary, the contents after it
        assert text[0].index("Summary") < text[0].find("Contents") or "Contents" not in text[0]
    # every job's command line: folded in the HTML, not in the PDF
    page = (out / "index.html").read_text(encoding="utf-8")
    folded = page.index('<details class="html-only"><summary>Every job')
    assert page.index('id="methods-jobs"') > folded
    assert not any("Every job's command line" in t for t in text)
    image = np.asarray(pdf[0].render(scale=1).to_pil().convert("L"))
    assert (image < 128).mean() > 0.005 and len(np.unique(image)) > 10


def test_without_weasyprint_the_same_html_and_pngs_are_written_and_a_line_says_what_to_install(
        batch, report, tmp_path, monkeypatch):  # fmt: skip
    """In-process, with WeasyPrint "missing" and the sections built in this one process: the
    page and figures are those of the fixture's run, whose sections were built on several
    (same results, same bytes: build.sections' tasks), and no PDF."""
    def missing(page):
        raise build.PdfUnavailable("report.pdf not written (OSError: cannot load library "
                                   "'pango'): " + PDF_HINT)  # fmt: skip

    monkeypatch.setattr(build, "pdf", missing)
    one_process = build.sections
    monkeypatch.setattr(build, "sections", lambda results, workers: one_process(results, 1))
    from click.testing import CliRunner

    from usvtool.cli import cli

    r = CliRunner().invoke(cli, ["report", str(batch), "-o", str(tmp_path / "r")])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "r" / "index.html").is_file()
    assert not (tmp_path / "r" / "report.pdf").exists()
    warning = [line for line in r.stderr.splitlines() if line.startswith("Warning:")]
    assert len(warning) == 1 and "apt-get install libpango" in warning[0]
    assert json.loads(r.stdout)["pdf"] is None
    out, _ = report
    assert (tmp_path / "r" / "index.html").read_bytes() == (out / "index.html").read_bytes()
    for p in (out / "figures").glob("*.png"):
        assert (tmp_path / "r" / "figures" / p.name).read_bytes() == p.read_bytes(), p.name


#: Put first in a page's <head>: records every uncaught error and console error or warning.
CATCH = ("<script>window.usvErrors = []; window.addEventListener('error', e => "
         "window.usvErrors.push(String(e.message))); for (const k of ['error', 'warn']) {"
         " const f = console[k]; console[k] = (...a) => {window.usvErrors.push(a.join(' '));"
         " f.apply(console, a)}; }</script>")  # fmt: skip
#: After load, what the page fetched (every resource but its own data: URIs) and its errors.
LOADED = ("d.errors = window.usvErrors.join(' | '); d.requests = performance"
          ".getEntriesByType('resource').map(r => r.name).join(' ');")  # fmt: skip
#: The player's test: folded at load (not started), opened from a link to it (started), Play
#: (its ship moves), Pause, the slider to mid-run (its ship moves). Headless Chromium dumping
#: the DOM draws no frame (requestAnimationFrame never fires under its virtual time), so a
#: frame is a 16 ms timer here.
PLAY = """<script>window.requestAnimationFrame = f => setTimeout(() => f(performance.now()), 16);
window.addEventListener('load', () => {
  const d = document.body.dataset, root = document.querySelector('div.usv-player');
  const hull = () => root.querySelector('svg.usv-map polygon').getAttribute('transform');
  d.atLoad = root.hasAttribute('data-ready') ? 'started' : 'folded';
  document.querySelector('td > a').click();
  setTimeout(() => {
    d.opened = root.getAttribute('data-ready') === '1' ? 'started' : 'not started';
    const before = hull();
    root.querySelector('button').click();
    setTimeout(() => {
      d.played = root.getAttribute('data-playing') === '1' && hull() !== before ? 'moved' : 'still';
      root.querySelector('button').click();
      const slider = root.querySelector('input[type=range]'), at = hull();
      slider.value = String(Math.round(Number(slider.max) / 2));
      slider.dispatchEvent(new Event('input'));
      d.slid = hull() !== at ? 'moved' : 'still';
      """ + LOADED + """
    }, 500);
  }, 100);
});</script></body>"""


def chromium_dom(page: str, path: Path, tmp_path: Path) -> str:
    """The DOM of ``page`` (written to ``path``) once headless Chromium has loaded it and run
    its timers (5 s of virtual time), no address resolving; the console's lines refused."""
    path.write_text(page.replace("<head>", "<head>" + CATCH, 1), encoding="utf-8")
    cmd = ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
           "--disable-background-networking", "--disable-component-update", "--disable-sync",
           "--host-resolver-rules=MAP * ~NOTFOUND", f"--user-data-dir={tmp_path / 'profile'}",
           "--virtual-time-budget=5000", "--enable-logging=stderr", "--v=0",
           "--dump-dom", path.as_uri()]  # fmt: skip
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert not [line for line in r.stderr.splitlines() if ":CONSOLE" in line], r.stderr[-2000:]
    return r.stdout


def body_data(dom: str) -> dict[str, str]:
    body = re.search(r"<body[^>]*>", dom)
    assert body, dom[:300]
    return dict(re.findall(r'data-([a-z-]+)="([^"]*)"', body.group(0)))


@pytest.mark.skipif(shutil.which("chromium") is None,
                    reason="Chromium is not installed (the Makefile installs Debian's chromium "
                           "as root; elsewhere: apt-get install chromium)")  # fmt: skip
def test_headless_chromium_shows_every_figure_and_plays_a_player(batch, report, tmp_path):
    out, summary = report
    page = (out / "index.html").read_text(encoding="utf-8")
    probe = ("<script>window.addEventListener('load', () => {const d = document.body.dataset; "
             "d.sizes = [...document.images].map(i => i.complete ? i.naturalWidth + 'x' + "
             "i.naturalHeight : '0x0').join(' '); " + LOADED + "})</script></body>")  # fmt: skip
    shown = body_data(chromium_dom(page.replace("</body>", probe), tmp_path / "probe.html",
                                   tmp_path))  # fmt: skip
    assert (shown["errors"], shown["requests"]) == ("", "")
    sizes = shown["sizes"].split()
    assert len(sizes) == summary["figures"]
    for size, png in zip(sizes, Page(page).images, strict=True):
        import cv2

        h, w = cv2.imdecode(np.frombuffer(base64.b64decode(png.split(",", 1)[1]), np.uint8),
                            cv2.IMREAD_UNCHANGED).shape[:2]  # fmt: skip
        assert size == f"{w}x{h}"
    # a run of the batch as the report plays one: folded, linked from a table's cell
    from usvtool.report.animation.embed import run_player
    from usvtool.report.document import Cell, Section, Table
    from usvtool.report.page import html
    from usvtool.trace import read_events, read_trace

    run = next(d for d in sorted((batch.parent / "runs").iterdir())
               if (d / "trace.csv").is_file())  # fmt: skip
    events = run / "trace.events.json"
    player = run_player(read_trace(run / "trace.csv"), read_events(events), events, "run-1",
                        "A run", "Its caption")  # fmt: skip
    links = Table("links", "Links", "c", ["run"], [[Cell("play it", link="run-1")]])
    page = html("Players", "s", [Section("runs", "Runs", ["text"], [links, player])])
    played = body_data(chromium_dom(page.replace("</body>", PLAY), tmp_path / "player.html",
                                    tmp_path))  # fmt: skip
    assert played == {"at-load": "folded", "opened": "started", "played": "moved",
                      "slid": "moved", "errors": "", "requests": ""}


@pytest.mark.parametrize(
    "args, status, message",
    [
        (["missing.csv"], 1, "missing.csv: no such file"),
        (["bad.csv"], 1, "not a results table"),
        ([], 2, "Missing argument"),
    ],
)
def test_bad_input_one_line_and_nothing_written(tmp_path, args, status, message):
    (tmp_path / "bad.csv").write_text("a,b\n1,2\n")
    r = usvtool("report", *args, "-o", tmp_path / "out", cwd=tmp_path)
    assert r.returncode == status and message in r.stderr, r.stderr
    errors = [line for line in r.stderr.splitlines() if line.startswith("Error:")]
    assert len(errors) == 1 and message in errors[0] and "Traceback" not in r.stderr
    assert not (tmp_path / "out").exists()


def test_an_output_that_is_a_file_is_refused(batch, tmp_path):
    (tmp_path / "out").write_text("keep")
    r = usvtool("report", batch, "-o", tmp_path / "out")
    assert r.returncode in (1, 2) and "out" in r.stderr
    assert (tmp_path / "out").read_text() == "keep"


def copy_of(batch: Path, tmp_path: Path) -> Path:
    """A copy of the fixture's batch (its table and job folders) to spoil: its table."""
    return shutil.copytree(batch.parent, tmp_path / "batch") / "metrics.csv"


def files_under(root: Path, leave_out: Path) -> dict[str, bytes | None]:
    """Every file and folder below ``root`` but those below ``leave_out``, with its bytes."""
    return {str(p): p.read_bytes() if p.is_file() else None for p in sorted(root.rglob("*"))
            if not p.is_relative_to(leave_out)}  # fmt: skip


def error_line(r) -> str:
    """The one line of a refusal: exit 1, no traceback, nothing on stdout."""
    assert (r.returncode, r.stdout) == (1, ""), r.stderr
    assert len(r.stderr.splitlines()) == 1 and "Traceback" not in r.stderr, r.stderr
    return r.stderr.strip()


def test_a_case_naming_a_path_writes_in_the_report_folder_only_under_an_encoded_name(
        batch, tmp_path):  # fmt: skip
    table = copy_of(batch, tmp_path)
    case = "x/../../../outside/<PWNED>"
    table.write_text(table.read_text().replace(",env1,", f",{case},"))
    out = tmp_path / "r" / "out"
    out.parent.mkdir()
    before = files_under(tmp_path, out)
    r = in_process("report", table, "-o", out, "--no-pdf")
    assert r.returncode == 0, r.stderr
    assert files_under(tmp_path, out) == before  # nothing written beside the report's folder
    encoded = "routes-x%2F..%2F..%2F..%2Foutside%2F%3CPWNED%3E"
    for name in ("map", "convergence", "boxes"):
        assert (out / "figures" / f"{encoded}-{name}.png").is_file()
        assert (out / "data" / f"{encoded}-{name}.csv").is_file()
    assert sorted(p.name for p in out.iterdir()) == [".usvtool-report.json", "data", "figures",
                                                     "index.html"]  # fmt: skip
    page = (out / "index.html").read_text(encoding="utf-8")
    assert "<h3>Chart x/../../../outside/&lt;PWNED&gt;</h3>" in page  # its name, escaped
    assert "<PWNED>" not in page
    assert f'download="{encoded}-map.csv"' in page


def test_a_table_without_its_job_folders_is_refused_naming_them_unless_allowed(batch, tmp_path):
    table = tmp_path / "alone" / "metrics.csv"
    table.parent.mkdir()
    shutil.copy(batch, table)
    rows = [line.split(",") for line in table.read_text().splitlines()[1:]]
    jobs = sorted({(key, kind) for key, kind, *_ in rows})
    n = len(jobs)
    folders = [str(tmp_path / "alone" / kind / key) for key, kind in jobs[:3]]
    out = tmp_path / "report"
    line = error_line(in_process("report", table, "-o", out, "--no-pdf"))
    assert line == (f"Error: {n} of {n} job folders are missing ({', '.join(folders)} and "
                    f"{n - 3} more): give the batch's table with its job folders beside it, or "
                    "--allow-missing to report without their files")
    assert not out.exists()
    r = in_process("report", table, "-o", out, "--no-pdf", "--allow-missing")
    assert r.returncode == 0, r.stderr
    warning, done = r.stderr.splitlines()  # the warning, then where the report is
    assert warning == (f"Warning: {n} job folders missing (--allow-missing): the report is "
                       "without their files; its methods section lists them")
    assert done.startswith(f"report: {out / 'index.html'} (") and "no PDF (--no-pdf)" in done
    assert json.loads(r.stdout)["missing_jobs"] == n
    missing = _table_html((out / "index.html").read_text(encoding="utf-8"), "methods-missing")
    assert missing.count("<tr>") == n + 1  # the header and one row a folder
    assert all(f">{f}<" in missing for f in folders)


@pytest.mark.parametrize("kind, name", [("runs", "trace.csv"), ("routes", "route.geojson"),
                                        ("grids", "preview.png")])  # fmt: skip
def test_a_job_file_changed_since_its_run_is_refused_naming_it_and_its_job(
        batch, tmp_path, kind, name):  # fmt: skip
    table = copy_of(batch, tmp_path)
    folder = sorted((table.parent / kind).iterdir())[0]
    size = (folder / name).stat().st_size
    with open(folder / name, "r+b") as f:  # one byte changed, the size kept: the SHA-256 tells
        f.write(b"\x00" if f.read(1) != b"\x00" else b"\x01")
    out = tmp_path / "report"
    line = error_line(in_process("report", table, "-o", out, "--no-pdf"))
    assert (folder / name).stat().st_size == size
    assert line == (f"Error: {folder / name}: its SHA-256 is not the one job.json records (job "
                    f"{folder.name}): run the batch again")
    assert not out.exists()
    (folder / name).unlink()
    line = error_line(in_process("report", table, "-o", out, "--no-pdf", "--allow-missing"))
    assert line == f"Error: {folder / name}: missing (job {folder.name}): run the batch again"
