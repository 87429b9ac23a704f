"""``usvtool plugins``: every method usvtool knows (optimizers, exact planners, controllers, scene
families), built in or from an installed distribution's entry points (usvtool/registry.py), with
its kind, where it comes from and every parameter of its declaration (usvtool/params.py: default,
kind, range or choices, help); the plugins that cannot be used, each in one line."""

from __future__ import annotations

import click

from usvtool.cli.options import emit


@click.command()
def plugins() -> None:
    """List every method, its kind, distribution and version, and its parameters (default,
    range or choices, what each sets)."""
    from usvtool.params import describe
    from usvtool.plan.optimizers import OPTIMIZERS
    from usvtool.plan.planners import EXACT
    from usvtool.sim.controllers import CONTROLLERS
    from usvtool.sim.families import FAMILIES

    def rows(kind: str, registry) -> list[dict]:
        return [{"name": name, "kind": kind, "distribution": registry.origin(name)[0],
                 "version": registry.origin(name)[1],
                 "parameters": describe(getattr(cls, "declarations", dict)())}
                for name, cls in registry.items()]  # fmt: skip

    registries = {"optimizer": OPTIMIZERS, "exact planner": EXACT, "controller": CONTROLLERS,
                  "scene family": FAMILIES}  # fmt: skip
    methods = [row for kind, registry in registries.items() for row in rows(kind, registry)]
    problems = []  # registries sharing a group share its problems: each line once
    for registry in registries.values():
        problems += [line for line in registry.problems if line not in problems]
    emit({"methods": methods, "problems": problems})
