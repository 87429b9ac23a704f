"""``usvtool render``: draw an S-57 cell as an S-52 coloured chart GeoTIFF (and its land truth)."""

from __future__ import annotations

import time
from pathlib import Path

import click

from usvtool.cli.options import POSITIVE, emit, output_option


@click.command()
@click.argument("cell", type=click.Path(dir_okay=False))
@output_option("Chart GeoTIFF to write (RGB, UTM).")
@click.option(
    "--truth",
    type=click.Path(dir_okay=False),
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
    from usvtool.atomic import check_output_path, staged
    from usvtool.chart.render import TRUTH_LAND, TRUTH_NODATA, render_cell, write_chart, write_truth
    from usvtool.chart.s57 import read_cell, update_status

    if not shallow <= safety <= deep:
        raise click.UsageError(
            f"--shallow {shallow:g} --safety {safety:g} --deep {deep:g}: "
            "need shallow <= safety <= deep"
        )
    out = check_output_path(output, "-o")
    truth_path = check_output_path(truth, "--truth") if truth else None
    if truth_path and truth_path.resolve() == out.resolve():
        raise click.UsageError(f"--truth {truth}: same file as -o")

    start = time.perf_counter()
    status = update_status(cell)
    chart = read_cell(cell)
    read_s = time.perf_counter() - start
    rgb, land_truth, frame = render_cell(chart, resolution, shallow, safety, deep, soundings)
    render_s = time.perf_counter() - start - read_s
    tags = {
        "source": Path(cell).name,
        "edition": chart.edition,
        "update": chart.update,
        "resolution_m": resolution,
        "shallow_m": shallow,
        "safety_m": safety,
        "deep_m": deep,
    }
    with staged(out, truth_path) as (chart_tmp, truth_tmp):  # renamed together at the end
        write_chart(chart_tmp, rgb, frame, tags)
        if truth_tmp:
            write_truth(truth_tmp, land_truth, frame, tags)
    total_s = time.perf_counter() - start
    covered = land_truth != TRUTH_NODATA
    land_fraction = float((land_truth[covered] == TRUTH_LAND).mean()) if covered.any() else 0.0
    emit(
        {
            "cell": chart.name,
            **status,
            "output": str(out),
            "truth": str(truth_path) if truth_path else None,
            "width": frame.width,
            "height": frame.height,
            "resolution_m": resolution,
            "crs": frame.crs.to_string(),
            "land_fraction": round(land_fraction, 6),
            "soundings": soundings,
            "timings_s": {
                "read": round(read_s, 3),
                "render": round(render_s, 3),
                "write": round(total_s - read_s - render_s, 3),
                "total": round(total_s, 3),
            },
        }
    )
