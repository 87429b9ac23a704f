"""``usvtool batch``: run a pipeline's jobs in a local pool, resumable (docs/batch.md)."""

from __future__ import annotations

import click

from usvtool.cli.options import emit


@click.command()
@click.argument("pipeline_path", metavar="PIPELINE.yaml", type=click.Path(dir_okay=False))
@click.option("-j", "--jobs", "workers", type=click.IntRange(min=1), default=None,
              help="Jobs run at once (default: the number of cores).")  # fmt: skip
@click.option("-o", "--output", "out_dir", type=click.Path(file_okay=False), default="build/batch",
              show_default=True, help="Directory of the results and metrics.csv.")  # fmt: skip
def batch(pipeline_path, workers, out_dir) -> None:
    """Run every job of PIPELINE.yaml (grids, routes, runs) locally; rerun to resume."""
    from usvtool.batch import BatchOptions, run_batch

    result = run_batch(pipeline_path, BatchOptions(workers, out_dir),
                       log=lambda text: click.echo(text, err=True))  # fmt: skip
    emit(result.summary())
    if result.failed:
        total = result.figures["jobs"]
        raise click.ClickException(f"{len(result.failed)} of {total} jobs failed")
