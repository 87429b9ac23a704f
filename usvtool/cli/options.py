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


def output_option(help: str):
    return click.option("-o", "--output", required=True, type=click.Path(dir_okay=False), help=help)


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


POSITIVE = PositiveFloat()
NON_NEGATIVE = NonNegativeFloat()


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


def param_option(help: str):
    """``--param NAME=VALUE`` (repeatable) into a dict ``params``."""
    return click.option(
        "--param", "params", multiple=True, callback=_name_values, metavar="NAME=VALUE", help=help
    )


def emit(summary: dict) -> None:
    """Print the command's summary JSON on stdout."""
    json.dump(summary, sys.stdout, indent=2, default=jsonable)
    sys.stdout.write("\n")
