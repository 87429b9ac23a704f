"""``usvtool preprocess``: a chart to a navigation grid GeoTIFF (+ preview PNG)."""

from __future__ import annotations

import logging

import click

from usvtool.cli.options import (
    NON_NEGATIVE,
    POSITIVE,
    OutputPath,
    emit,
    max_memory_option,
    output_option,
    seed_option,
    summary_option,
    write_summary,
)

log = logging.getLogger(__name__)


class Colour(click.ParamType):
    name = "R,G,B"

    def convert(self, value, param, ctx):
        try:
            rgb = tuple(int(v) for v in str(value).split(","))
        except ValueError:
            rgb = ()
        if len(rgb) != 3 or not all(0 <= v <= 255 for v in rgb):
            self.fail(f"{value!r} is not R,G,B with values 0..255", param, ctx)
        return rgb


@click.command()
@click.argument("chart", type=click.Path(dir_okay=False))
@output_option("Output grid GeoTIFF.")
@click.option("--preview", type=OutputPath(), help="Also write a preview PNG.")
@click.option("--preview-resolution", type=POSITIVE, metavar="METRES",
              help="Metres per preview pixel [default: longest side 1200 pixels; an S-57 "
              "cell's background drawn at half a cell, or coarser to match].")
@click.option("--ship-length", type=POSITIVE, default=2.5, show_default=True,
              help="Ship length in metres (cell = 1.5 x ship length).")
@click.option("--cell-size", type=POSITIVE, help="Cell size in metres (overrides the rule).")
@click.option("--margin", type=POSITIVE,
              help="Safety margin in metres around obstacles [default: 0.5 cell].")
@click.option("--swell/--no-swell", default=True, show_default=True,
              help="Swell obstacles by the margin (--no-swell: use the grid as drawn).")
@click.option("--resolution", type=POSITIVE,
              help="Metres per pixel of a plain chart image (refused for a georeferenced one).")
@click.option("--cutline", type=click.Path(dir_okay=False), metavar="FILE.geojson",
              help="Polygon (lon/lat) of a raster chart's area: pixels outside it are outside the "
              "chart (a KAP: also outside its own cutline).")
@click.option("--bounds", type=float, nargs=4, metavar="L B R T",
              help="Extent of a GeoJSON obstacle map (default: its bbox or its obstacles').")
@click.option("--clusters", type=click.IntRange(2, 32), default=8, show_default=True,
              help="Fuzzy C-means clusters of chart colours.")
@click.option("--land-colour", "land_colours", type=Colour(), multiple=True,
              help="A land colour of this chart (repeatable).")
@click.option("--channel", type=click.Choice(["membership", "chromatic", "grey"]),
              default="membership", show_default=True, help="What Otsu binarises.")
@click.option("--threshold", type=click.FloatRange(0, 255),
              help="Fixed threshold 0..255 instead of Otsu's (the paper: 100).")
@click.option("--min-area", type=click.IntRange(1), default=16, show_default=True,
              help="Land specks and water holes smaller than this many pixels are clutter.")
@click.option("--ink", type=click.Choice(["auto", "auto+bridges", "clutter", "obstacle"]),
              default="auto", show_default=True,
              help="Ink in water: auto (by shape: solid and ring symbols, thick strokes from the "
              "shore, free dark bars and dock networks are hazards; text and lines, and lines "
              "and bridges crossing water, are clutter), auto+bridges (dark ink crossing water "
              "blocks), clutter (all becomes water) or obstacle (all blocks).")
@click.option("--occupancy", type=click.FloatRange(0, 1, max_open=True), default=0.0,
              show_default=True, help="Obstacle share of a cell above which it blocks.")
@click.option("--min-depth", type=float,
              help="S-57: depth areas shallower than this (m) are obstacles "
              "[default: 1.2 = 0.6 m draft + 0.5 m under-keel clearance + 0.1 m].")
@click.option("--hazard-radius", type=NON_NEGATIVE,
              help="S-57: buffer (m) around rocks, wrecks and obstructions [default: 10].")
@seed_option
@max_memory_option
@summary_option
def preprocess(chart, output, preview, ship_length, cell_size, margin, swell, resolution, bounds,
               clusters, land_colours, channel, threshold, min_area, occupancy, min_depth,
               hazard_radius, seed, preview_resolution, ink, cutline, max_memory, summary_path):
    """Turn CHART (image, GeoTIFF, BSB/KAP, S-57 cell or GeoJSON) into a navigation grid.

    Fuzzy C-means colour clustering, Otsu binarisation, clutter removal, gridding at
    1.5 x ship length and obstacle swelling, as in the ISSA paper (section 3).
    """
    from usvtool.atomic import check_outputs, staged
    from usvtool.chart.preprocessing import PreprocessOptions
    from usvtool.chart.preprocessing import preprocess as run
    from usvtool.chart.sources import chart_kind
    from usvtool.grid import write_grid

    check_outputs([("-o", output), ("--preview", preview), ("--summary", summary_path)])
    if not preview and preview_resolution is not None:
        raise click.UsageError("--preview-resolution: give --preview too")
    opts = PreprocessOptions(
        ship_length=ship_length, cell_size=cell_size, margin=margin, swell=swell,
        resolution=resolution, cutline=cutline,
        bounds=tuple(bounds) if bounds else None, clusters=clusters,
        land_colours=list(land_colours), channel=channel, threshold=threshold,
        min_area=min_area, ink=ink, occupancy=occupancy, min_depth=min_depth,
        hazard_radius=hazard_radius, seed=seed, max_memory=max_memory,
    )
    if preview and chart_kind(chart) == "s57":
        from usvtool.chart.preview import check_s57_preview

        check_s57_preview(chart, opts.cell, preview_resolution)  # fail before the grid work
    result = run(chart, opts)
    summary = {**result.summary(), "output": output}
    if preview:
        from usvtool.chart.preview import (
            background_resolution,
            render_preview,
            s57_background,
            write_png,
        )

        background = result.chart
        if background is None and summary["source_kind"] == "s57":
            px = preview_resolution or background_resolution(result.grid.bounds, opts.cell)
            background = s57_background(chart, px)
        image = render_preview(result.grid, background, preview_resolution)  # before any file
        summary["preview"] = preview
    with staged(output, preview, summary_path) as (grid_tmp, preview_tmp, summary_tmp):
        write_grid(grid_tmp, result.grid)  # all renamed together at the end, the grid last
        if preview_tmp:
            write_png(preview_tmp, image)
        if summary_tmp:
            write_summary(summary_tmp, summary)
    log.info("%s: %d x %d cells of %g m", output, result.grid.width, result.grid.height,
             result.grid.cell_size)
    emit(summary)
