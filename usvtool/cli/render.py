"""``usvtool render``: draw an S-57 cell as an S-52 coloured chart GeoTIFF (and its land truth)."""

from __future__ import annotations

import click

from usvtool.cli.options import POSITIVE, OutputPath, emit, output_option


@click.command()
@click.argument("cell", type=click.Path(dir_okay=False))
@output_option("Chart GeoTIFF to write (RGB, UTM).")
@click.option(
    "--truth",
    type=OutputPath(),
    help="Also write the land truth GeoTIFF (1 land, 0 water, 255 outside coverage).",
)
@click.option("--resolution", type=POSITIVE, default=10.0, show_default=True, help="Metres/pixel.")
@click.option(
    "--shallow", type=POSITIVE, default=2.0, show_default=True, help="Shallow contour, m."
)
@click.option("--safety", type=POSITIVE, default=10.0, show_default=True, help="Safety contour, m.")
@click.option("--deep", type=POSITIVE, default=30.0, show_default=True, help="Deep contour, m.")
@click.option("--soundings/--no-soundings", default=True, show_default=True, help="Draw soundings.")
def render(
    cell: str,
    output: str,
    truth: str | None,
    resolution: float,
    shallow: float,
    safety: float,
    deep: float,
    soundings: bool,
) -> None:
    """Draw the S-57 CELL (.000, updates beside it applied) in the S-52 day colours."""
    from pathlib import Path

    from usvtool.atomic import check_outputs
    from usvtool.chart.rendering import RenderOptions
    from usvtool.chart.rendering import render as run

    if not shallow <= safety <= deep:
        raise click.UsageError(
            f"--shallow {shallow:g} --safety {safety:g} --deep {deep:g}: "
            "need shallow <= safety <= deep"
        )
    check_outputs([("-o", output), ("--truth", truth)])
    out, truth_path = Path(output), Path(truth) if truth else None
    options = RenderOptions(
        resolution=resolution, shallow=shallow, safety=safety, deep=deep, soundings=soundings
    )
    result = run(cell, options)
    result.write(out, truth_path)
    emit(result.summary())
