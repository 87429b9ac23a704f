"""The DWA controllers, by name."""

from __future__ import annotations

from usvtool.errors import UsvError
from usvtool.sim.controllers.base import Controller, Decision, Encounter, Own, Targets, World
from usvtool.sim.controllers.ccdwa import CCDWA
from usvtool.sim.controllers.dwa import DWA
from usvtool.sim.controllers.gdwa import GDWA
from usvtool.sim.controllers.udwa import UDWA
from usvtool.sim.controllers.udwa_plus import UDWAPlus

CONTROLLERS: dict[str, type[Controller]] = {
    cls.name: cls for cls in (DWA, GDWA, CCDWA, UDWA, UDWAPlus)
}


def make_controller(name: str, **params) -> Controller:
    """The controller registered as ``name``; :class:`UsvError` for an unknown name."""
    try:
        cls = CONTROLLERS[name]
    except KeyError:
        known = ", ".join(CONTROLLERS)
        raise UsvError(f"unknown controller {name!r} (known: {known})") from None
    return cls(**params)


__all__ = [
    "CONTROLLERS", "Controller", "Decision", "Encounter", "Own", "Targets", "World",
    "make_controller",
]  # fmt: skip
