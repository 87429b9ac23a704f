"""What every scene family shares: its options (its parameters), its seeded draws, the bound on
them, and the checks of what a scene promises (docs/families.md).

A :class:`Family` draws a scene of one of its ``kinds`` from a generator seeded by the scene's
number alone (:meth:`Family.generator`), checks the draw (:meth:`Family.reject`: the reason it
breaks the family's promise, or None) and draws again, at most :attr:`Family.max_draws` times;
:meth:`Family.scene` gives the first draw that keeps the promise, with the number of draws it
took and the reasons of the rejected ones, or raises :class:`UsvError` in one line. A scene is
an ordinary scenario mapping (docs/scenario.md) plus the rasters it names (a map, a wind field:
:class:`Draw`), written by :func:`usvtool.sim.families.scenefile.write_scene`.

Conventions of every family: map metres, x east and y north, compass degrees, m/s; floats as
drawn (the scenario file holds them exactly: YAML floats round-trip).
"""

from __future__ import annotations

import zlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from usvtool import encounter
from usvtool.errors import UsvError
from usvtool.params import NON_NEGATIVE, POSITIVE, Param, View, check, declared
from usvtool.sim.vessel import PRESETS
from usvtool.yamlfile import show

#: Option values: a number or a word.
Value = float | int | str
#: ``where(option)``: how an error names an option (``--family-option own_speed``).
Where = Callable[[str], str]


def Option(default: Value, help: str, positive: bool = True, choices: tuple[str, ...] = (),
           file: bool = False, required: bool = True) -> Param:  # fmt: skip
    """The families' older declaration of an option, still taken (a family declares a
    :class:`usvtool.params.Param` now): a number (any, an int default too) > 0 (``positive``)
    or >= 0; a word one of ``choices`` when given; a ``file`` option (default ``""``) names a
    file the family reads, which must be given unless it is not ``required``."""
    if file:
        return Param(default, help, file=True, required=required)
    if isinstance(default, str):
        return Param(default, help, choices=tuple(choices))
    return Param(default, help, POSITIVE if positive else NON_NEGATIVE, kind="number")


def vessel_option(default: str) -> Param:
    """The own ship's vessel preset (:data:`usvtool.sim.vessel.PRESETS`)."""
    return Param(default, "the own ship's vessel preset", choices=tuple(sorted(PRESETS)))


def duration_option(default: float) -> Param:
    return Param(default, "sim.duration, s (the run stops there if the own ship has not arrived)",
                 POSITIVE)


class MapFile:
    """A scene's map, written as a navigation grid GeoTIFF (:func:`usvtool.grid.write_grid`)."""

    def __init__(self, grid):
        self.grid = grid

    def write(self, path) -> None:
        from usvtool.grid import write_grid

        write_grid(path, self.grid)


@dataclass(frozen=True)
class Draw:
    """One drawn scene: its scenario mapping and the files it names, by the scenario field
    that names them (``"map"``, ``"weather.field"``; a list item by its index,
    ``"targets.0.track"``) -> (the file's suffix, an object with ``write(path)``); the scenario
    file gives them as ``<its stem>.<suffix>`` beside it. ``comments``: lines added to the
    file's header (what the scene is made of)."""

    scenario: dict
    files: dict[str, tuple[str, object]] = field(default_factory=dict)
    comments: tuple[str, ...] = ()


@dataclass(frozen=True)
class Scene:
    """A scene that keeps its family's promise: which one it is, its options (every one, the
    defaults filled in), the draw, the number of draws it took and why the others were
    rejected (reason -> count)."""

    family: str
    kind: str
    scene: int
    options: dict[str, Value]
    given: dict[str, Value]
    draw: Draw
    draws: int
    rejected: dict[str, int]

    @property
    def name(self) -> str:
        """The scenario's name: ``emergency-head-on-s007`` (or the name the draw gave itself),
        the options given that differ from the defaults appended (``-own_speed=5``; not the
        files, which the draw's name stands for), so two scenes of one name are the same."""
        return self.draw.scenario["name"]

    def summary(self) -> dict:
        return {"family": self.family, "kind": self.kind, "scene": self.scene,
                "name": self.name, "options": self.options, "draws": self.draws,
                "rejected": self.rejected}  # fmt: skip


class Family:
    """A scene family (a subclass per family: ``name``, ``kinds``, ``parameters`` (its options:
    a :class:`usvtool.params.Param` each; the older ``options`` is still read), ``controller``,
    :meth:`draw` and :meth:`reject`). A ``file`` option names a file the family reads (its
    default ``""``: it must be given when it is ``required``, and the file must exist; a
    pipeline gives it relative to its root, and its content keys the jobs)."""

    name: ClassVar[str] = ""
    kinds: ClassVar[tuple[str, ...]] = ()
    #: False: a kind is one scene (the Imazu cases); its only scene is 0.
    seeded: ClassVar[bool] = True
    parameters: ClassVar[dict[str, Param]] = {}
    #: The older attribute, read from :meth:`declarations` (name -> its declaration).
    options = View(dict)
    #: The scenario's controller field: the paper's (``usvtool simulate --controller`` overrides).
    controller: ClassVar[str] = "dwa"
    max_draws: ClassVar[int] = 100
    #: A short line per kind for ``usvtool scene --list`` and the docs.
    about: ClassVar[dict[str, str]] = {}

    def draw(self, kind: str, rng: np.random.Generator, opts: dict) -> Draw:
        """One candidate scene of ``kind``."""
        raise NotImplementedError

    def reject(self, kind: str, draw: Draw, opts: dict) -> str | None:
        """Why ``draw`` breaks the family's promise for ``kind`` (a few words), or None."""
        raise NotImplementedError

    def draw_scene(self, kind: str, scene: int, rng: np.random.Generator, opts: dict) -> Draw:
        """One candidate of scene ``scene`` of ``kind``: :meth:`draw` (a family whose scenes
        are numbered, not drawn, such as recorded encounters, overrides this instead)."""
        return self.draw(kind, rng, opts)

    def generator(self, kind: str, scene: int) -> np.random.Generator:
        """The draws' generator of scene ``scene`` of ``kind``: seeded by the family's name, the
        kind and the scene's number only (CRC-32 of the names: the same on every machine)."""
        words = [zlib.crc32(self.name.encode()), zlib.crc32(kind.encode()), scene]
        return np.random.default_rng(np.random.SeedSequence(words))

    @classmethod
    def declarations(cls) -> dict[str, Param]:
        """Its options: ``parameters`` (and the older ``options``) of each class from
        :class:`Family` down (:func:`usvtool.params.declared`)."""
        return declared(cls, ("options", "parameters"))

    def check_options(self, given: Mapping, where: Where) -> dict[str, Value]:
        """Every option: ``given`` checked against :meth:`declarations`
        (:func:`usvtool.params.check`, every required one given), the defaults filled in."""
        return check(self.declarations(), given, where, f"family {self.name}", complete=True)

    def scene(self, kind: str, scene: int = 0, given: Mapping | None = None,
              where: Where = lambda key: f"option {key}") -> Scene:  # fmt: skip
        """Scene ``scene`` of ``kind``: the first of at most :attr:`max_draws` draws that keeps
        the promise; a :class:`UsvError` naming the rejections when none does."""
        if kind not in self.kinds:
            raise UsvError(f"family {self.name} has no kind {show(kind)} (kinds: "
                           f"{', '.join(self.kinds)})")  # fmt: skip
        if isinstance(scene, bool) or not isinstance(scene, int) or scene < 0:
            raise UsvError(f"family {self.name}: a scene is an integer >= 0, not {show(scene)}")
        if not self.seeded and scene != 0:
            raise UsvError(f"family {self.name} is not seeded: each kind is one scene, 0, not "
                           f"{scene}")  # fmt: skip
        given = dict(given or {})
        opts = self.check_options(given, where)
        rng = self.generator(kind, scene)
        rejected: dict[str, int] = {}
        declared = self.declarations()
        suffix = "".join(f"-{k}={v}" for k, v in sorted(given.items())
                         if v != declared[k].default and not declared[k].file)
        for draws in range(1, self.max_draws + 1):
            draw = self.draw_scene(kind, scene, rng, opts)
            reason = self.reject(kind, draw, opts)
            if reason is None:
                own = draw.scenario.get("name") or f"{self.name}-{kind}-s{scene:03d}"
                draw.scenario["name"] = own + suffix
                return Scene(self.name, kind, scene, opts, given, draw, draws, rejected)
            rejected[reason] = rejected.get(reason, 0) + 1
        counts = ", ".join(f"{n} {r}" for r, n in sorted(rejected.items(), key=lambda i: -i[1]))
        raise UsvError(f"family {self.name}, kind {kind}, scene {scene}: no draw of "
                       f"{self.max_draws} keeps its promise ({counts})")  # fmt: skip


# ----------------------------------------------------------------------------- building scenes


def ship(name: str, x, y, heading, speed, length) -> dict:
    """A target on a straight course, as a scenario's ``targets`` entry."""
    return {"name": name, "start": [float(x), float(y)], "heading": float(heading % 360.0),
            "speed": float(speed), "length": float(length)}  # fmt: skip


def scenario(own: dict, targets: list[dict], duration: float, controller: str, *,
             dt: float = 0.1, goal_tolerance: float = 5.0, **extra) -> dict:  # fmt: skip
    """A scenario mapping (its name is set by :meth:`Family.scene`); ``extra``: ``weather``,
    ``map``."""
    out = {"name": "", **extra,
           "sim": {"dt": dt, "duration": float(duration), "goal_tolerance": goal_tolerance},
           "own": own}  # fmt: skip
    if targets:
        out["targets"] = targets
    out["controller"] = {"name": controller}
    return out


def own_ship(start, goal, heading: float, speed: float, vessel: str) -> dict:
    return {"start": [float(v) for v in start], "goal": [float(v) for v in goal],
            "heading": float(heading), "speed": float(speed), "vessel": vessel}  # fmt: skip


def toward(point, heading: float, distance) -> np.ndarray:
    """The point ``distance`` metres from ``point`` along compass ``heading``."""
    return np.asarray(point, float) + distance * encounter.velocity(heading, 1.0)


# ----------------------------------------------------------------------------- promise checks


def start_situation(s: dict) -> encounter.Situation:
    """Each target's class, bearings, range and CPA at the start (``encounter.assess``)."""
    own, targets = s["own"], s["targets"]
    return encounter.assess(own["start"], own["heading"], own["speed"],
                            [t["start"] for t in targets], [t["heading"] for t in targets],
                            [t["speed"] for t in targets])  # fmt: skip


def class_names(s: dict) -> list[str]:
    return [encounter.CLASS_NAMES[c] for c in start_situation(s).cls]


def crowding(s: dict) -> str | None:
    """Why the targets do not start clear: one inside the own ship's domain (7 L x 3 L,
    :func:`usvtool.encounter.in_domain`, L the own length: its override, else its preset's),
    or two whose hulls are less than half their mean length apart (centres closer than 3/4 of
    the sum of their lengths)."""
    own, targets = s["own"], s.get("targets", [])
    if not targets:
        return None
    xy = np.array([t["start"] for t in targets], float)
    length = own.get("length", PRESETS[own["vessel"]]["length"])  # a vessel override, if any
    if encounter.in_domain(own["start"], own["heading"], xy, length).any():
        return "target in the own ship's domain"
    lengths = np.array([t["length"] for t in targets], float)
    gap = np.hypot(*(xy[:, None, :] - xy[None, :, :]).transpose(2, 0, 1))
    close = gap < 0.75 * (lengths[:, None] + lengths[None, :])
    np.fill_diagonal(close, False)
    return "targets too close to each other" if close.any() else None
