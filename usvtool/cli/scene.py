"""``usvtool scene``: write one scene of a scene family as a scenario file (docs/families.md), or
list the families, their kinds and options; ``usvtool scene import`` / ``export``: the field's
scenario files (trafficgen JSON, colav-simulator YAML) in and out (docs/scenario.md)."""

from __future__ import annotations

import click

from usvtool.cli.options import OutputPath, emit
from usvtool.cli.simulate import family_options, make_family_scene


@click.group(invoke_without_command=True)
@family_options
@click.option("-o", "--output", type=OutputPath(), metavar="FILE.yaml",
              help="The scenario file to write (the rasters it names beside it).")  # fmt: skip
@click.option(
    "--list",
    "listing",
    is_flag=True,
    help="Print the families, their kinds and options (JSON) and write nothing.",
)
@click.pass_context
def scene(ctx: click.Context, family: str | None, kind: str | None, scene_number: int,
          family_options: dict, output: str | None, listing: bool) -> None:  # fmt: skip
    """Write scene --scene of --kind of --family to -o: the scenario ``usvtool simulate --family``
    runs. The summary JSON (the scene, its options, its draws) goes to stdout.

    ``usvtool scene import FILE -o SCENARIO.yaml`` and ``usvtool scene export SCENARIO.yaml -o
    FILE.json``: the field's scenario files in and out (docs/scenario.md)."""
    if ctx.invoked_subcommand is not None:
        if family or kind or scene_number or family_options or output or listing:
            raise click.UsageError(f"scene {ctx.invoked_subcommand}: the family options go "
                                   "without it")  # fmt: skip
        return
    from usvtool.atomic import check_outputs
    from usvtool.sim.families import FAMILIES, scene_files, write_scene

    if listing:
        if family or kind or scene_number or family_options or output:
            raise click.UsageError("--list: alone")
        emit({name: {"kinds": cls.about, "seeded": cls.seeded,
                     "options": {k: {"default": o.default, "help": o.help}
                                 for k, o in cls.declarations().items()}}
              for name, cls in FAMILIES.items()})  # fmt: skip
        return
    if family is None or output is None:
        raise click.UsageError("give --family, --kind and -o (or --list)")
    made = make_family_scene(family, kind, scene_number, family_options)
    check_outputs(("-o", p) for p in scene_files(made, output))
    files = write_scene(made, output)
    emit({"output": output, "files": [str(p) for p in files[1:]], **made.summary()})


def _latlon(value: str | None) -> tuple[float, float] | None:
    if value is None:
        return None
    try:
        lat, lon = (float(v) for v in value.split(","))
    except ValueError:
        raise click.BadParameter(f"LAT,LON in degrees, not {value!r}") from None
    if not (-90 <= lat <= 90 and -180 <= lon <= 180):
        raise click.BadParameter(f"LAT,LON in degrees, not {value!r}")
    return lat, lon


@scene.command("import")
@click.argument("source", metavar="FILE", type=click.Path(exists=True, dir_okay=False))
@click.option("-o", "--output", type=OutputPath(), metavar="SCENARIO.yaml", required=True,
              help="The usvtool scenario to write.")  # fmt: skip
@click.option("--vessel", default="udwa-usv", show_default=True,
              help="The own ship's vessel preset (the file's length, width and speed limits "
                   "are overrides of it).")  # fmt: skip
@click.option(
    "--controller", default="udwa", show_default=True, help="The scenario's controller field."
)
@click.option(
    "--origin",
    metavar="LAT,LON",
    default=None,
    help="trafficgen: the local projection's centre (default: the own ship's start).",
)
@click.option(
    "--length",
    type=click.FloatRange(min=0, min_open=True),
    default=None,
    help="A ship's length (m) where the file gives none.",
)
@click.option("--duration", type=click.FloatRange(min=0, min_open=True), default=None,
              help="sim.duration (s) where the file gives none (default: 1.5 times the own "
                   "ship's straight run to its goal).")  # fmt: skip
def import_(source: str, output: str, vessel: str, controller: str, origin: str | None,
            length: float | None, duration: float | None) -> None:  # fmt: skip
    """Turn a trafficgen situation (.json) or a colav-simulator scenario (.yaml) into a usvtool
    scenario: positions, courses, speeds, lengths and waypoints kept; a field not in the format's
    schema refused in one line; one the scenario has no place for named in its header comment
    and the summary's not_imported. The summary JSON goes to stdout."""
    from pathlib import Path

    from usvtool.atomic import check_outputs, staged
    from usvtool.sim.interchange import import_scene, scenario_text
    from usvtool.sim.scenario import parse

    scenario, header, dropped = import_scene(source, vessel=vessel, controller=controller,
                                             origin=_latlon(origin), length=length,
                                             duration=duration)  # fmt: skip
    parse(scenario, output)  # a scenario usvtool runs, or one line naming the field
    check_outputs([("-o", output)])
    with staged(output) as (tmp,):
        Path(tmp).write_text(scenario_text(scenario, header), encoding="utf-8")
    emit({"output": output, "source": source, "name": scenario["name"],
          "targets": len(scenario["targets"]), "not_imported": dropped})  # fmt: skip


@scene.command("export")
@click.argument("source", metavar="SCENARIO.yaml", type=click.Path(exists=True, dir_okay=False))
@click.option(
    "-o",
    "--output",
    type=OutputPath(),
    metavar="FILE.json",
    required=True,
    help="The trafficgen situation to write.",
)
@click.option(
    "--origin",
    metavar="LAT,LON",
    default="0,0",
    show_default=True,
    help="Where the map's (0, 0) lies: the local projection's centre.",
)
def export(source: str, output: str, origin: str) -> None:
    """Write the usvtool scenario as a trafficgen situation (JSON, maritime-schema 0.2.0): the
    own ship and the targets with their positions (lon/lat), courses, speeds (knots), lengths
    and waypoints. The summary JSON goes to stdout."""
    import json
    from pathlib import Path

    from usvtool.atomic import check_outputs, staged
    from usvtool.sim.interchange import export_trafficgen

    situation = export_trafficgen(source, _latlon(origin))
    check_outputs([("-o", output)])
    with staged(output) as (tmp,):
        Path(tmp).write_text(json.dumps(situation, indent=2) + "\n", encoding="utf-8")
    emit({"output": output, "source": source, "targets": len(situation["targetShips"])})
