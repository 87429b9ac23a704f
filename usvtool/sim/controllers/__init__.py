"""The controllers, by name: :data:`CONTROLLERS`, the built-ins (the DWA controllers, and
``exec``, a program run as a process: :mod:`.process`) and the plugins installed distributions
declare (:class:`usvtool.registry.Registry`)."""

from __future__ import annotations

from usvtool.errors import UsvError
from usvtool.registry import Registry
from usvtool.sim.controllers.base import (
    Controller,
    ControllerFailed,
    Decision,
    DynamicWindow,
    Encounter,
    Own,
    Targets,
    World,
)
from usvtool.sim.controllers.ccdwa import CCDWA
from usvtool.sim.controllers.dwa import DWA
from usvtool.sim.controllers.gdwa import GDWA
from usvtool.sim.controllers.process import ProcessController
from usvtool.sim.controllers.sbmpc import SBMPC
from usvtool.sim.controllers.udwa import UDWA
from usvtool.sim.controllers.udwa_plus import UDWAPlus
from usvtool.sim.controllers.vo import VelocityObstacle

#: Every controller: the built-ins, then the ``usvtool.controllers`` plugins (docs/extending.md).
CONTROLLERS = Registry("controller", Controller, "usvtool.controllers")
#: Add a controller (a class decorator too); ``ValueError`` for a taken or bad name.
register = CONTROLLERS.register
#: Remove the controller registered under a name (``KeyError`` when there is none).
unregister = CONTROLLERS.unregister
for _cls in (DWA, GDWA, CCDWA, UDWA, UDWAPlus, VelocityObstacle, SBMPC, ProcessController):
    register(_cls)


def make_controller(name: str, **params) -> Controller:
    """The controller registered as ``name``; :class:`UsvError` for an unknown name."""
    try:
        cls = CONTROLLERS[name]
    except KeyError:
        known = ", ".join(CONTROLLERS)
        raise UsvError(f"unknown controller {name!r} (known: {known})") from None
    return cls(**params)


__all__ = [
    "CONTROLLERS", "Controller", "ControllerFailed", "Decision", "DynamicWindow", "Encounter",
    "Own", "ProcessController", "Targets", "World", "make_controller", "register", "unregister",
]  # fmt: skip
