"""``usvtool simulate``: run a scenario and write its trace CSV (+ events JSON, tracks GeoJSON).

The scenario's schema is docs/scenario.md, the outputs and the summary docs/simulate.md. With
``--family`` the scenario is a scene of a scene family (docs/families.md), written first to
``--scenario-out`` (with the rasters it names beside it) and run from there.
"""

from __future__ import annotations

import logging
import re
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
#: What ``--label`` may be (a method's name in a pipeline and the report).
_LABEL = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.+-]*$")


class ControllerChoice(click.Choice):
    """A registered controller's name, or ``exec:PROGRAM [ARGS...]``: a program run as a
    process (docs/protocol.md), its words split as a shell would (``shlex``), kept as given."""

    def __init__(self) -> None:
        super().__init__(list(CONTROLLERS))

    def get_metavar(self, param, *args, **kwargs) -> str:
        names = [c for c in self.choices if c != "exec"]
        return f"[{'|'.join(names)}|exec:PROGRAM [ARGS...]]"

    def convert(self, value, param, ctx):
        if isinstance(value, str) and value.startswith("exec:"):
            return value
        return super().convert(value, param, ctx)


def exec_words(controller: str | None) -> list[str] | None:
    """The program and arguments of ``--controller exec:PROGRAM [ARGS...]`` (None for another
    controller); a usage error for no program or unbalanced quotes."""
    import shlex

    if controller is None or not controller.startswith("exec:"):
        return None
    try:
        words = shlex.split(controller.removeprefix("exec:"))
    except ValueError as exc:
        raise click.BadParameter(f"{controller!r}: {exc}", param_hint="'--controller'") from None
    if not words:
        raise click.BadParameter("exec: names no program (exec:PROGRAM [ARGS...])",
                                 param_hint="'--controller'")  # fmt: skip
    return words


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


def check_label(label: str | None, program: list[str] | None) -> None:
    """A usage error for a ``--label`` that is no name, or is another controller's (an exec
    controller is named by its ``label`` parameter instead)."""
    if label is None:
        return
    if program is not None:
        raise click.BadParameter("an exec controller is named by --param label=NAME",
                                 param_hint="'--label'")  # fmt: skip
    if not _LABEL.match(label):
        raise click.BadParameter(f"{label!r} is not a name (letters, digits, _ . + -)",
                                 param_hint="'--label'")  # fmt: skip
    if label in CONTROLLERS:
        raise click.BadParameter(f"{label!r} is a controller's name: a variant needs a name of "
                                 "its own", param_hint="'--label'")  # fmt: skip


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
    type=ControllerChoice(),
    help="The controller to run instead of the scenario's (its parameters are then dropped); "
    "exec:PROGRAM [ARGS...] runs a program speaking docs/protocol.md (one word: quote it).",
)
@param_option("A controller parameter (repeatable), over the scenario's.")
@click.option("--label", metavar="NAME",
              help="The run's controller name in its summary and events (the method in the "
              "results; a batch gives a variant's name: docs/pipelines.md); default the "
              "controller's own.")  # fmt: skip
@seed_option
@output_option("Trace CSV to write.")
@click.option("--events", type=OutputPath(), help="Also write the events JSON.")
@click.option("--tracks", type=OutputPath(), help="Also write the tracks GeoJSON.")
@click.option("--controller-log", type=OutputPath(), metavar="FILE",
              help="Write what the controller's program wrote on its stderr to FILE (with the "
              "other outputs; empty for a built-in controller) instead of relaying it on "
              "stderr.")  # fmt: skip
@max_memory_option
@summary_option
def simulate(scenario_path: str | None, family: str | None, kind: str | None, scene_number: int,
             family_options: dict, scenario_out: str | None, controller: str | None,
             params: dict, label: str | None, seed: int, output: str, events: str | None,
             tracks: str | None, controller_log: str | None, max_memory: int | None,
             summary_path: str | None) -> None:  # fmt: skip
    """Run SCENARIO.yaml (own ship, targets, weather, controller), or a scene of a --family,
    and write its trace to -o.

    All the outputs are written, or none (with --family, the scene is written first). The
    summary JSON goes to stdout.
    """
    from usvtool.atomic import check_outputs, staged, write_text
    from usvtool.errors import UsvError
    from usvtool.sim.controllers import make_controller
    from usvtool.sim.run import SimOptions
    from usvtool.sim.run import simulate as run
    from usvtool.sim.scenario import controller_params, read_scenario
    from usvtool.trace import write_events, write_trace, write_tracks

    program = exec_words(controller)
    check_label(label, program)
    if program is not None:
        controller, params = "exec", {**params, "command": program}
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
               ("--controller-log", controller_log), ("--summary", summary_path)]  # fmt: skip
    check_outputs([*outputs, *scene_outputs])
    if scene is not None:
        write_scene(scene, scenario_out)
        scenario_path = scenario_out
    scenario = read_scenario(scenario_path)
    name = controller or scenario.controller["name"]
    controller_params(name, params, lambda key: f"--param {key}")
    own = {k: v for k, v in scenario.controller.items() if k != "name"}
    if name != scenario.controller["name"]:
        own = {}  # the scenario's parameters belong to its own controller
    try:  # the values, before the scenario's files are read
        make_controller(name, **{**own, **params})
    except UsvError as exc:
        where = "--controller" if program else "--param" if params else \
            f"{scenario_path}: controller"  # fmt: skip
        raise UsvError(f"{where}: {exc}") from None
    if controller and controller != scenario.controller["name"] and len(scenario.controller) > 1:
        log.info("%s: --controller %s: the parameters the scenario gives %s are not used",
                 scenario_path, controller, scenario.controller["name"])  # fmt: skip
    log.info("%s: running %s for %g s in steps of %g s", scenario_path, name,
             scenario.sim.duration, scenario.sim.dt)  # fmt: skip
    base = Path(events).resolve().parent if events else None
    result = run(scenario, SimOptions(controller=controller, params=params, seed=seed,
                                      max_memory=max_memory, files_base=base,
                                      label=label))  # fmt: skip
    summary = result.summary()
    extra = {"output": output, "scenario_file": scenario_path}
    if scene is not None:
        extra["scene"] = scene.summary()
    if events:
        extra["events"] = events
    if tracks:
        extra["tracks"] = tracks
    if controller_log:
        extra["controller_log"] = controller_log
    targets = (output, events, tracks, controller_log, summary_path)
    with staged(*targets) as (trace_tmp, events_tmp, tracks_tmp, log_tmp, summary_tmp):
        write_trace(trace_tmp, result.trace)
        if events_tmp:
            write_events(events_tmp, result.events)
        if tracks_tmp:
            write_tracks(tracks_tmp, result.trace, result.crs)
        if log_tmp:
            write_text(log_tmp, result.controller_log or "")
        if summary_tmp:
            write_summary(summary_tmp, {**extra, **summary})
    if not controller_log:
        for line in (result.controller_log or "").splitlines():
            log.warning("%s: %s", summary["controller"], line)
    if summary.get("collision"):
        log.warning("%s: the own ship collided with %s at t %g s", scenario_path,
                    summary["collision"], summary["time_s"])  # fmt: skip
    elif not summary.get("arrived"):
        log.info("%s: the own ship did not reach the goal in %g s", scenario_path,
                 summary["time_s"])  # fmt: skip
    log.info("%s: %d steps of %d ships", output, result.trace.n_steps, len(result.trace.ships))
    emit({**extra, **summary})
