"""``usvtool report``: the comparison report (HTML and PDF) of results tables (docs/report.md)."""

from __future__ import annotations

import click

from usvtool.cli.options import OutputDir, emit, summary_option, write_summary


@click.command()
@click.argument("tables", metavar="RESULTS.csv...", nargs=-1, required=True,
                type=click.Path(dir_okay=False))
@click.option("-o", "--output", default="build/report", show_default=True,
              type=OutputDir(), metavar="DIR",
              help="Directory of index.html, report.pdf, figures/ and data/.")  # fmt: skip
@click.option("--pdf/--no-pdf", default=True, show_default=True,
              help="Also write report.pdf (WeasyPrint).")  # fmt: skip
@click.option("--allow-missing", is_flag=True,
              help="Report without the job folders that are missing (the methods section "
                   "lists them) rather than refuse.")  # fmt: skip
@summary_option
def report(tables, output, pdf, allow_missing, summary_path) -> None:
    """The comparison report of results tables (usvtool batch's metrics.csv and the job files
    beside it): index.html, self-contained, and report.pdf from the same templates.

    Without WeasyPrint's system libraries the HTML is still written and one line on stderr
    says what to install. Every job folder the tables point to must be there, its files the
    ones its job.json records.
    """
    from usvtool.atomic import check_outputs
    from usvtool.report.build import ReportOptions, make_report

    check_outputs([("--summary", summary_path)])
    result = make_report(ReportOptions(tuple(tables), output, pdf, order=stage_methods(),
                                       allow_missing=allow_missing))  # fmt: skip
    summary = result.summary()
    if result.hint:
        click.echo(f"Warning: {result.hint}", err=True)
    if result.missing:
        click.echo(f"Warning: {len(result.missing)} job folders missing (--allow-missing): the "
                   "report is without their files; its methods section lists them", err=True)
    if summary_path:
        write_summary(summary_path, summary)
    emit(summary)
    click.echo(summary_line(summary), err=True)


def summary_line(summary: dict) -> str:
    """The one line ``make report`` and ``usvtool report`` end with (from the summary JSON):
    where the report is and its size (the HTML with its figures inline; the PDF), the PDF's
    pages (main body and in all) and how many of the papers' claims get each verdict,
    then, when the pipelines declared any, the user's claims' (kept apart).

    >>> summary_line({"output": "build/report/index.html", "pdf": "build/report/report.pdf",
    ...               "pdf_pages": 41, "main_pages": 28, "pdf_hint": None,
    ...               "html_bytes": 12_345_678, "pdf_bytes": 2_100_000,
    ...               "claims": {"holds": 3, "does not hold": 1, "not tested": 0}})
    'report: build/report/index.html (12.3 MB) and build/report/report.pdf (2.1 MB), 28 pages \
of main body, 41 in all; claims: 3 holds, 1 does not hold, 0 not tested'
    >>> summary_line({"output": "r/index.html", "pdf": None, "pdf_hint": None,
    ...               "claims": {"holds": 3}, "your_claims": {"holds": 1, "inconclusive": 1}})
    'report: r/index.html, no PDF (--no-pdf); claims: 3 holds; your claims: 1 holds, 1 \
inconclusive'
    """
    html = _size(summary.get("html_bytes"))
    if summary.get("pdf"):
        where = (f"{summary['output']}{html} and {summary['pdf']}{_size(summary.get('pdf_bytes'))}"
                 f", {summary['main_pages']} pages of main body, {summary['pdf_pages']} in all")
    else:
        why = "WeasyPrint cannot run: pdf_hint" if summary.get("pdf_hint") else "--no-pdf"
        where = f"{summary['output']}{html}, no PDF ({why})"
    claims = ", ".join(f"{n} {verdict}" for verdict, n in summary["claims"].items())
    line = f"report: {where}; claims: {claims or 'none'}"
    yours = summary.get("your_claims") or {}
    if any(yours.values()):
        line += "; your claims: " + ", ".join(f"{n} {verdict}" for verdict, n in yours.items())
    return line


def _size(n: int | None) -> str:
    """`` (12.3 MB)`` of ``n`` bytes; '' when unknown.

    >>> _size(12_345_678), _size(5_400), _size(None)
    (' (12.3 MB)', ' (5.4 kB)', '')
    """
    if n is None:
        return ""
    return f" ({n / 1e6:.1f} MB)" if n >= 1e6 else f" ({n / 1e3:.1f} kB)"


def stage_methods() -> tuple[str, ...]:
    """The methods the stages' registries know, in the order the report shows them: the
    planners (:func:`usvtool.plan.planners.names`), then the controllers."""
    from usvtool.plan.planners import names
    from usvtool.sim.controllers import CONTROLLERS

    return (*names(), *CONTROLLERS)
