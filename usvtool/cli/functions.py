"""``usvtool functions``: the optimizers on the benchmark functions F1-F10 (IWSO paper, Table 1).

The paper's "population size ... 300, and the search agent ... 50" is read as 50 agents and 300
iterations, the setting its path-planning experiments state explicitly; hence ``--pop 50
--iters 300``. Results (stdout) and the table are the same whatever ``--jobs``.
"""

from __future__ import annotations

import csv
import sys

import click

from usvtool.cli.options import OutputPath, emit, seed_option
from usvtool.plan.benchmark_functions import FUNCTIONS
from usvtool.plan.optimizers import OPTIMIZERS


@click.command()
@click.option("--runs", type=click.IntRange(min=1), default=25, show_default=True, help="Runs.")
@click.option("--pop", type=click.IntRange(min=2), default=50, show_default=True, help="Agents.")
@click.option(
    "--iters", type=click.IntRange(min=1), default=300, show_default=True, help="Iterations."
)
@click.option("--dim", type=click.IntRange(min=1), default=30, show_default=True, help="Dimension.")
@click.option(
    "--algo",
    "algos",
    multiple=True,
    type=click.Choice(list(OPTIMIZERS)),
    help="Algorithm (repeatable; default all).",
)
@click.option(
    "--function",
    "function_names",
    multiple=True,
    type=click.Choice(list(FUNCTIONS), case_sensitive=False),
    metavar="F1..F10",
    help="Function (repeatable; default F1-F10).",
)
@seed_option
@click.option(
    "-j", "--jobs", type=click.IntRange(min=1), default=1, show_default=True, help="Processes."
)
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["json", "csv"]),
    default="json",
    show_default=True,
    help="Format of the results on stdout.",
)
@click.option(
    "--table",
    type=OutputPath(),
    help="Write the human-readable table here (default: stderr).",
)
def functions(
    runs: int,
    pop: int,
    iters: int,
    dim: int,
    algos: tuple[str, ...],
    function_names: tuple[str, ...],
    seed: int,
    jobs: int,
    fmt: str,
    table: str | None,
) -> None:
    """Best, worst, mean and std of the final cost of every algorithm on every function."""
    from usvtool.atomic import check_output_path
    from usvtool.plan.benchrun import BenchmarkOptions, run_benchmark

    table_path = check_output_path(table, "--table") if table else None
    options = BenchmarkOptions(
        algorithms=algos, functions=function_names, runs=runs, pop=pop, iters=iters, dim=dim,
        seed=seed, jobs=jobs,
    )
    result = run_benchmark(options)
    if table_path:
        result.write_table(table_path)
    else:
        click.echo(result.table(), err=True, nl=False)
    if fmt == "csv":
        rows = result.rows()
        writer = csv.DictWriter(sys.stdout, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    else:
        emit(result.summary())
