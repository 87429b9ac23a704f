"""``usvtool report``: the comparison report of one or more results tables.

Writes into the output directory ``index.html`` (self-contained), ``report.pdf`` (the same page
laid out by WeasyPrint; skipped with a one-line hint when WeasyPrint cannot run),
``figures/<id>.png`` and ``data/<id>.csv`` (each figure's picture and data). Every file is
staged and renamed together (:class:`usvtool.atomic.staged`), ``index.html`` last; files of an
earlier report that this one no longer has are then removed from ``figures/`` and ``data/``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from usvtool.atomic import staged
from usvtool.errors import UsvError
from usvtool.report import claims, encounters, functions, methods, planning, preprocessing
from usvtool.report.data import load
from usvtool.report.document import Section
from usvtool.report.render import PdfUnavailable, html, pdf

TITLE = "usvtool: path planning and collision avoidance, compared with the papers"


@dataclass(frozen=True)
class ReportOptions:
    """``tables``: results tables (``usvtool batch``'s ``metrics.csv``); ``out``: the report's
    directory; ``pdf``: also write ``report.pdf``."""

    tables: tuple[str, ...]
    out: str = "build/report"
    pdf: bool = True


@dataclass
class ReportResult:
    out: Path
    sections: list[Section]
    html_bytes: int
    pdf_bytes: int | None
    pdf_pages: int | None
    hint: str | None = None
    verdicts: dict[str, int] = field(default_factory=dict)

    def summary(self) -> dict:
        return {
            "output": str(self.out / "index.html"),
            "pdf": None if self.pdf_bytes is None else str(self.out / "report.pdf"),
            "html_bytes": self.html_bytes,
            "pdf_bytes": self.pdf_bytes,
            "pdf_pages": self.pdf_pages,
            "sections": [s.id for s in self.sections],
            "figures": sum(len(s.figures()) for s in self.sections),
            "tables": sum(len(s.tables()) for s in self.sections),
            "claims": self.verdicts,
            "pdf_hint": self.hint,
        }


def sections(results) -> list[Section]:
    """The report's sections, in reading order (a section without data is left out)."""
    built = [claims.section(results), planning.section(results), functions.section(results),
             encounters.section(results), preprocessing.section(results),
             methods.section(results)]  # fmt: skip
    return [s for s in built if s is not None]


def make_report(options: ReportOptions) -> ReportResult:
    out = Path(options.out)
    if out.exists() and not out.is_dir():
        raise UsvError(f"-o {out}: is a file, not a directory")
    if not out.parent.is_dir():
        raise UsvError(f"-o {out}: directory {out.parent} does not exist")
    results = load(options.tables)
    parts = sections(results)
    subtitle = (f"{len(results.jobs)} jobs from {len(results.tables)} results table(s): "
                "every optimizer on every chart, every controller in every encounter, beside "
                "the published figures of the three papers.")  # fmt: skip
    page = html(TITLE, subtitle, parts)
    document, pages, hint = None, None, None
    if options.pdf:
        try:
            document, pages = pdf(page)
        except PdfUnavailable as e:
            hint = str(e)
    figures = [f for s in parts for f in s.figures()]
    files = {out / "index.html": page.encode("utf-8")}
    if document is not None:
        files[out / "report.pdf"] = document
    for f in figures:
        files[out / "figures" / f"{f.id}.png"] = f.png
        files[out / "data" / f"{f.id}.csv"] = f.data.encode("utf-8")
    for d in ("figures", "data"):
        (out / d).mkdir(parents=True, exist_ok=True)
    with staged(*files) as temporaries:
        for tmp, content in zip(temporaries, files.values(), strict=True):
            Path(tmp).write_bytes(content)
    for d in ("figures", "data"):
        for stale in set((out / d).iterdir()) - set(files):
            if stale.is_file() and not stale.name.startswith("."):
                stale.unlink()
    verdicts = claims.counts(parts)
    return ReportResult(out, parts, len(files[out / "index.html"]),
                        None if document is None else len(document), pages, hint,
                        verdicts)  # fmt: skip
