"""``usvtool batch``: run a pipeline's jobs on a local pool or a Dask cluster, resumable
(docs/batch.md, docs/cluster.md).

The engine (:mod:`usvtool.batch`) imports no stage; this module gives it what it needs from
them: :func:`run_command`, which its workers call to run one ``usvtool`` command line
in-process; :func:`stage_names`, the algorithms, controllers, scene families and functions the
stages know and the file options of the commands (:func:`file_options`), to check the pipeline
against before anything runs; and :func:`scenario_files`, the files a scenario names, for the
runs' keys. ``--make-fragment FILE`` writes the pipeline's Make fragment instead
(:mod:`usvtool.batch.make`) and runs nothing.
"""

from __future__ import annotations

import contextlib
import io
from functools import partial
from pathlib import Path

import click

from usvtool.cli.options import MEMORY_SIZE, OutputDir, OutputPath, emit, write_summary
from usvtool.pipeline import FamilySpec, FileOptions, Names


def run_command(args: list[str]) -> tuple[int, str, str]:
    """Run ``usvtool ARGS`` in this process: (exit status, stdout, stderr), as the console
    script would give them (a one-line ``Error: ...`` on stderr for a failure)."""
    from usvtool.cli import cli

    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        try:
            status = cli.main(args, prog_name="usvtool", standalone_mode=False) or 0
        except click.ClickException as exc:
            exc.show()
            status = exc.exit_code
        except click.Abort:
            click.echo("Aborted!", err=True)
            status = 1
    return status, stdout.getvalue(), stderr.getvalue()


def file_options(command: click.Command) -> FileOptions:
    """The long options of ``command`` that name a file (their type a ``click.Path``), as it
    declares them: those it writes (:class:`~usvtool.cli.options.OutputPath`), those it
    reads (any other)."""
    reads: set[str] = set()
    writes: set[str] = set()
    for param in command.params:
        if isinstance(param, click.Option) and isinstance(param.type, click.Path):
            long = {o[2:] for o in (*param.opts, *param.secondary_opts) if o.startswith("--")}
            (writes if isinstance(param.type, OutputPath) else reads).update(long)
    return FileOptions(frozenset(reads), frozenset(writes))


def stage_names() -> Names:
    """The optimizers, exact planners, controllers, benchmark functions and scene families of
    the stages, and the file options of the commands a pipeline gives options to."""
    from usvtool.cli.plan import plan
    from usvtool.cli.preprocess import preprocess
    from usvtool.params import check
    from usvtool.plan.benchmark_functions import FUNCTIONS
    from usvtool.plan.optimizers import OPTIMIZERS
    from usvtool.plan.planners import EXACT
    from usvtool.registry import BUILT_IN
    from usvtool.sim.controllers import CONTROLLERS
    from usvtool.sim.families import FAMILIES

    files = {"preprocess": file_options(preprocess), "plan": file_options(plan)}
    plugins = {name: " ".join(registry.origin(name)) for registry in (OPTIMIZERS, EXACT,
               CONTROLLERS, FAMILIES) for name in registry
               if registry.origin(name)[0] != BUILT_IN}  # fmt: skip
    families = {name: FamilySpec(cls.kinds, cls.seeded, cls().check_options,
                                 frozenset(k for k, o in cls.declarations().items() if o.file))
                for name, cls in FAMILIES.items()}  # fmt: skip
    variants = {name: tuple(cls.variants) for name, cls in EXACT.items()}
    controller_params = {name: partial(check, cls.declarations(), owner=name)
                         for name, cls in CONTROLLERS.items()}  # fmt: skip
    return Names(tuple(OPTIMIZERS), tuple(EXACT), tuple(CONTROLLERS), tuple(FUNCTIONS), files,
                 families, plugins, variants, controller_params)  # fmt: skip


def scenario_files(path: Path) -> list[Path]:
    """The files the scenario at ``path`` names, as :func:`usvtool.sim.scenario.read_scenario`
    resolves them: its map, route, targets' tracks and wind field (a :class:`UsvError` for a
    scenario that does not read)."""
    from usvtool.sim.scenario import read_scenario

    s = read_scenario(path)
    field = s.weather.field if s.weather is not None else None
    return [p for p in (s.map, s.route, *(t.track for t in s.targets), field) if p is not None]


@click.command()
@click.argument("pipeline_path", metavar="PIPELINE.yaml", type=click.Path(dir_okay=False))
@click.option("-j", "--jobs", "workers", type=click.IntRange(min=1), default=None,
              help="Local worker processes (default: the number of cores).")  # fmt: skip
@click.option("--scheduler", metavar="tcp://HOST:PORT",
              help="Run the jobs on this Dask scheduler's workers instead (usvtool[dask]).")
@click.option("-o", "--output", "out_dir", type=OutputDir(), default="build/batch",
              show_default=True, help="Directory of the results and metrics.csv.")  # fmt: skip
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True), metavar="SECONDS",
              help="Stop a job that runs longer than this and count it failed (it runs again "
              "on the next batch); local workers only.")  # fmt: skip
@click.option("--summary", "summary_path", type=OutputPath(), metavar="FILE.json",
              help="Also write the summary JSON printed on stdout to this file (atomically, "
              "once the tables are written; failed jobs too).")  # fmt: skip
@click.option("--max-memory", type=MEMORY_SIZE, metavar="SIZE",
              help="The memory budget of the jobs that run at once (4G, 512M, 2.5GiB or bytes): "
              "each job gets SIZE / workers as its --max-memory [default: half the machine's "
              "memory; with --scheduler, each job its own machine's default].")  # fmt: skip
@click.option("--make-fragment", "fragment_path", type=OutputPath(), metavar="FILE.mk",
              help="Write the pipeline's Make variables to this file (atomically) and run no "
              "job: pipelines/charts.mk includes it (docs/pipelines.md).")  # fmt: skip
@click.pass_context
def batch(ctx, pipeline_path, workers, scheduler, out_dir, timeout, summary_path, max_memory,
          fragment_path) -> None:  # fmt: skip
    """Run every job of PIPELINE.yaml (grids, routes, runs, function runs); rerun to resume."""
    from usvtool.atomic import check_output_path
    from usvtool.batch import BatchOptions, run_batch

    if fragment_path is not None:
        _make_fragment(ctx, pipeline_path, fragment_path)
        return
    if workers is not None and scheduler is not None:
        raise click.UsageError("-j: not with --scheduler (the cluster's workers run the jobs)")
    if timeout is not None and scheduler is not None:
        raise click.UsageError("--timeout: not with --scheduler (a running Dask task cannot be "
                               "stopped)")  # fmt: skip
    if summary_path is not None and Path(summary_path).parent.resolve() != Path(out_dir).resolve():
        check_output_path(summary_path, "--summary")  # (DIR itself is made by the batch)
    options = BatchOptions(run_command, stage_names(), workers, scheduler, out_dir,
                           timeout=timeout, scenario_files=scenario_files,
                           max_memory=max_memory)  # fmt: skip
    result = run_batch(pipeline_path, options)
    if summary_path is not None:
        write_summary(summary_path, result.summary())
    emit(result.summary())
    if result.failed:
        raise click.ClickException(f"{len(result.failed)} of {result.figures['jobs']} jobs failed")


def _make_fragment(ctx: click.Context, pipeline_path: str, fragment_path: str) -> None:
    """``--make-fragment``: the pipeline read with the stages' names, its fragment written."""
    from usvtool.atomic import check_output_path, write_text
    from usvtool.batch.make import fragment
    from usvtool.pipeline import load

    for name in ("workers", "scheduler", "out_dir", "timeout", "summary_path", "max_memory"):
        if ctx.get_parameter_source(name) is not click.core.ParameterSource.DEFAULT:
            option = next(p for p in ctx.command.params if p.name == name).opts[0]
            raise click.UsageError(f"{option}: not with --make-fragment (it runs no job)")
    check_output_path(fragment_path, "--make-fragment")
    write_text(fragment_path, fragment(load(pipeline_path, stage_names())))
