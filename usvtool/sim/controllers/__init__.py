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


def register(cls: type[Controller]) -> type[Controller]:
    """Add ``cls`` to :data:`CONTROLLERS` under its ``name``, which must be new; returns
    ``cls``, so it also serves as a class decorator (docs/extending.md)."""
    if not cls.name or cls.name in CONTROLLERS:
        raise ValueError(f"controller name {cls.name!r}: empty or already registered")
    CONTROLLERS[cls.name] = cls
    return cls


def unregister(name: str) -> None:
    """Remove the controller registered as ``name`` (KeyError when there is none)."""
    del CONTROLLERS[name]


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
    "make_controller", "register", "unregister",
]  # fmt: skip
