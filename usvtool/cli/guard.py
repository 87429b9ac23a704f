"""What every command gets checked before it runs, from its own parameters' types: an output
(:class:`~usvtool.cli.options.OutputPath`, :class:`~usvtool.cli.options.OutputDir`) that is one
of its inputs (any other ``click.Path``) is refused, and an ``OSError`` that names no file (a
damaged archive, a device's refusal) is one line naming the command's files."""

from __future__ import annotations

import functools
import os
import stat
from collections.abc import Callable

import click

from usvtool.cli.options import OutputDir, OutputPath
from usvtool.errors import UsvError

Files = list[tuple[str, str]]  # (option or argument, path)


def guarded(command: click.Command) -> click.Command:
    """``command`` (each subcommand of a group) with its callback checked by :func:`_checked`;
    idempotent."""
    if isinstance(command, click.Group):
        for sub in command.commands.values():
            guarded(sub)
    elif command.callback is not None and not getattr(command.callback, "guarded", False):
        command.callback = _checked(command.callback)
    return command


def files(ctx: click.Context) -> tuple[Files, Files]:
    """The (outputs, inputs) the command was given, by their parameters' types."""
    outputs: Files = []
    inputs: Files = []
    for param in ctx.command.params:
        value = ctx.params.get(param.name) if isinstance(param.type, click.Path) else None
        for path in value if isinstance(value, tuple | list) else (value,):
            if path is not None:
                role = outputs if isinstance(param.type, OutputPath | OutputDir) else inputs
                role.append((_label(param), os.fspath(path)))
    return outputs, inputs


def refuse_inputs_as_outputs(outputs: Files, inputs: Files) -> None:
    """Refuse (one line) the first output that is one of the inputs (the same file or folder,
    through any link): writing it would replace what is being read."""
    for out_label, out in outputs:
        for in_label, given in inputs:
            if _same(out, given):
                raise UsvError(f"{out_label} {out}: the same file as the input {in_label} "
                               f"{given}; write the output elsewhere")  # fmt: skip


def _checked(callback: Callable) -> Callable:
    @functools.wraps(callback)
    def run(*args, **kwargs):
        outputs, inputs = files(click.get_current_context())
        refuse_inputs_as_outputs(outputs, inputs)
        try:
            return callback(*args, **kwargs)
        except OSError as exc:
            named = [path for _, path in inputs or outputs]
            if exc.filename is not None or not named:
                raise
            raise UsvError(f"{', '.join(named)}: {exc.strerror or exc}") from None

    run.guarded = True
    return run


def _label(param: click.Parameter) -> str:
    if isinstance(param, click.Option):
        return param.opts[0]
    return param.human_readable_name.strip("[].")


def _same(a: str, b: str) -> bool:
    """Both exist, ``a`` is a regular file or a folder (a device or a pipe is written in
    place, and reading one is not spoilt by writing another end), and they are one."""
    try:
        mode = os.stat(a).st_mode
        return (stat.S_ISREG(mode) or stat.S_ISDIR(mode)) and os.path.samefile(a, b)
    except (OSError, ValueError):
        return False
