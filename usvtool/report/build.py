"""``usvtool report``: the comparison report of one or more results tables.

Writes into the output directory ``index.html`` (self-contained), ``report.pdf`` (the same page
laid out by WeasyPrint; skipped with a one-line hint when WeasyPrint cannot run),
``figures/<file>.png`` and ``data/<file>.csv`` (each figure's picture and data; ``<file>`` its
id as a :func:`usvtool.results.file_name`) and the list of them all (:mod:`.manifest`). Every
file is staged and renamed together (:func:`usvtool.report.output.write_together`, which writes
through no link below the directory), ``index.html`` last; the directories made for them are
removed again when that fails (a full disk), so a failed report leaves the output directory as
it was. The files the list of the report before lists and this one no longer writes are then
removed, and no other.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from usvtool.errors import UsvError
from usvtool.report import evidence, manifest
from usvtool.report.data import load
from usvtool.report.document import Section
from usvtool.report.figures import styles
from usvtool.report.output import write_together
from usvtool.report.page import PdfUnavailable, html, pdf
from usvtool.report.sections import SECTIONS, TASKS, builders, claims, your_claims

TITLE = "usvtool: path planning and collision avoidance, compared with the papers"


@dataclass(frozen=True)
class ReportOptions:
    """``tables``: results tables (``usvtool batch``'s ``metrics.csv``); ``out``: the report's
    directory; ``pdf``: also write ``report.pdf``; ``workers``: processes building the
    sections (None: the cores, at most 4); ``order``: the methods in the order the stages'
    registries list them (``usvtool report`` gives it; :func:`usvtool.report.data.load`);
    ``allow_missing``: report without the job folders that are missing rather than refuse
    (:func:`usvtool.report.evidence.check`)."""

    tables: tuple[str, ...]
    out: str = "build/report"
    pdf: bool = True
    workers: int | None = None
    order: tuple[str, ...] = ()
    allow_missing: bool = False


@dataclass
class ReportResult:
    out: Path
    sections: list[Section]
    html_bytes: int
    pdf_bytes: int | None
    pdf_pages: int | None
    hint: str | None = None
    verdicts: dict[str, int] = field(default_factory=dict)  # the papers' claims'
    your_verdicts: dict[str, int] = field(default_factory=dict)  # the user's claims
    main_pages: int | None = None  # the PDF's pages before the appendix
    missing: list[Path] = field(default_factory=list)  # job folders reported without

    def summary(self) -> dict:
        return {
            "output": str(self.out / "index.html"),
            "pdf": None if self.pdf_bytes is None else str(self.out / "report.pdf"),
            "html_bytes": self.html_bytes,
            "pdf_bytes": self.pdf_bytes,
            "pdf_pages": self.pdf_pages,
            "main_pages": self.main_pages,
            "sections": [s.id for s in self.sections],
            "figures": sum(len(s.figures()) for s in self.sections),
            "tables": sum(len(s.tables()) for s in self.sections),
            "claims": self.verdicts,
            "your_claims": self.your_verdicts,
            "pdf_hint": self.hint,
            "missing_jobs": len(self.missing),
        }


def sections(results, workers: int = 1) -> list[Section]:
    """The report's sections, in reading order (:data:`usvtool.report.sections.SECTIONS`; a
    section without data is left out). With ``workers`` > 1 they are built in that many forked
    processes, by the tasks of :data:`usvtool.report.sections.TASKS` (their figures are most of
    the report's time); each figure's bytes do not depend on where it is drawn."""
    import multiprocessing

    if workers > 1 and "fork" in multiprocessing.get_all_start_methods():
        from concurrent.futures import ProcessPoolExecutor

        _FORKED[:] = [results]  # the workers inherit it: not pickled to each task
        try:
            context = multiprocessing.get_context("fork")
            with ProcessPoolExecutor(workers, mp_context=context) as pool:
                done = [f.result() for f in [pool.submit(_task, i) for i in range(len(TASKS))]]
        finally:
            _FORKED.clear()
        by_module = {m: s for task, built in zip(TASKS, done, strict=True)
                     for m, s in zip(task, built, strict=True)}
        built = [by_module[m] for m in SECTIONS]
    else:
        built = [b(results) for b in builders()]
    return [s for s in built if s is not None]


#: The results the forked workers of :func:`sections` build from.
_FORKED: list = []


def _task(i: int) -> list[Section | None]:
    """The sections of task ``i`` of :data:`~usvtool.report.sections.TASKS`, in a forked worker."""
    return [m.section(_FORKED[0]) for m in TASKS[i]]


def outputs(out: Path, page: str, document: bytes | None,
            parts: list[Section]) -> dict[Path, bytes]:  # fmt: skip
    """Every file of the report by its path in ``out``, ``index.html`` first (renamed last),
    the :mod:`.manifest` listing them last."""
    files = {out / "index.html": page.encode("utf-8")}
    if document is not None:
        files[out / "report.pdf"] = document
    for f in (f for s in parts for f in s.figures()):
        files[out / "figures" / f"{f.file}.png"] = f.png
        files[out / "data" / f"{f.file}.csv"] = f.data.encode("utf-8")
    files[out / manifest.NAME] = manifest.text(out, list(files))
    return files


def make_report(options: ReportOptions) -> ReportResult:
    out = Path(options.out)
    if out.exists() and not out.is_dir():
        raise UsvError(f"-o {out}: is a file, not a directory")
    if not out.parent.is_dir():
        raise UsvError(f"-o {out}: directory {out.parent} does not exist")
    before = manifest.previous(out)  # refused before the work when it is not the report's
    results = load(options.tables, options.order)
    results.missing = evidence.check(results, options.allow_missing)
    styles.assign(options.order)  # a method without a hand-chosen style gets its own
    parts = sections(results, options.workers or min(os.cpu_count() or 1, 4))
    subtitle = (f"{len(results.jobs)} jobs from {len(results.tables)} results table(s): "
                "every optimizer on every chart, every controller in every encounter, beside "
                "the published figures of the three papers.")  # fmt: skip
    page = html(TITLE, subtitle, parts)
    document, pages, main_pages, hint = None, None, None, None
    if options.pdf:
        try:
            document, pages, main_pages = pdf(html(TITLE, subtitle, parts, "print"))
        except PdfUnavailable as e:
            hint = str(e)
    files = outputs(out, page, document, parts)
    write_together(files, out, remove=sorted(before - set(files)))
    return ReportResult(out, parts, len(files[out / "index.html"]),
                        None if document is None else len(document), pages, hint,
                        claims.counts(parts), claims.counts(parts, your_claims.TABLE),
                        main_pages, results.missing)  # fmt: skip
