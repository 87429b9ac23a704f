"""``usvtool ais``: real traffic. ``read`` AIS files into tracks, find the ``encounters`` in them,
write one as a ``scenario`` (docs/ais.md)."""

from __future__ import annotations

import click

from usvtool.cli.options import (
    NON_NEGATIVE,
    POSITIVE,
    OutputDir,
    OutputPath,
    emit,
    max_memory_option,
    summary_option,
)


@click.group()
def ais() -> None:
    """Real traffic: AIS files into tracks, their encounters, scenarios from them."""


def _write_with_summary(output, summary_path, summary: dict, write) -> None:
    """``write(tmp)`` the output and the summary together (atomically), then print it."""
    from usvtool.atomic import check_outputs, staged
    from usvtool.cli.options import write_summary

    check_outputs([("-o", output), ("--summary", summary_path)])
    with staged(output, summary_path) as (out_tmp, summary_tmp):
        write(out_tmp)
        if summary_tmp:
            write_summary(summary_tmp, summary)
    emit(summary)


def _bbox(ctx, param, value):
    if value is None:
        return None
    try:
        box = tuple(float(v) for v in value.split(","))
    except ValueError:
        raise click.BadParameter(f"{value!r} is not LON_MIN,LAT_MIN,LON_MAX,LAT_MAX") from None
    if len(box) != 4:
        raise click.BadParameter(f"{value!r} is not LON_MIN,LAT_MIN,LON_MAX,LAT_MAX")
    return box


def _known(kind: str):
    """A callback refusing (usage error) a ``kind`` name usvtool simulate does not know: a
    vessel preset or a registered controller, listed."""

    def check(ctx, param, value):
        if kind == "vessel":
            from usvtool.sim.vessel import PRESETS as names
        else:
            from usvtool.sim.controllers import CONTROLLERS as names
        if value not in names:
            raise click.BadParameter(f"{value!r} is not a {kind} usvtool simulate knows "
                                     f"({', '.join(sorted(names))})")  # fmt: skip
        return value

    return check


@ais.command("read")
@click.argument("inputs", metavar="FILE...", nargs=-1, required=True,
                type=click.Path(dir_okay=False))  # fmt: skip
@click.option("-o", "--output", required=True, type=OutputPath(), metavar="TRACKS",
              help="The tracks table to write: .parquet or .csv (usvtool/tracks.py).")  # fmt: skip
@click.option("--columns", metavar="ROLE=NAME,...",
              help="Read every CSV as a generic one, with these columns (roles: mmsi, time, lat, "
              "lon, sog, cog, heading, length, beam, name, ship_type).")  # fmt: skip
@click.option("--max-gap", type=POSITIVE, default=600.0, show_default=True, metavar="S",
              help="A gap longer than this (seconds) between a vessel's fixes starts a new "
              "track.")  # fmt: skip
@click.option("--max-speed", type=POSITIVE, default=50.0, show_default=True, metavar="KN",
              help="A fix that implies more than this speed (knots) is dropped.")  # fmt: skip
@click.option("--bbox", callback=_bbox, metavar="LON_MIN,LAT_MIN,LON_MAX,LAT_MAX",
              help="Keep only the positions inside this box (degrees); a CSV is read block by "
              "block, holding only those.")  # fmt: skip
@max_memory_option
@summary_option
def read(inputs, output, columns, max_gap, max_speed, bbox, max_memory, summary_path) -> None:
    """Read AIS files (MarineCadastre, DMA, NMEA, any CSV; gzip, zstd or zip) into one tidy
    tracks table, cleaned (each rule counted in the summary on stdout)."""
    from usvtool.ais import CleanOptions, ReadOptions, read_ais
    from usvtool.ais.generic import parse_columns
    from usvtool.atomic import check_outputs
    from usvtool.tracks import check_suffix, write_tracks

    check_suffix(output, "-o")
    check_outputs([("-o", output), ("--summary", summary_path)])
    options = ReadOptions(parse_columns(columns), CleanOptions(max_gap, max_speed), bbox,
                          max_memory)  # fmt: skip
    result = read_ais(inputs, options)
    summary = {"output": output, **result.summary()}
    _write_with_summary(output, summary_path, summary, lambda tmp: write_tracks(tmp,
                                                                                result.tracks))


@ais.command("encounters")
@click.argument("tracks", metavar="TRACKS", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=OutputPath(), metavar="ENCOUNTERS.csv",
              help="The encounters CSV to write, ranked by CPA.")  # fmt: skip
@click.option("--cpa", type=POSITIVE, default=500.0, show_default=True, metavar="M",
              help="Pairs that come within this distance (metres).")  # fmt: skip
@click.option("--tcpa", type=POSITIVE, default=900.0, show_default=True, metavar="S",
              help="An encounter is detected when the CPA is within --cpa and this many seconds "
              "ahead.")  # fmt: skip
@click.option("--bbox", callback=_bbox, metavar="LON_MIN,LAT_MIN,LON_MAX,LAT_MAX",
              help="Search only the fixes inside this box (degrees).")  # fmt: skip
@click.option("--step", type=POSITIVE, default=10.0, show_default=True, metavar="S",
              help="The common time grid the tracks are interpolated on (seconds).")  # fmt: skip
@click.option("--min-speed", type=NON_NEGATIVE, default=1.0, show_default=True, metavar="KN",
              help="At the CPA one of the two makes at least this speed (knots).")  # fmt: skip
@max_memory_option
@summary_option
def encounters(tracks, output, cpa, tcpa, bbox, step, min_speed, max_memory,
               summary_path) -> None:  # fmt: skip
    """Every pair of vessels in TRACKS whose interpolated tracks come within --cpa: window,
    CPA, TCPA at first detection and the COLREGs class of each then."""
    from usvtool.ais.encounters import EncounterOptions, find_encounters
    from usvtool.ais.source import read_tracks_within
    from usvtool.atomic import check_outputs
    from usvtool.budget import default_budget

    check_outputs([("-o", output), ("--summary", summary_path)])
    options = EncounterOptions(cpa, tcpa, bbox, step, min_speed, max_memory)
    budget = default_budget() if max_memory is None else max_memory
    result = find_encounters(read_tracks_within(tracks, budget, "split it (usvtool ais read "
                                                "--bbox)"), options, tracks)  # fmt: skip
    summary = {"output": output, **result.summary()}
    _write_with_summary(output, summary_path, summary,
                        lambda tmp: tmp.write_text(result.to_csv(), encoding="utf-8"))  # fmt: skip


@ais.command("scenario")
@click.argument("tracks", metavar="TRACKS", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=OutputDir(), metavar="DIR",
              help="The directory to write scenario.yaml, route.geojson and the targets' "
              "tracks into (made if missing).")  # fmt: skip
@click.option("--own", type=int, metavar="MMSI",
              help="The vessel the USV replaces (default with --encounter: its first).")
@click.option("--start", metavar="TIME", help="The window's start (ISO 8601, UTC).")
@click.option("--end", metavar="TIME", help="The window's end (ISO 8601, UTC).")
@click.option("--encounter", type=click.IntRange(min=1), metavar="N",
              help="The window of encounter rank N of --encounters.")  # fmt: skip
@click.option("--encounters", "encounters_path", type=click.Path(dir_okay=False),
              metavar="ENCOUNTERS.csv", help="The encounters file of --encounter.")  # fmt: skip
@click.option("--pad", type=NON_NEGATIVE, default=60.0, show_default=True, metavar="S",
              help="Seconds added on each side of the encounter's window.")  # fmt: skip
@click.option("--radius", type=POSITIVE, default=2000.0, show_default=True, metavar="M",
              help="Vessels that come within this of the own ship are targets.")  # fmt: skip
@click.option("--map", "map_path", type=click.Path(dir_okay=False), metavar="GRID.tif",
              help="A navigation grid with a CRS: the scenario in lon/lat on it.")  # fmt: skip
@click.option("--vessel", default="udwa-usv", show_default=True, callback=_known("vessel"),
              help="The USV's vessel preset (usvtool simulate's).")  # fmt: skip
@click.option("--controller", default="udwa", show_default=True, callback=_known("controller"),
              help="The scenario's controller (usvtool simulate --controller runs another).")
@click.option("--duration", type=POSITIVE, metavar="S",
              help="The run's duration [default: twice the window].")  # fmt: skip
@summary_option
def scenario(tracks, output, own, start, end, encounter, encounters_path, pad, radius, map_path,
             vessel, controller, duration, summary_path) -> None:  # fmt: skip
    """A scenario YAML of a window of TRACKS: the own ship --own as the USV, every vessel within
    --radius of her as a replayed track."""
    from pathlib import Path

    from usvtool.ais.scenario import (
        ScenarioOptions,
        make_scenario,
        scenario_paths,
        write_scenario,
    )
    from usvtool.ais.source import read_tracks_within
    from usvtool.atomic import check_outputs
    from usvtool.budget import default_budget
    from usvtool.cli.options import summary_text

    check_outputs([("--summary", summary_path)])
    options = ScenarioOptions(own, start, end, encounter, encounters_path, radius, map_path,
                              vessel, controller, pad, duration)  # fmt: skip
    found = read_tracks_within(tracks, default_budget(), "cut it (usvtool ais read --bbox)")
    result = make_scenario(found, options, output)
    paths = scenario_paths(output, result)
    summary = {"output": str(Path(output) / "scenario.yaml"),
               "files": [str(p) for p in paths[1:]], **result.summary()}  # fmt: skip
    write_scenario(output, result, {summary_path: summary_text(summary)} if summary_path else {})
    emit(summary)
