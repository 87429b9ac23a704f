"""Scene families by name: :data:`FAMILIES`, seeded scenes drawn around the papers' geometry,
each checked for what its family promises (docs/families.md).

``make_scene(family, kind, scene, options)`` gives one scene (:class:`Scene`), reproducible from
those alone; :func:`write_scene` writes it as an ordinary scenario file (and the rasters it
names). Adding a family is its module (a :class:`Family` subclass with ``name``, ``kinds``,
``options``, ``draw`` and ``reject``) and its entry in the tuple below; :func:`register` adds
one at run time.

>>> s = make_scene("emergency", "head-on", 0)
>>> s.name, s.draws, [t["name"] for t in s.draw.scenario["targets"]]
('emergency-head-on-s000', 1, ['target', 'blocker'])
"""

from __future__ import annotations

from collections.abc import Mapping

from usvtool.errors import UsvError
from usvtool.sim.families.ais import Ais
from usvtool.sim.families.base import Draw, Family, Option, Scene, Where
from usvtool.sim.families.emergency import Emergency
from usvtool.sim.families.imazu import Imazu
from usvtool.sim.families.iwso import Iwso
from usvtool.sim.families.scenefile import scene_files, scene_text, write_scene
from usvtool.sim.families.wind import Wind

FAMILIES: dict[str, type[Family]] = {}


def register(cls: type[Family]) -> type[Family]:
    """Add ``cls`` to :data:`FAMILIES` under its ``name`` (new, a pipeline name: no ``/``);
    returns ``cls``, so it also serves as a class decorator."""
    if not cls.name or "/" in cls.name or not cls.kinds:
        raise ValueError(f"family {cls.name!r}: needs a name without '/' and kinds")
    if cls.name in FAMILIES:
        raise ValueError(f"family {cls.name!r} is already registered")
    FAMILIES[cls.name] = cls
    return cls


def unregister(name: str) -> None:
    """Remove the family registered as ``name`` (KeyError when there is none)."""
    del FAMILIES[name]


for _cls in (Emergency, Iwso, Imazu, Wind, Ais):
    register(_cls)


def family(name: str) -> Family:
    """The family registered as ``name``; :class:`UsvError` for an unknown name."""
    try:
        return FAMILIES[name]()
    except KeyError:
        raise UsvError(f"unknown scene family {name!r} (known: {', '.join(FAMILIES)})") from None


def make_scene(name: str, kind: str, scene: int = 0, options: Mapping | None = None,
               where: Where = lambda key: f"option {key}") -> Scene:  # fmt: skip
    """Scene ``scene`` of ``kind`` of family ``name`` with ``options`` (:meth:`Family.scene`)."""
    return family(name).scene(kind, scene, options, where)


__all__ = ["FAMILIES", "Draw", "Family", "Option", "Scene", "family", "make_scene", "register",
           "scene_files", "scene_text", "unregister", "write_scene"]  # fmt: skip
