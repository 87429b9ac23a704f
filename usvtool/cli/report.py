"""``usvtool report``: the comparison report (HTML and PDF) of results tables (docs/report.md)."""

from __future__ import annotations

import click

from usvtool.cli.options import emit, summary_option, write_summary


@click.command()
@click.argument("tables", metavar="RESULTS.csv...", nargs=-1, required=True)
@click.option("-o", "--output", default="build/report", show_default=True,
              type=click.Path(file_okay=False), metavar="DIR",
              help="Directory of index.html, report.pdf, figures/ and data/.")  # fmt: skip
@click.option("--pdf/--no-pdf", default=True, show_default=True,
              help="Also write report.pdf (WeasyPrint).")  # fmt: skip
@summary_option
def report(tables, output, pdf, summary_path) -> None:
    """The comparison report of results tables (usvtool batch's metrics.csv and the job files
    beside it): index.html, self-contained, and report.pdf from the same templates.

    Without WeasyPrint's system libraries the HTML is still written and one line on stderr
    says what to install.
    """
    from usvtool.atomic import check_outputs
    from usvtool.report.build import ReportOptions, make_report

    check_outputs([("--summary", summary_path)])
    result = make_report(ReportOptions(tuple(tables), output, pdf, order=stage_methods()))
    summary = result.summary()
    if result.hint:
        click.echo(f"Warning: {result.hint}", err=True)
    if summary_path:
        write_summary(summary_path, summary)
    emit(summary)


def stage_methods() -> tuple[str, ...]:
    """The methods the stages' registries know, in the order the report shows them: the
    planners (:func:`usvtool.plan.planners.names`), then the controllers."""
    from usvtool.plan.planners import names
    from usvtool.sim.controllers import CONTROLLERS

    return (*names(), *CONTROLLERS)
