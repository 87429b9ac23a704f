"""``usvtool compare``: a regression report of a results table against a baseline
(docs/compare.md)."""

from __future__ import annotations

import logging

import click

from usvtool.cli.options import OutputDir, emit


@click.command()
@click.argument("baseline", metavar="BASELINE.csv", type=click.Path(dir_okay=False))
@click.argument("current", metavar="CURRENT.csv", type=click.Path(dir_okay=False))
@click.option("-o", "--output", "out_dir", type=OutputDir(),
              default="build/regression", show_default=True,
              help="Directory of index.html, regression.json and summary.md.")  # fmt: skip
@click.option("--tolerances", type=click.Path(dir_okay=False), metavar="FILE.yaml",
              help="Tolerances (default: BASELINE with the suffix .tolerances.yaml when it "
              "exists, else the built-in ones).")  # fmt: skip
def compare(baseline, current, out_dir, tolerances) -> None:
    """Compare CURRENT.csv with BASELINE.csv (results tables); exit 1 when a metric regressed,
    went missing or holds values that are not numbers where numbers are expected.

    The summary JSON goes to stdout, the Markdown summary (summary.md) to stderr too.
    """
    from usvtool.report.regression.compare import CompareOptions
    from usvtool.report.regression.compare import compare as run_compare

    result = run_compare(CompareOptions(baseline, current, tolerances, out_dir))
    if logging.getLogger("usvtool").isEnabledFor(logging.WARNING):  # not with -q
        click.echo(result.to_markdown(), err=True, nl=False)
    summary = result.summary()
    emit(summary)
    if result.status:
        failed = (
            f"{len(summary['regressed'])} regressed, {len(summary['missing'])} missing, "
            f"{len(summary['invalid'])} invalid"
        )
        raise click.ClickException(f"{failed} (see {out_dir}/summary.md)")
