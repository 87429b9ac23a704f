"""``usvtool scene``: write one scene of a scene family as a scenario file (docs/families.md), or
list the families, their kinds and options."""

from __future__ import annotations

import click

from usvtool.cli.options import OutputPath, emit
from usvtool.cli.simulate import family_options, make_family_scene


@click.command()
@family_options
@click.option("-o", "--output", type=OutputPath(), metavar="FILE.yaml",
              help="The scenario file to write (the rasters it names beside it).")  # fmt: skip
@click.option(
    "--list",
    "listing",
    is_flag=True,
    help="Print the families, their kinds and options (JSON) and write nothing.",
)
def scene(family: str | None, kind: str | None, scene_number: int, family_options: dict,
          output: str | None, listing: bool) -> None:  # fmt: skip
    """Write scene --scene of --kind of --family to -o: the scenario ``usvtool simulate --family``
    runs. The summary JSON (the scene, its options, its draws) goes to stdout."""
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
