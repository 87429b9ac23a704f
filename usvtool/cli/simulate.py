"""``usvtool simulate``: run a scenario and write its trace CSV (+ events JSON, tracks GeoJSON).

The scenario's schema is docs/scenario.md, the outputs and the summary docs/simulate.md. With
``--family`` the scenario is a scene of a scene family (docs/families.md), written first to
``--scenario-out`` (with the rasters it names beside it) and run from there.
"""

from __future__ import annotations

import logging
from pathlib import Path

import click

from usvtool.cli.options import (
    OutputPath,
    emit,
    max_memory_option,
    output_option,
    param_option,
    seed_option,
    summary_option,
    write_summary,
)
from usvtool.sim.controllers import CONTROLLERS

log = logging.getLogger(__name__)


class FamilyChoice(click.Choice):
    """The scene families' names, their registry imported when first asked for (it brings the
    families' raster writers, which a scenario file's run does not need)."""

    def __init__(self) -> None:
        self.case_sensitive = True

    @property
    def choices(self) -> tuple[str, ...]:
        from usvtool.sim.families import FAMILIES

        return tuple(FAMILIES)


def family_options(f):
    """``--family``, ``--kind``, ``--scene`` and ``--family-option``: one scene of a family."""
    f = param_option("An option of the family (repeatable; usvtool scene --list names them).",
                     "--family-option", "family_options")(f)  # fmt: skip
    f = click.option("--scene", "scene_number", type=click.IntRange(min=0), default=0,
                     show_default=True, help="The scene's seed (a family that is not seeded "
                     "has only scene 0).")(f)  # fmt: skip
    f = click.option("--kind", help="The kind of scene (usvtool scene --list names them).")(f)
    return click.option("--family", type=FamilyChoice(),
                        help="A scene family (docs/families.md).")(f)  # fmt: skip


def make_family_scene(family: str | None, kind: str | None, scene: int, options: dict):
    """The scene the family options name (:func:`usvtool.sim.families.make_scene`); None without
    ``--family``. Usage errors for options given without it or ``--kind`` missing."""
    if family is None:
        given = [o for o, v in (("--kind", kind), ("--family-option", options)) if v]
        if given or scene:
            raise click.UsageError(f"{(given or ['--scene'])[0]}: only with --family")
        return None
    if kind is None:
        raise click.UsageError("--family: needs --kind")
    from usvtool.sim.families import make_scene

    return make_scene(family, kind, scene, options, lambda key: f"--family-option {key}")


@click.command()
@click.argument("scenario_path", metavar="[SCENARIO.yaml]", required=False,
                type=click.Path(dir_okay=False))  # fmt: skip
@family_options
@click.option(
    "--scenario-out",
    type=OutputPath(),
    metavar="FILE.yaml",
    help="With --family: where to write the scene (its rasters beside it) that runs.",
)
@click.option(
    "--controller",
    type=click.Choice(list(CONTROLLERS)),
    help="The controller to run instead of the scenario's (its parameters are then dropped).",
)
@param_option("A controller parameter (repeatable), over the scenario's.")
@seed_option
@output_option("Trace CSV to write.")
@click.option("--events", type=OutputPath(), help="Also write the events JSON.")
@click.option("--tracks", type=OutputPath(), help="Also write the tracks GeoJSON.")
@max_memory_option
@summary_option
def simulate(scenario_path: str | None, family: str | None, kind: str | None, scene_number: int,
             family_options: dict, scenario_out: str | None, controller: str | None,
             params: dict, seed: int, output: str, events: str | None, tracks: str | None,
             max_memory: int | None, summary_path: str | None) -> None:  # fmt: skip
    """Run SCENARIO.yaml (own ship, targets, weather, controller), or a scene of a --family,
    and write its trace to -o.

    All the outputs are written, or none (with --family, the scene is written first). The
    summary JSON goes to stdout.
    """
    from usvtool.atomic import check_outputs, staged
    from usvtool.errors import UsvError
    from usvtool.sim.controllers import make_controller
    from usvtool.sim.run import SimOptions
    from usvtool.sim.run import simulate as run
    from usvtool.sim.scenario import controller_params, read_scenario
    from usvtool.trace import write_events, write_trace, write_tracks

    if (scenario_path is None) == (family is None):
        raise click.UsageError("give SCENARIO.yaml or --family, one of them")
    if (scenario_out is None) != (family is None):
        raise click.UsageError("--scenario-out: with --family, and --family needs it")
    scene = make_family_scene(family, kind, scene_number, family_options)
    written = []
    if scene is not None:  # the families' writers, only for a scene
        from usvtool.sim.families import scene_files, write_scene

        written = scene_files(scene, scenario_out)
    scene_outputs = [("--scenario-out", p) for p in written]
    outputs = [("-o", output), ("--events", events), ("--tracks", tracks),
               ("--summary", summary_path)]  # fmt: skip
    check_outputs([*outputs, *scene_outputs])
    if scene is not None:
        write_scene(scene, scenario_out)
        scenario_path = scenario_out
    scenario = read_scenario(scenario_path)
    name = controller or scenario.controller["name"]
    controller_params(name, params, lambda key: f"--param {key}")
    try:
        make_controller(name, **params)  # the values, before the scenario's files are read
    except UsvError as exc:
        raise UsvError(f"--param: {exc}") from None
    if controller and controller != scenario.controller["name"] and len(scenario.controller) > 1:
        log.info("%s: --controller %s: the parameters the scenario gives %s are not used",
                 scenario_path, controller, scenario.controller["name"])  # fmt: skip
    log.info("%s: running %s for %g s in steps of %g s", scenario_path, name,
             scenario.sim.duration, scenario.sim.dt)  # fmt: skip
    base = Path(events).resolve().parent if events else None
    result = run(scenario, SimOptions(controller=controller, params=params, seed=seed,
                                      max_memory=max_memory, files_base=base))  # fmt: skip
    summary = result.summary()
    extra = {"output": output, "scenario_file": scenario_path}
    if scene is not None:
        extra["scene"] = scene.summary()
    if events:
        extra["events"] = events
    if tracks:
        extra["tracks"] = tracks
    targets = (output, events, tracks, summary_path)
    with staged(*targets) as (trace_tmp, events_tmp, tracks_tmp, summary_tmp):
        write_trace(trace_tmp, result.trace)
        if events_tmp:
            write_events(events_tmp, result.events)
        if tracks_tmp:
            write_tracks(tracks_tmp, result.trace, result.crs)
        if summary_tmp:
            write_summary(summary_tmp, {**extra, **summary})
    if summary.get("collision"):
        log.warning("%s: the own ship collided with %s at t %g s", scenario_path,
                    summary["collision"], summary["time_s"])  # fmt: skip
    elif not summary.get("arrived"):
        log.info("%s: the own ship did not reach the goal in %g s", scenario_path,
                 summary["time_s"])  # fmt: skip
    log.info("%s: %d steps of %d ships", output, result.trace.n_steps, len(result.trace.ships))
    emit({**extra, **summary})
