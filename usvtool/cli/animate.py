"""``usvtool animate``: a run (trace CSV, events JSON, map) as a GIF, an MP4 or an HTML player.

Options, the drawing, the player and the formats: docs/animate.md.
"""

from __future__ import annotations

import re
from pathlib import Path

import click

from usvtool.cli.options import NON_NEGATIVE, POSITIVE, OutputPath, emit, summary_option

#: The format of each output suffix.
SUFFIXES = {".gif": "gif", ".mp4": "mp4", ".html": "html", ".htm": "html"}


class Size(click.ParamType):
    """``WxH``: two positive integers (pixels)."""

    name = "WxH"

    def convert(self, value, param, ctx):
        if isinstance(value, tuple):
            return value
        m = re.fullmatch(r"\s*(\d+)\s*[xX]\s*(\d+)\s*", str(value))
        if not m:
            self.fail(f"{value!r} is not WIDTHxHEIGHT (e.g. 800x600)", param, ctx)
        from usvtool.report.animation.build import MAX_SIDE, MIN_SIDE

        w, h = int(m.group(1)), int(m.group(2))
        if not (MIN_SIDE <= w <= MAX_SIDE and MIN_SIDE <= h <= MAX_SIDE):
            self.fail(f"{value!r}: each side {MIN_SIDE} to {MAX_SIDE} pixels", param, ctx)
        return w, h


@click.command()
@click.argument("trace", metavar="TRACE.csv", type=click.Path(dir_okay=False))
@click.option("--events", type=click.Path(dir_okay=False), metavar="EVENTS.json",
              help="The run's events JSON [default: TRACE.events.json, else TRACE.json, "
              "beside the trace].")  # fmt: skip
@click.option("--map", "map_path", type=click.Path(dir_okay=False), metavar="GRID.tif",
              help="A navigation grid GeoTIFF to draw beneath, in the trace's CRS [default: "
              "the run's map, if any].")  # fmt: skip
@click.option("-o", "--output", required=True, type=OutputPath(), metavar="OUT.gif|.mp4|.html",
              help="The animation; its suffix says the format.")  # fmt: skip
@click.option("--speed", type=POSITIVE, default=10.0, show_default=True,
              help="Times real time (a player's initial speed).")
@click.option("--size", type=Size(), default="800x600", show_default=True, metavar="WxH",
              help="Width x height in pixels (at a fixed dpi).")
@click.option("--wake", type=NON_NEGATIVE, default=60.0, show_default=True,
              help="Seconds of track drawn behind each ship.")
@click.option("--fps", type=click.IntRange(1, 60), default=10, show_default=True,
              help="Frames per second of a GIF or MP4.")
@click.option("--tolerance", type=POSITIVE, default=0.5, show_default=True,
              help="A player's decimation tolerance in metres: what it draws is within 1.15 "
              "times this of the trace (docs/animate.md).")
@summary_option
def animate(trace: str, events: str | None, map_path: str | None, output: str, speed: float,
            size: tuple[int, int], wake: float, fps: int, tolerance: float,
            summary_path: str | None) -> None:
    """Animate a run of usvtool simulate: TRACE.csv with its events JSON, over its map, as a
    GIF, an MP4 (ffmpeg) or a self-contained HTML player, written all at once or not at all.
    The summary JSON goes to stdout."""
    from usvtool.atomic import check_outputs, staged
    from usvtool.cli.options import write_summary
    from usvtool.report.animation import AnimateOptions
    from usvtool.report.animation import animate as make

    fmt = SUFFIXES.get(Path(output).suffix.lower())
    if fmt is None:
        raise click.BadParameter(f"{output}: the suffix says the format: "
                                 f"{', '.join(SUFFIXES)}", param_hint="'-o'")  # fmt: skip
    if fmt == "mp4" and (size[0] % 2 or size[1] % 2):
        raise click.BadParameter(f"{size[0]}x{size[1]}: an MP4's width and height must be even",
                                 param_hint="'--size'")  # fmt: skip
    check_outputs([("-o", output), ("--summary", summary_path)])
    options = AnimateOptions(trace, fmt, events, map_path, speed, size, wake, float(fps),
                             tolerance)  # fmt: skip
    result = make(options)
    summary = {"output": output, "trace": trace, **result.summary()}
    with staged(output, summary_path) as (out_tmp, summary_tmp):
        Path(out_tmp).write_bytes(result.content)
        if summary_tmp:
            write_summary(summary_tmp, summary)
    emit(summary)
