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
from usvtool.registry import Registry
from usvtool.sim.families.ais import Ais
from usvtool.sim.families.base import Draw, Family, Option, Scene, Where
from usvtool.sim.families.emergency import Emergency
from usvtool.sim.families.imazu import Imazu
from usvtool.sim.families.iwso import Iwso
from usvtool.sim.families.scenefile import scene_files, scene_text, write_scene
from usvtool.sim.families.trafficgen import Trafficgen
from usvtool.sim.families.wind import Wind

#: Every scene family: the built-ins below, then the ``usvtool.families`` plugins.
FAMILIES = Registry("family", Family, "usvtool.families",
                    lambda cls: "has a '/' (a pipeline name)" if "/" in cls.name
                    else None if cls.kinds else "no kinds")  # fmt: skip
#: Add a family (a class decorator too); ``ValueError`` for a taken or bad name.
register = FAMILIES.register
#: Remove the family registered under a name (``KeyError`` when there is none).
unregister = FAMILIES.unregister

for _cls in (Emergency, Iwso, Imazu, Wind, Ais, Trafficgen):
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
