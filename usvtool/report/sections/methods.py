"""The report's methods section: what produced the results and how to produce them again.

Versions of usvtool and its main libraries, the git commit of the source tree, the machine,
the seeds and every job's parameters (from each job's ``job.json``), and the commands to rerun.
Nothing here depends on the time of day, so the same results give the same page.
"""

from __future__ import annotations

import os
import platform
import subprocess
from importlib import metadata
from pathlib import Path

from usvtool import __version__
from usvtool.report.data import Results, seed_text
from usvtool.report.document import Cell, Section, Table

LIBRARIES = ("numpy", "scipy", "rasterio", "pyogrio", "shapely", "pyproj",
             "opencv-python-headless", "scikit-fuzzy", "matplotlib", "jinja2", "weasyprint",
             "click", "pyyaml")  # fmt: skip
RERUN = ("make report  (pipelines/full.yaml: usvtool batch, then usvtool report)",
         "usvtool batch pipelines/full.yaml -j 2 -o build/batch",
         "usvtool report build/batch/metrics.csv -o build/report")  # fmt: skip


def git_commit() -> str:
    """The commit of the source tree (``+changes`` when it has uncommitted ones), or
    ``unknown`` outside a git work tree."""
    where = Path(__file__).resolve().parent
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=where, capture_output=True,
                              text=True, timeout=10)  # fmt: skip
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                               cwd=where, capture_output=True, text=True, timeout=10)  # fmt: skip
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    if head.returncode != 0:
        return "unknown"
    if dirty.returncode != 0:  # the tree's state unknown (e.g. the index locked meanwhile)
        return head.stdout.strip() + " (uncommitted changes unknown)"
    return head.stdout.strip() + (" +changes" if dirty.stdout.strip() else "")


def _version(name: str) -> str:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "not installed"


def _memory_gib() -> str:
    try:
        pages, size = os.sysconf("SC_PHYS_PAGES"), os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return "unknown"
    return f"{pages * size / 2**30:.0f} GiB"


def section(results: Results) -> Section:
    s = Section("methods", "Methods")
    s.paragraphs.append(
        "Every figure of this report comes from the results tables named below and the job "
        "files beside them; the same tables give the same page. Timings are those of the "
        "machine described here.")
    software = [[Cell("usvtool"), Cell(__version__)], [Cell("git commit"), Cell(git_commit())],
                [Cell("Python"), Cell(platform.python_version())]]  # fmt: skip
    software += [[Cell(name), Cell(_version(name))] for name in LIBRARIES]
    machine = [[Cell("system"), Cell(f"{platform.system()} {platform.machine()}")],
               [Cell("processor"), Cell(platform.processor() or platform.machine())],
               [Cell("cores"), Cell(str(os.cpu_count()))],
               [Cell("memory"), Cell(_memory_gib())]]  # fmt: skip
    s.blocks.append(Table("methods-software", "Software", "", ["package", "version"], software))
    s.blocks.append(Table("methods-machine", "Machine", "", ["", ""], machine))
    rows = []
    for kind in ("routes", "runs", "functions"):
        for case in results.cases(kind):
            for method in results.methods(kind, case):
                jobs = results.select(kind, case, method)
                seeds = sorted(j.seed for j in jobs if j.seed is not None)
                args = jobs[0].config.get("args")
                rows.append([Cell(kind), Cell(case), Cell(method), Cell(seed_text(seeds)),
                             Cell(" ".join(map(str, args)) if args else "-")])  # fmt: skip
    s.blocks.append(Table("methods-jobs", "Jobs and parameters",
                          "Each (case, method) with its seeds and the command line of its "
                          "first job (the others differ in the seed only).",
                          ["kind", "case", "method", "seeds", "command"], rows))  # fmt: skip
    tables = ", ".join(str(t) for t in results.tables)
    s.paragraphs.append(f"Results tables: {tables}. To run it all again: " + "; ".join(RERUN))
    return s

