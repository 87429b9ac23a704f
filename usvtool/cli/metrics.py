"""``usvtool metrics``: the papers' metrics of routes and runs, one row each (docs/metrics.md)."""

from __future__ import annotations

from pathlib import Path

import click

from usvtool.cli.options import OutputPath, emit, summary_option, write_summary


@click.command()
@click.argument("inputs", metavar="INPUT...", nargs=-1, required=True, type=click.Path())
@click.option(
    "-o", "--output", type=OutputPath(),
    help="Table to write: CSV, or JSON when it ends in .json (default: CSV on stdout).",
)  # fmt: skip
@click.option(
    "--reference", "references", multiple=True, type=click.Path(dir_okay=False),
    metavar="ROUTE.geojson",
    help="The optimum (any-angle) route of the routes in its directory (repeatable); "
    "default: the input route of that directory planned by anyangle.",
)  # fmt: skip
@click.option(
    "--events", "events", multiple=True, type=click.Path(dir_okay=False), metavar="EVENTS.json",
    help="The events JSON of each trace, in the order of the traces (repeatable); default: "
    "<stem>.json, else <stem>.events.json, beside the trace.",
)  # fmt: skip
@click.option(
    "--reference-controller", metavar="NAME",
    help="Optimisation rates of the runs against this controller's run of the same scenario "
    "and seed.",
)  # fmt: skip
@summary_option
def metrics(inputs, output, references, events, reference_controller, summary_path) -> None:
    """One row of metrics per route (*.geojson) or run (*.csv trace with its events JSON).

    With -o the summary JSON goes to stdout (and to --summary); without it the CSV table does.
    """
    import sys

    from usvtool.atomic import check_outputs, staged
    from usvtool.metrics import MetricsOptions, measure

    if summary_path is not None and output is None:
        raise click.UsageError("--summary: give -o too (without it stdout has the table)")
    check_outputs([("-o", output), ("--summary", summary_path)])
    options = MetricsOptions(tuple(references), tuple(events), reference_controller)
    result = measure(inputs, options)
    if output is None:
        sys.stdout.write(result.to_csv())
        return
    as_json = Path(output).suffix.lower() == ".json"
    summary = {"output": output, "format": "json" if as_json else "csv", **result.summary()}
    with staged(output, summary_path) as (table_tmp, summary_tmp):  # the table renamed last
        table_tmp.write_text(result.to_json() if as_json else result.to_csv(), encoding="utf-8")
        if summary_tmp:
            write_summary(summary_tmp, summary)
    emit(summary)
