"""Shared click options and output helpers for the subcommands."""

from __future__ import annotations

import json
import math
import sys

import click

from usvtool.atomic import jsonable

seed_option = click.option(
    "--seed", type=int, default=0, show_default=True, help="Seed of the random generator."
)


class OutputPath(click.Path):
    """A file the command writes (a file option of any other ``click.Path`` type is one it
    reads): ``usvtool batch`` refuses such an option in a pipeline, as it names a job's
    outputs itself (:func:`usvtool.cli.batch.file_options`)."""

    def __init__(self) -> None:
        super().__init__(dir_okay=False)


class OutputDir(click.Path):
    """A folder the command writes into (made if missing)."""

    def __init__(self) -> None:
        super().__init__(file_okay=False)


def output_option(help: str):
    return click.option("-o", "--output", required=True, type=OutputPath(), help=help)


class PositiveFloat(click.ParamType):
    """A finite float > 0 (rejects zero, negatives, NaN and infinity)."""

    name = "positive number"

    def convert(self, value, param, ctx):
        try:
            x = float(value)
        except (TypeError, ValueError):
            self.fail(f"{value!r} is not a number", param, ctx)
        if not math.isfinite(x) or x <= 0:
            self.fail(f"{value!r} must be a finite number > 0", param, ctx)
        return x


class NonNegativeFloat(click.ParamType):
    """A finite float >= 0."""

    name = "number >= 0"

    def convert(self, value, param, ctx):
        try:
            x = float(value)
        except (TypeError, ValueError):
            self.fail(f"{value!r} is not a number", param, ctx)
        if not math.isfinite(x) or x < 0:
            self.fail(f"{value!r} must be a finite number >= 0", param, ctx)
        return x


class MemorySize(click.ParamType):
    """A size in bytes: ``4G``, ``512M``, ``2.5GiB`` or plain bytes
    (:func:`usvtool.budget.parse_size`)."""

    name = "size"

    def convert(self, value, param, ctx):
        from usvtool.budget import parse_size

        try:
            return parse_size(value)
        except ValueError as exc:
            self.fail(str(exc), param, ctx)


POSITIVE = PositiveFloat()
NON_NEGATIVE = NonNegativeFloat()
MEMORY_SIZE = MemorySize()


def max_memory_option(f):
    """``--max-memory SIZE``: the memory budget a job's estimated need must stay within."""
    return click.option(
        "--max-memory", type=MEMORY_SIZE, metavar="SIZE",
        help="Refuse a job whose estimated memory exceeds SIZE (4G, 512M, 2.5GiB or bytes) "
        "before allocating [default: half the machine's memory].",
    )(f)  # fmt: skip


def _name_values(ctx, param, values: tuple[str, ...]) -> dict:
    """``NAME=VALUE`` pairs, each value a JSON number, ``true``, ``false`` or ``null``, else the
    text itself."""
    params = {}
    for item in values:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise click.BadParameter(f"{item!r} is not NAME=VALUE")
        if not text.strip():
            raise click.BadParameter(f"{item!r} has no value (write {name}=null for none)")
        try:
            value = json.loads(text)
        except ValueError:
            value = text
        if isinstance(value, list | dict):
            raise click.BadParameter(
                f"{item!r}: the value must be a number, true, false, null or a string"
            )
        params[name] = value
    return params


def param_option(help: str, flag: str = "--param", dest: str = "params"):
    """``--param NAME=VALUE`` (repeatable; or ``flag``) into a dict ``params`` (or ``dest``)."""
    return click.option(
        flag, dest, multiple=True, callback=_name_values, metavar="NAME=VALUE", help=help
    )


def summary_option(f):
    """``--summary FILE``: also write the summary JSON to FILE (atomically, with the outputs)."""
    return click.option(
        "--summary", "summary_path", type=OutputPath(), metavar="FILE.json",
        help="Also write the summary JSON printed on stdout to this file (atomically, together "
        "with the outputs: none is written when the command fails).",
    )(f)  # fmt: skip


def summary_text(summary: dict) -> str:
    """The summary JSON as :func:`emit` prints it (and ``--summary`` writes it)."""
    return json.dumps(summary, indent=2, default=jsonable) + "\n"


def write_summary(path, summary: dict) -> None:
    """Write the summary JSON to ``path`` (a staged temporary, or atomically by itself)."""
    from usvtool.atomic import write_text

    write_text(path, summary_text(summary))


def emit(summary: dict) -> None:
    """Print the command's summary JSON on stdout."""
    sys.stdout.write(summary_text(summary))
