"""``usvtool plugins``: every method usvtool knows (optimizers, exact planners, controllers, scene
families), built in or from an installed distribution's entry points (usvtool/registry.py), with
its kind, where it comes from and its parameters' defaults; the plugins that cannot be used,
each in one line."""

from __future__ import annotations

import click

from usvtool.cli.options import emit


@click.command()
def plugins() -> None:
    """List every method, its kind, distribution and version, and its parameters' defaults."""
    from usvtool import __version__
    from usvtool.plan.optimizers import OPTIMIZERS
    from usvtool.plan.planners import EXACT
    from usvtool.sim.controllers import CONTROLLERS
    from usvtool.sim.families import FAMILIES

    def rows(kind: str, registry, params) -> list[dict]:
        return [{"name": name, "kind": kind, "distribution": registry.origin(name)[0],
                 "version": registry.origin(name)[1], "parameters": params(cls)}
                for name, cls in registry.items()]  # fmt: skip

    methods = [
        *rows("optimizer", OPTIMIZERS, lambda cls: dict(cls.defaults)),
        *({"name": name, "kind": "exact planner", "distribution": "usvtool",
           "version": __version__, "parameters": {}} for name in EXACT),
        *rows("controller", CONTROLLERS, lambda cls: {**cls.common, **cls.defaults}),
        *rows("scene family", FAMILIES, lambda cls: {k: o.default for k, o in cls.options.items()}),
    ]  # fmt: skip
    problems = [*OPTIMIZERS.problems, *CONTROLLERS.problems, *FAMILIES.problems]
    emit({"methods": methods, "problems": problems})
