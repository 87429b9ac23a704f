"""The ``usvtool`` command group.

Subcommands live one per module and are imported only when invoked, so ``usvtool --help`` and
quick commands do not pay for heavy imports. Library errors (:class:`usvtool.errors.UsvError`)
become one-line messages with exit status 1; usage errors exit 2 (click's convention). SIGINT
and SIGTERM give one line and exit 130 or 143, once the outputs being written are cleaned up.
"""

from __future__ import annotations

import atexit
import gc
import importlib
import logging
import os
import signal

import click

from usvtool import __version__
from usvtool.atomic import catch_signals
from usvtool.errors import UsvError, one_line

SUBCOMMANDS = {
    "preprocess": ("usvtool.cli.preprocess", "Turn a chart into a navigation grid GeoTIFF."),
    "render": ("usvtool.cli.render", "Draw an S-57 cell as an S-52 coloured chart image."),
    "plan": ("usvtool.cli.plan", "Plan a global route on a navigation grid."),
    "simulate": ("usvtool.cli.simulate", "Run an encounter scenario: trace, events, tracks."),
    "animate": ("usvtool.cli.animate", "Animate a run: GIF, MP4 or a self-contained HTML player."),
    "scene": ("usvtool.cli.scene", "Write one scene of a scene family as a scenario file."),
    "functions": ("usvtool.cli.functions", "Run the optimizers on benchmark functions F1-F10."),
    "metrics": ("usvtool.cli.metrics", "Tabulate the papers' metrics of routes and runs."),
    "report": ("usvtool.cli.report", "Write the comparison report (HTML and PDF) of results."),
    "batch": ("usvtool.cli.batch", "Run a pipeline's jobs in a local pool, resumable."),
    "compare": ("usvtool.cli.compare", "Regression report: a results table against a baseline."),
    "ais": ("usvtool.cli.ais", "Real traffic: AIS into tracks, encounters, scenarios."),
    "plugins": ("usvtool.cli.plugins", "Every method, built in or plugged in: its parameters."),
}


class LazyGroup(click.Group):
    """A group whose subcommands are imported on first use."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(SUBCOMMANDS)

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        if name not in SUBCOMMANDS:
            return None
        from usvtool.cli.guard import guarded

        module = importlib.import_module(SUBCOMMANDS[name][0])
        return guarded(getattr(module, name))

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        rows = [(name, SUBCOMMANDS[name][1]) for name in self.list_commands(ctx)]
        with formatter.section("Commands"):
            formatter.write_dl(rows)

    def invoke(self, ctx: click.Context):
        try:
            with catch_signals():  # SIGTERM too becomes an exception: outputs are cleaned up
                return super().invoke(ctx)
        except KeyboardInterrupt as exc:  # 128 + signal number, the shell's convention
            signum = getattr(exc, "signum", signal.SIGINT)
            click.echo(f"Error: interrupted by {signal.Signals(signum).name}", err=True)
            raise click.exceptions.Exit(128 + signum) from None
        except UsvError as exc:
            raise click.ClickException(one_line(str(exc))) from None
        except (click.ClickException, click.exceptions.Exit, click.Abort):
            raise
        except OSError as exc:  # a file the OS refused (disk full, permission): named
            if ctx.obj and ctx.obj.get("verbose", 0) > 0:
                raise
            where = exc.filename if exc.filename is not None else type(exc).__name__
            raise click.ClickException(one_line(f"{where}: {exc.strerror or exc}")) from None
        except MemoryError:  # past the stages' guards (usvtool.budget.allocating): one line
            raise click.ClickException(
                f"out of memory while running usvtool {ctx.invoked_subcommand}; lower its "
                "inputs' sizes or --max-memory"
            ) from None
        except Exception as exc:  # a bug: one line unless -v asks for the traceback
            if ctx.obj and ctx.obj.get("verbose", 0) > 0:
                raise
            raise click.ClickException(one_line(
                f"internal error: {type(exc).__name__}: {exc} (run with -v for the traceback)"
            )) from None  # fmt: skip


@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.option("-v", "--verbose", count=True, help="More messages on stderr (tracebacks too).")
@click.option("-q", "--quiet", count=True, help="Fewer messages on stderr.")
@click.version_option(__version__, prog_name="usvtool")
@click.pass_context
def cli(ctx: click.Context, verbose: int, quiet: int) -> None:
    """USV path planning on real nautical charts.

    Every command prints one JSON summary on stdout; messages go to stderr.
    """
    _log_to_stderr(max(logging.DEBUG, logging.WARNING - 10 * (verbose - quiet)))
    ctx.obj = {"verbose": verbose}


def _log_to_stderr(level: int) -> None:
    """The ``usvtool`` logger's records at ``level`` and above as ``usvtool: message`` lines."""
    logger = logging.getLogger("usvtool")
    logger.handlers[:] = [_StderrHandler()]
    logger.setLevel(level)
    logger.propagate = False


class _StderrHandler(logging.Handler):
    """Log records as ``usvtool: message`` lines on the current stderr (click's, so that test
    runners that swap the stream see them)."""

    def emit(self, record: logging.LogRecord) -> None:
        click.echo(f"usvtool: {record.getMessage()}", err=True)


# from the start: click imports a subcommand's module (whose registries may name a plugin they
# cannot use) before the group's options set the level
_log_to_stderr(logging.WARNING)


def main() -> None:
    """The console script. At exit the objects left are frozen, not collected: the interpreter's
    last collections over numba's compiled kernels took 0.25-0.35 s of every ``usvtool simulate``
    (docs/simulate.md, "Start-up"); the system frees the memory all the same.

    BLAS runs on one thread unless ``OPENBLAS_NUM_THREADS`` says otherwise (set before NumPy
    loads it; a batch's workers inherit it): a process holds three OpenBLAS copies (NumPy's,
    SciPy's, OpenCV's), each with a thread per further core that spins after every call, and
    usvtool's products are small. Those threads took a quarter of the CPU of a ``usvtool
    simulate`` (1.1 s against 0.8) and of a ``usvtool plan``, from the other processes on the
    machine, and gained nothing, not even on an 11 000-pixel chart's preprocessing."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    atexit.register(gc.freeze)
    cli(prog_name="usvtool")
