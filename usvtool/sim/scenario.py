"""Scenario YAML: what ``usvtool simulate`` runs (the schema is docs/scenario.md).

A scenario names its map, route, simulation settings, own ship, targets, weather and controller.
:func:`read_scenario` validates the file and returns plain dataclasses: every error is one line
that names the file and the field (``env1-head-on.yaml: own.speed must be a number, not 'fast'``).
Paths inside are relative to the scenario's own directory. Points are ``[x, y]`` map metres, or
``{lon: .., lat: ..}`` on a map with a CRS (converted by the simulation, which has the map).
Headings are compass degrees, speeds m/s, lengths metres.

>>> s = parse({"name": "demo", "own": {"start": [0, 0], "goal": [0, 100], "speed": 2}}, "x.yaml")
>>> s.own.vessel, s.sim.dt, s.targets
('iwso-dwa-usv', 0.1, [])
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

from usvtool.angles import wrap360
from usvtool.errors import UsvError
from usvtool.params import check
from usvtool.sim.vessel import PRESETS, USER_UNITS
from usvtool.yamlfile import read_yaml, show

DEFAULT_VESSEL = "iwso-dwa-usv"
#: Inline vessel fields a scenario may set, in user units (:data:`usvtool.sim.vessel.USER_UNITS`).
VESSEL_FIELDS = tuple(USER_UNITS)
#: The smallest ``sim.dt`` (s): the trace writes times to the millisecond.
MIN_DT = 0.001
#: Characters a ship name may not hold (the trace CSV's rule), and the own ship's name.
_BAD_NAME = (",", '"', "\n", "\r")
OWN_NAME = "own"


@dataclass(frozen=True)
class Sim:
    dt: float = 0.1  # s
    duration: float = 600.0  # s
    goal_tolerance: float = 5.0  # m


@dataclass(frozen=True)
class Ship:
    """The own ship: start, goal, compass heading, speed, vessel preset and overrides."""

    start: object
    goal: object
    heading: float = 0.0
    speed: float = 0.0
    vessel: str = DEFAULT_VESSEL
    overrides: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Target:
    """A target ship: straight on from its start, along waypoints, or replaying a track file."""

    name: str
    start: object | None
    heading: float
    speed: float
    length: float
    waypoints: list | None = None
    track: Path | None = None
    heading_sd: float = 0.0  # deg, per step
    speed_sd: float = 0.0  # m/s, per step


@dataclass(frozen=True)
class Weather:
    """Uniform wind (and waves), or a field raster."""

    wind_speed: float | None = None
    wind_from: float | None = None
    wave_height: float | None = None
    wave_from: float | None = None
    field: Path | None = None


@dataclass(frozen=True)
class Scenario:
    name: str
    path: Path
    own: Ship
    sim: Sim = field(default_factory=Sim)
    map: Path | None = None
    route: Path | None = None
    targets: list[Target] = field(default_factory=list)
    weather: Weather | None = None
    controller: dict = field(default_factory=lambda: {"name": "dwa"})


def read_scenario(path: str | os.PathLike) -> Scenario:
    """Read and validate a scenario YAML file (bounded: :func:`usvtool.yamlfile.read_yaml`)."""
    return parse(read_yaml(path), path)


def parse(data, path: str | os.PathLike) -> Scenario:
    """Validate a scenario already loaded from YAML (``path`` names it in errors)."""
    path = Path(path)
    v = _Fields(path)
    top = v.mapping(data, "", required={"name", "own"},
                    allowed={"name", "map", "route", "sim", "own", "targets", "weather",
                             "controller"})  # fmt: skip
    sim = v.mapping(top.get("sim", {}), "sim", allowed={"dt", "duration", "goal_tolerance"})
    own_fields = {"start", "goal", "heading", "speed", "vessel", *VESSEL_FIELDS}
    own = v.mapping(top["own"], "own", required={"start", "goal"}, allowed=own_fields)
    targets = v.sequence(top.get("targets", []), "targets")
    controller = v.mapping(top.get("controller", {"name": "dwa"}), "controller", required={"name"})
    controller_name = v.text(controller["name"], "controller.name")
    if controller_name not in _controllers():
        v.fail("controller.name", f"must be one of {', '.join(_controllers())}, not "
                                  f"{show(controller_name)}")  # fmt: skip
    controller_params(controller_name, {k: val for k, val in controller.items() if k != "name"},
                      lambda key: f"{path}: controller.{key}")  # fmt: skip
    vessel = v.text(own.get("vessel", DEFAULT_VESSEL), "own.vessel")
    if vessel not in PRESETS:
        v.fail("own.vessel", f"must be a vessel preset ({', '.join(sorted(PRESETS))}), not "
                             f"{show(vessel)}")  # fmt: skip
    dt = v.number(sim.get("dt", Sim.dt), "sim.dt", positive=True)
    if dt < MIN_DT:
        v.fail("sim.dt", f"must be at least {MIN_DT:g} s (the trace's time resolution), not {dt:g}")
    duration = v.number(sim.get("duration", Sim.duration), "sim.duration", positive=True)
    if dt > duration:
        v.fail("sim.dt", f"must be at most sim.duration ({duration:g} s), not {dt:g}: the run "
                         "would take no step")  # fmt: skip
    targets = [_target(v, t, i) for i, t in enumerate(targets)]
    names = [OWN_NAME]
    for i, t in enumerate(targets):
        if t.name in names:
            v.fail(f"targets[{i}].name", f"{show(t.name)} is taken (by the own ship or a target)")
        names.append(t.name)
    return Scenario(
        name=v.text(top["name"], "name"),
        path=path,
        map=v.file(top["map"], "map") if "map" in top else None,
        route=v.file(top["route"], "route") if "route" in top else None,
        sim=Sim(
            dt=dt,
            duration=duration,
            goal_tolerance=v.number(
                sim.get("goal_tolerance", Sim.goal_tolerance), "sim.goal_tolerance", positive=True
            ),
        ),
        own=Ship(
            start=v.point(own["start"], "own.start"),
            goal=v.point(own["goal"], "own.goal"),
            heading=v.angle(own.get("heading", 0.0), "own.heading"),
            speed=v.number(own.get("speed", 0.0), "own.speed", minimum=0.0),
            vessel=vessel,
            overrides={
                k: v.number(own[k], f"own.{k}", positive=k != "min_speed", minimum=0.0)
                for k in VESSEL_FIELDS
                if k in own
            },
        ),
        targets=targets,
        weather=_weather(v, top["weather"]) if "weather" in top else None,
        controller={
            "name": controller_name,
            **{k: val for k, val in controller.items() if k != "name"},
        },
    )


def _target(v: _Fields, data, index: int) -> Target:
    where = f"targets[{index}]"
    t = v.mapping(data, where, required={"speed", "length"},
                  allowed={"name", "start", "heading", "speed", "length", "waypoints", "track",
                           "noise"})  # fmt: skip
    kinds = [k for k in ("waypoints", "track") if k in t]
    if len(kinds) > 1:
        raise UsvError(f"{v.path}: {where}: give waypoints or track, not both")
    if not kinds and "start" not in t:
        raise UsvError(f"{v.path}: {where}.start is missing (a straight course needs a start)")
    if not kinds and "heading" not in t:
        raise UsvError(f"{v.path}: {where}.heading is missing (a straight course needs one)")
    noise = v.mapping(t.get("noise", {}), f"{where}.noise", allowed={"heading_sd", "speed_sd"})
    waypoints = None
    if "waypoints" in t:
        points = v.sequence(t["waypoints"], f"{where}.waypoints")
        if not points:
            raise UsvError(f"{v.path}: {where}.waypoints is empty")
        waypoints = [v.point(p, f"{where}.waypoints[{i}]") for i, p in enumerate(points)]
    name = v.text(t.get("name", f"target{index + 1}"), f"{where}.name")
    if any(c in name for c in _BAD_NAME):
        v.fail(f"{where}.name", f"must hold no comma, quote or line break, not {show(name)}")
    return Target(
        name=name,
        start=v.point(t["start"], f"{where}.start") if "start" in t else None,
        heading=v.angle(t.get("heading", 0.0), f"{where}.heading"),
        speed=v.number(t["speed"], f"{where}.speed", minimum=0.0),
        length=v.number(t["length"], f"{where}.length", positive=True),
        waypoints=waypoints,
        track=v.file(t["track"], f"{where}.track") if "track" in t else None,
        heading_sd=v.number(noise.get("heading_sd", 0.0), f"{where}.noise.heading_sd", minimum=0),
        speed_sd=v.number(noise.get("speed_sd", 0.0), f"{where}.noise.speed_sd", minimum=0),
    )


def _weather(v: _Fields, data) -> Weather:
    fields = {"wind_speed", "wind_from", "wave_height", "wave_from", "field"}
    w = v.mapping(data, "weather", allowed=fields)
    if "field" in w:
        extra = sorted(set(w) - {"field"})
        if extra:
            raise UsvError(f"{v.path}: weather: give a field or uniform values, not both {extra}")
        return Weather(field=v.file(w["field"], "weather.field"))
    for key in ("wind_speed", "wind_from"):
        if key not in w:
            raise UsvError(f"{v.path}: weather.{key} is missing")
    return Weather(
        wind_speed=v.number(w["wind_speed"], "weather.wind_speed", minimum=0.0),
        wind_from=v.angle(w["wind_from"], "weather.wind_from"),
        wave_height=(
            v.number(w["wave_height"], "weather.wave_height", minimum=0.0)
            if "wave_height" in w else None
        ),
        wave_from=v.angle(w["wave_from"], "weather.wave_from") if "wave_from" in w else None,
    )  # fmt: skip


def controller_params(name: str, params: dict, where) -> dict:
    """Check ``params`` against controller ``name``'s declared parameters (known names, and the
    kind, range and choices of each: :func:`usvtool.params.check`); ``where(key)`` names a
    parameter in the errors. Returns ``params``.

    >>> controller_params("dwa", {"horizon": 2}, lambda k: f"--param {k}")
    {'horizon': 2}
    >>> controller_params("dwa", {"horizon": "far"}, lambda k: f"--param {k}")
    Traceback (most recent call last):
    usvtool.errors.UsvError: --param horizon must be a finite number, not 'far'
    >>> controller_params("dwa", {"horizon": 0}, lambda k: f"s.yaml: controller.{k}")
    Traceback (most recent call last):
    usvtool.errors.UsvError: s.yaml: controller.horizon must be > 0 for dwa, not 0
    """
    check(_controllers()[name].declarations(), params, where, name)
    return params


def _controllers() -> dict:
    from usvtool.sim.controllers import CONTROLLERS

    return CONTROLLERS


class _Fields:
    """Typed field readers whose errors name the file and the field."""

    def __init__(self, path: Path):
        self.path = path

    def fail(self, where: str, what: str):
        raise UsvError(f"{self.path}: {where} {what}" if where else f"{self.path}: {what}")

    def mapping(self, value, where: str, required=frozenset(), allowed=None) -> dict:
        if not isinstance(value, dict):
            self.fail(where, f"must be a mapping, not {_kind(value)}")
        for key in sorted(required - set(value)):
            self.fail(f"{where}.{key}".lstrip("."), "is missing")
        if allowed is not None:
            unknown = sorted(set(value) - set(allowed))
            if unknown:
                name = f"{where}.{unknown[0]}".lstrip(".")
                self.fail(name, f"is not a field (known: {', '.join(sorted(allowed))})")
        return value

    def sequence(self, value, where: str) -> list:
        if not isinstance(value, list):
            self.fail(where, f"must be a list, not {_kind(value)}")
        return value

    def text(self, value, where: str) -> str:
        if not isinstance(value, str) or not value:
            self.fail(where, f"must be a non-empty string, not {show(value)}")
        return value

    def number(self, value, where: str, positive=False, minimum=None) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            self.fail(where, f"must be a number, not {show(value)}")
        value = float(value)
        if not math.isfinite(value):
            self.fail(where, f"must be finite, not {value}")
        if positive and value <= 0:
            self.fail(where, f"must be > 0, not {value:g}")
        if minimum is not None and value < minimum:
            self.fail(where, f"must be >= {minimum:g}, not {value:g}")
        return value

    def angle(self, value, where: str) -> float:
        return float(wrap360(self.number(value, where)))

    def point(self, value, where: str):
        if isinstance(value, dict):
            self.mapping(value, where, required={"lon", "lat"}, allowed={"lon", "lat"})
            lon = self.number(value["lon"], f"{where}.lon")
            lat = self.number(value["lat"], f"{where}.lat")
            if not (-180 <= lon <= 180 and -90 <= lat <= 90):
                self.fail(where, f"is not a lon/lat position: {lon}, {lat}")
            return {"lon": lon, "lat": lat}
        if not isinstance(value, list) or len(value) != 2:
            self.fail(where, f"must be [x, y] or {{lon, lat}}, not {show(value)}")
        return (self.number(value[0], f"{where}[0]"), self.number(value[1], f"{where}[1]"))

    def file(self, value, where: str) -> Path:
        name = self.text(value, where)
        path = (self.path.parent / name).resolve()
        if not path.is_file():
            self.fail(where, f"names {show(name)}, which is not a file ({path})")
        return path


def _kind(value) -> str:
    return {dict: "a mapping", list: "a list", str: "a string"}.get(type(value), show(value))
