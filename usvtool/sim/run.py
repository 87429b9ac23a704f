"""Run a scenario: the own ship under a DWA controller among its targets (``usvtool simulate``).

Each step of ``sim.dt`` seconds: the targets are where their courses put them
(:mod:`usvtool.sim.targets`, computed before the run); every target is classified
(:mod:`usvtool.encounter`) and its encounter latched (:mod:`usvtool.sim.tracking`); the
controller picks a velocity pair for the step, with the side rule of the most urgent latched
encounter (the smallest time to the closest point of approach); the own ship moves on an exact
arc (IWSO-DWA eq. 16) at the speed she makes good in the wind and waves (UDWA eq. 5, when the
scenario has weather: for every controller, the sea does not care which one steers).

The run ends when the own ship is within ``sim.goal_tolerance`` of the goal (*arrived*), when she
touches a target (centres closer than half the sum of the two lengths) or an obstacle cell of the
map (*collision*), or at ``sim.duration``.

Figures of a run (the summary; :meth:`SimResult.summary`): ``closest_distance_m`` the smallest
centre distance to any target, ``average_distance_m`` the mean over the steps with a latched
encounter of the distance to the nearest target (the UDWA paper's Table 1;
:func:`usvtool.measures.run_distances`, as the metrics table),
``domain_intrusion_s`` the time some target is inside the own ship's domain, ``path_length_m``
the length of her track, ``turns`` and ``mot`` (:mod:`usvtool.measures`) on her track sampled
every ``measures.TURN_WINDOW`` seconds (:func:`usvtool.measures.track_samples`): a turn is a course
change between two such legs (per 0.1 s step a smooth turn would count once per step, or never),
``step_time_ms`` the mean time of one control decision.

The events JSON's ``run`` object makes the trace and events pair self-describing (``usvtool
metrics`` reads it): ``scenario``, ``controller``, ``parameters``, ``seed``, ``arrived``,
``collision``, ``time_s``, ``dt``, ``goal`` [x, y] (map metres), ``goal_tolerance``, ``own_length``,
``vessel`` (the own ship's figures in user units, ``Vessel.user_units``), ``domain_intrusion_s``,
and the scenario's resolved facts (:func:`scenario_facts`: ``scenario_file``, ``ships`` with
their lengths, ``map``, ``route``, ``tracks``, ``wind_field``).
"""

from __future__ import annotations

import contextlib
import functools
import logging
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from usvtool import angles, geodesy, measures
from usvtool.encounter import CLASS_NAMES
from usvtool.errors import UsvError
from usvtool.sim import memory, tracking, verdicts
from usvtool.sim import targets as target_motion
from usvtool.sim import vessel as vessel_model
from usvtool.sim.controllers import (
    ControllerFailed,
    Encounter,
    Own,
    Targets,
    World,
    make_controller,
)
from usvtool.sim.scenario import Scenario
from usvtool.trace import Trace

log = logging.getLogger("usvtool")


@dataclass(frozen=True)
class SimOptions:
    """What the command line adds to a scenario: another controller, parameters, the seed, the
    memory budget (bytes; None: :func:`usvtool.budget.default_budget`), and the folder the
    events are written to (``files_base``: the scenario's files below it are named relative to
    it, so that a run moved with its files, as a batch job is, still names them)."""

    controller: str | None = None
    params: dict = field(default_factory=dict)
    seed: int = 0
    max_memory: int | None = None
    files_base: Path | None = None  # the events file's folder: paths below it kept relative
    label: str | None = None  # the run's controller name in its summary and events (None: the
    # controller's own)


@dataclass
class SimResult:
    """A finished run: its trace, its events and its figures."""

    scenario: Scenario
    trace: Trace
    events: dict
    figures: dict
    crs: object | None = None
    #: what the controller wrote for people to read (a process's stderr: Controller.log)
    controller_log: str | None = None

    def summary(self) -> dict:
        return dict(self.figures)


def simulate(scenario: Scenario, options: SimOptions | None = None) -> SimResult:
    """Run ``scenario`` (see the module docstring)."""
    opts = options or SimOptions()
    name = opts.controller or scenario.controller["name"]
    params = {k: v for k, v in scenario.controller.items() if k != "name"}
    if opts.controller and opts.controller != scenario.controller["name"]:
        params = {}  # the scenario's parameters belong to its own controller
    with _naming(scenario.path, "controller"):
        controller = make_controller(name, **{**params, **opts.params})
    if opts.label is not None:
        controller.name = opts.label  # a variant's runs: the method in the results
    sim = scenario.sim
    n_steps = int(round(sim.duration / sim.dt))
    ships = len(scenario.targets) + 1
    tracks = memory.track_sizes(t.track for t in scenario.targets if t.track is not None)
    with memory.check_run(scenario.path, controller, n_steps, ships, opts.max_memory,
                          tracks=tracks):  # fmt: skip
        setup = _Setup(scenario, lambda width, height: memory.check_run(
            None, controller, n_steps, ships, opts.max_memory, (width, height),
            tracks))  # fmt: skip
        return _run(scenario, opts, controller, n_steps, setup)


def _run(scenario: Scenario, opts: SimOptions, controller, n_steps: int,
         setup: _Setup) -> SimResult:  # fmt: skip
    """The run of :func:`simulate` once its memory is checked and its files read."""
    voyage = Voyage(scenario, setup, n_steps, opts.seed)
    controller.reset(voyage.world)
    decide_time, failed = 0.0, None
    try:
        while not voyage.over:
            own, targets, encounter = voyage.observe()
            t0 = time.perf_counter()
            try:
                decision = controller.decide(own, targets, encounter)
            except ControllerFailed as exc:
                failed = f"step {voyage.step} (t = {voyage.time:g} s): {exc}"
                voyage.events.append({"t": round(voyage.time, 3), "kind": "controller-failed",
                                      "why": str(exc)})  # fmt: skip
                log.warning("%s: controller failed at %s", scenario.path, failed)
                break
            decide_time += time.perf_counter() - t0
            voyage.advance(decision.v, decision.omega, decision.events)
    finally:
        controller.close()
    result = _result(scenario, setup, opts, controller, voyage, failed,
                     decide_time / max(voyage.step, 1))  # fmt: skip
    result.controller_log = controller.log()
    return result


class Voyage:
    """One run of a scenario, step by step, whoever steers: :meth:`observe` gives what a
    controller sees at the current step (the own ship, the targets, the encounter of the most
    urgent latched target), :meth:`advance` moves the own ship one step of ``sim.dt`` under a
    velocity pair and ends the voyage on arrival, a collision or at ``n_steps``
    (:attr:`over`). :func:`simulate` drives it with a controller; :mod:`usvtool.gym` with an
    agent's actions."""

    def __init__(self, scenario: Scenario, setup: _Setup, n_steps: int, seed: int):
        sim = self.sim = scenario.sim
        self.scenario, self.setup, self.n_steps = scenario, setup, n_steps
        self.times = sim.dt * np.arange(n_steps + 1)
        rng = np.random.default_rng(seed)
        # one step beyond the end, for the targets' velocities at the last step
        times_ahead = sim.dt * np.arange(n_steps + 2)
        tracks = [target_motion.positions(c, times_ahead, rng) for c in setup.courses]
        self.ahead = np.stack(tracks, axis=1) if tracks else np.zeros((len(times_ahead), 0, 2))
        self.motion = _Motion.of(self.ahead, sim.dt)
        self.lengths = np.array([t.length for t in scenario.targets], float)
        vessel = self.vessel = setup.vessel
        self._reach = (vessel.length + self.lengths) / 2  # a contact's centre distance
        self._goal = float(setup.goal[0]), float(setup.goal[1])
        self.world = World(vessel, setup.goal, setup.clearance, setup.route, setup.weather,
                           sim.dt, sim.goal_tolerance, seed, scenario.map)  # fmt: skip
        self.x, self.y = setup.start
        self.psi = float(angles.compass_to_math(scenario.own.heading))
        self.v = float(np.clip(scenario.own.speed, vessel.min_speed, vessel.max_speed))
        self.omega, made_good = 0.0, self.v
        self.tracker = tracking.EncounterTracker(
            self.ahead.shape[1], risk_distance=tracking.onset_distance(vessel.length)
        )
        self.heading = angles.math_to_compass(self.psi)  # the trace's and tracker's unit
        self.made_good = made_good
        self.states = [(self.x, self.y, self.heading, made_good, self.omega)]
        #: the controller's events and the run's (a collision), with their times
        self.events: list[dict] = []
        self.collision: int | None = None
        self.arrived = False
        #: the steps taken
        self.step = 0

    @property
    def time(self) -> float:
        """The current step's time (s)."""
        return float(self.times[self.step])

    @property
    def over(self) -> bool:
        """Arrived, collided or out of time."""
        return self.arrived or self.collision is not None or self.step >= self.n_steps

    def observe(self) -> tuple[Own, Targets, Encounter | None]:
        """What a controller sees now (the tracker updated with the current step: call once a
        step, before :meth:`advance`)."""
        i, motion = self.step, self.motion
        urgent = self.tracker.update_urgent(self.times[i], self.x, self.y, self.heading,
                                            self.made_good, self.ahead[i], motion.heading[i],
                                            motion.speed[i])  # fmt: skip
        encounter = None if urgent is None else Encounter(
            CLASS_NAMES[self.tracker.latched[urgent]], urgent
        )  # fmt: skip
        own = Own(self.x, self.y, self.psi, self.v, self.omega)
        return own, Targets(self.ahead[i], motion.vel[i], self.lengths), encounter

    def advance(self, v: float, omega: float, events: list[dict] = ()) -> None:
        """Move the own ship one step at ``v`` through the water and yaw rate ``omega``, at
        the speed she makes good in the weather; log the step's ``events``."""
        setup, sim = self.setup, self.sim
        if events:
            t = round(self.time, 3)
            self.events += [{"t": t, **e} for e in events]
        self.v, self.omega, psi = v, omega, self.psi
        made_good = v if setup.weather is None else float(
            setup.weather.attainable_speed(v, psi, self.x, self.y, self.vessel.deadweight)
        )  # fmt: skip
        self.x, self.y, self.psi = vessel_model.step_one(self.x, self.y, psi, made_good, omega,
                                                         sim.dt)  # fmt: skip
        self.heading, self.made_good = angles.math_to_compass(self.psi), made_good
        self.states.append((self.x, self.y, self.heading, made_good, omega))
        self.step += 1
        self.collision = _collision(setup, self.x, self.y, self.ahead[self.step], self._reach)
        if self.collision is not None:
            self.events.append({"t": round(self.time, 3), "kind": "collision",
                                "with": _name(self.scenario, self.collision)})  # fmt: skip
        elif np.hypot(self.x - self._goal[0], self.y - self._goal[1]) <= sim.goal_tolerance:
            self.arrived = True


    def trace(self) -> Trace:
        """The run so far as its trace (the own ship first; the targets' yaw rates from their
        courses): what :func:`simulate` writes."""
        times, own = self.times[: self.step + 1], np.array(self.states)
        ahead, motion, n = self.ahead, self.motion, self.step + 1
        course = np.unwrap(motion.course[:n], axis=0)
        turn = np.diff(course, axis=0, append=course[-1:]) / self.sim.dt
        x = np.column_stack([own[:, 0], ahead[:n, :, 0]])
        y = np.column_stack([own[:, 1], ahead[:n, :, 1]])
        heading = np.column_stack([own[:, 2], motion.heading[:n]])
        speed = np.column_stack([own[:, 3], motion.speed[:n]])
        yaw = -np.degrees(np.column_stack([own[:, 4], turn]))  # compass sense: + to starboard
        names = ["own", *[t.name for t in self.scenario.targets]]
        return Trace(times, names, x, y, heading, speed, yaw)


def start_voyage(scenario: Scenario, seed: int = 0) -> Voyage:
    """The :class:`Voyage` of ``scenario`` at its start (its files read, the targets' courses
    drawn with ``seed``), for a caller that steers it itself (:mod:`usvtool.gym`): the voyage
    :func:`simulate` runs, without a controller nor the memory check."""
    sim = scenario.sim
    return Voyage(scenario, _Setup(scenario), int(round(sim.duration / sim.dt)), seed)


@dataclass(frozen=True)
class _Motion:
    """The targets' motion over the run, derived once from their positions ``(n + 1, k, 2)``
    (one step beyond the end): at each step the velocity ``(n, k, 2)`` to the next position,
    its direction ``course`` (mathematical radians) and ``heading`` (compass degrees: the
    tracker's and the trace's), and its ``speed``."""

    vel: np.ndarray
    course: np.ndarray
    heading: np.ndarray
    speed: np.ndarray

    @classmethod
    def of(cls, ahead: np.ndarray, dt: float) -> _Motion:
        vel = np.diff(ahead, axis=0) / dt
        course = np.arctan2(vel[..., 1], vel[..., 0])
        return cls(vel, course, angles.math_to_compass(course),
                   np.hypot(vel[..., 0], vel[..., 1]))  # fmt: skip


class _Setup:
    """The scenario's files read and its points in map metres, with errors naming the field."""

    def __init__(self, scenario: Scenario, check_map=None):
        """``check_map(width, height)`` is called with the map's size before its cells are
        read (:func:`usvtool.sim.memory.check_run`)."""
        from usvtool.sim import weather as weather_model

        path = self.path = scenario.path
        self.grid = self.clearance = None
        crs = None
        if scenario.map is not None:
            from usvtool.clearance import Clearance
            from usvtool.grid import read_grid

            with _naming(path, "map"):
                self.grid = read_grid(scenario.map, check_map)
            self.clearance = Clearance(self.grid)
            crs = self.grid.crs
            from usvtool.grid import OBSTACLE

            #: the grid's bounds, cell size, cells and obstacle code, as _collision takes them
            self.box = (*self.grid.bounds, self.grid.cell_size, self.grid.cells, OBSTACLE)
        self.crs = crs
        self.start = self.point(scenario.own.start, "own.start")
        self.goal = np.array(self.point(scenario.own.goal, "own.goal"))
        if self.grid is not None:
            from usvtool.collision import check_point

            for field_name, p in (("own.start", self.start), ("own.goal", self.goal)):
                try:
                    check_point(self.grid, p, field_name)
                except UsvError as exc:
                    raise UsvError(f"{path}: {exc}") from None
        self.vessel = vessel_model.vessel_from(
            scenario.own.vessel, scenario.own.overrides, f"{path}: own"
        )
        self.route = None
        if scenario.route is not None:
            from usvtool.route import read_path_geojson

            with _naming(path, "route"):
                points, _ = read_path_geojson(scenario.route)
                if points.ndim != 2 or points.shape[1:] != (2,) or len(points) < 2:
                    raise UsvError(f"{scenario.route}: a route needs two or more [x, y] points")
                if not np.isfinite(points).all():
                    raise UsvError(f"{scenario.route}: a route's coordinates must be finite")
            gap = float(np.hypot(*(points[0] - np.asarray(self.start))))
            if gap > scenario.sim.goal_tolerance:
                raise UsvError(
                    f"{path}: route {scenario.route.name} starts {gap:.1f} m from own.start "
                    f"(at most sim.goal_tolerance, {scenario.sim.goal_tolerance:g} m)"
                )
            self.route = points
        self.weather = None
        w = scenario.weather
        if w is not None and w.field is not None:
            with _naming(path, "weather.field"):
                self.weather = weather_model.read_weather(w.field, crs=crs)
        elif w is not None:
            self.weather = weather_model.uniform(
                w.wind_speed, w.wind_from, w.wave_height, w.wave_from, f"{path}: weather"
            )
        self.courses = [self.course(t, i) for i, t in enumerate(scenario.targets)]

    def point(self, p, where: str) -> tuple[float, float]:
        if isinstance(p, dict):
            if self.crs is None:
                raise UsvError(f"{self.path}: {where}: lon/lat needs a map with a CRS")
            x, y = geodesy.lonlat_to_map(self.crs, p["lon"], p["lat"])
            return float(x), float(y)
        return float(p[0]), float(p[1])

    def course(self, t, i: int) -> target_motion.Course:
        where = f"targets[{i}]"
        track = None
        if t.track is not None:
            to_map = (lambda lon, lat: geodesy.lonlat_to_map(self.crs, lon, lat)) \
                if self.crs is not None else None  # fmt: skip
            with _naming(self.path, f"{where}.track"):
                try:
                    times, xy, _ = target_motion.read_track(t.track, to_map)
                except UnicodeDecodeError as exc:
                    raise UsvError(f"{t.track}: not UTF-8 text ({exc.reason} at byte "
                                   f"{exc.start})") from None  # fmt: skip
            track = (times, xy)
        waypoints = None
        if t.waypoints is not None:
            waypoints = np.array([self.point(p, f"{where}.waypoints") for p in t.waypoints])
        return target_motion.Course(
            start=np.array(self.point(t.start, f"{where}.start")) if t.start is not None else None,
            heading=float(angles.compass_to_math(t.heading)),
            speed=t.speed,
            waypoints=waypoints,
            track=track,
            heading_sd=np.radians(t.heading_sd),
            speed_sd=t.speed_sd,
        )


@contextlib.contextmanager
def _naming(path, where: str):
    """Prefix a :class:`UsvError` raised in the block with the scenario and its field."""
    try:
        yield
    except UsvError as exc:
        raise UsvError(f"{path}: {where}: {exc}") from None


def _collision(setup: _Setup, x: float, y: float, ahead: np.ndarray,
               reach: np.ndarray) -> int | None:  # fmt: skip
    """-1 for the grid, the target's index for a target (the first whose centre is within
    ``reach``, half the sum of the lengths, of the own ship's ``(x, y)``), None when the own
    ship is clear."""
    if len(reach):
        touching = _tracking_kernels().first_touching(ahead, x, y, reach)  # compiled
        if touching >= 0:
            return touching
    if setup.grid is not None:
        # Grid.contains and Grid.cell_of in floats, the grid's bounds taken once (_Setup.box):
        # the same comparisons and quotients, without their NumPy scalars and properties
        left, bottom, right, top, size, cells, obstacle = setup.box
        if not (left <= x < right and bottom < y <= top):
            return -1
        if cells[math.floor((top - y) / size), math.floor((x - left) / size)] == obstacle:
            return -1
    return None


@functools.cache
def _tracking_kernels():
    """:mod:`usvtool.sim.tracking_kernels`, imported at the first call (numba's import: a
    run's) and then at the cost of a cached call, not an import's, every step."""
    from usvtool.sim import tracking_kernels

    return tracking_kernels


def _name(scenario: Scenario, index: int) -> str:
    return "map" if index == -1 else scenario.targets[index].name


def _result(scenario, setup, opts, controller, voyage: Voyage, failed: str | None,
            step_time: float) -> SimResult:  # fmt: skip
    """The trace (the targets' yaw rates from their courses), the COLREGs evaluation and the
    figures; ``failed``: why the controller failed, None when it did not."""
    lengths = voyage.lengths
    controller_events, collision, arrived = voyage.events, voyage.collision, voyage.arrived
    dt = scenario.sim.dt
    trace = voyage.trace()
    times, x, y, names = trace.t, trace.x, trace.y, list(trace.ships)
    rule2 = [e for e in controller_events if e["kind"] == "rule2-departure"]
    evaluation = verdicts.evaluate(trace, [setup.vessel.length, *lengths], rule2)
    track = np.column_stack([x[:, 0], y[:, 0]])
    sampled = measures.track_samples(track, dt)
    figures = {
        "scenario": scenario.name,
        "controller": controller.name,
        "parameters": controller.params,
        "seed": opts.seed,
        "arrived": bool(arrived),
        "collision": None if collision is None else _name(scenario, collision),
        "controller_failed": failed,
        "time_s": round(float(times[-1]), 3),
        "path_length_m": round(float(measures.path_length(track)), 3),
        "turns": int(measures.turns(sampled)),
        "mot": round(float(measures.mot(sampled)), 6),
        "step_time_ms": round(step_time * 1e3, 4),
        **evaluation["figures"],
        "per_target": [
            _per_target(j, names[1 + j], evaluation["events"], times, x, y)
            for j in range(len(names) - 1)
        ],
    }
    events = {
        "scenario": scenario.name,
        "controller": controller.name,
        "steps": controller_events,
        "encounters": evaluation["events"],
        "thresholds": evaluation["thresholds"],
        "unmatched_rule2": evaluation["unmatched_rule2"],
        "run": {
            "scenario": scenario.name,
            "controller": controller.name,
            "parameters": controller.params,
            "seed": opts.seed,
            "arrived": figures["arrived"],
            "collision": figures["collision"],
            "controller_failed": failed,
            "time_s": figures["time_s"],
            "dt": float(dt),
            "goal": [float(v) for v in setup.goal],
            "goal_tolerance": float(scenario.sim.goal_tolerance),
            "own_length": float(setup.vessel.length),
            "vessel": setup.vessel.user_units(),
            "domain_intrusion_s": figures["domain_intrusion_s"],
            **scenario_facts(scenario, setup.vessel.length, opts.files_base),
        },
    }
    return SimResult(scenario, trace, events, figures, setup.crs)


def scenario_facts(scenario: Scenario, own_length: float, base: Path | None = None) -> dict:
    """The scenario as the run resolved it, for readers of its events (``usvtool metrics``,
    the report) that must not parse scenario YAML: its file, ``ships`` (name and length, in the
    trace's order, the own ship first), and the paths of its ``map``, ``route``, ``tracks``
    (per target, None when it sails a course) and ``wind_field`` (None when absent or
    uniform): absolute, or relative to ``base`` for a file below it.

    >>> from usvtool.sim.scenario import parse
    >>> s = parse({"name": "s", "own": {"start": [0, 0], "goal": [0, 9]}}, "/runs/a/s.yaml")
    >>> scenario_facts(s, 2.5, Path("/runs/a"))["scenario_file"], scenario_facts(s, 2.5)["map"]
    ('s.yaml', None)
    """

    def path(p) -> str | None:
        if p is None:
            return None
        p = Path(p).resolve()
        if base is not None and p.is_relative_to(base.resolve()):
            return p.relative_to(base.resolve()).as_posix()
        return str(p)

    weather = scenario.weather
    return {
        "scenario_file": path(scenario.path),
        "ships": [{"name": "own", "length": float(own_length)},
                  *({"name": t.name, "length": float(t.length)} for t in scenario.targets)],
        "map": path(scenario.map),
        "route": path(scenario.route),
        "tracks": [path(t.track) for t in scenario.targets],
        "wind_field": None if weather is None else path(weather.field),
        "duration_s": float(scenario.sim.duration),
        "vessel_preset": scenario.own.vessel,
    }  # fmt: skip


def _per_target(j: int, name: str, encounters: list[dict], times, x, y) -> dict:
    """The summary's entry for target ``j``: its closest distance and time over the whole run
    (from the trace), and the COLREGs figures of its closest encounter (the events JSON lists
    every encounter); ``compliant`` only when all its judged encounters are, ``rule2_departure``
    when any has one."""
    mine = [e for e in encounters if e["target"] == j]
    main = min(mine, key=lambda e: e["closest_distance_m"])
    gap = measures.target_distances(x[:, 0], y[:, 0], x[:, 1 + j], y[:, 1 + j])[:, 0]
    closest = int(np.argmin(gap))
    judged = [e["compliant"] for e in mine if e["compliant"] is not None]
    manoeuvre = main.get("first_manoeuvre") or {}
    return {
        "target": name,
        "class": main["class"],
        "encounters": sum(e["class"] != "none" for e in mine),
        "closest_distance_m": round(float(gap[closest]), 3),
        "cpa_time_s": round(float(times[closest]), 3),
        "passing_side": main["passing_side"],
        "first_manoeuvre_side": manoeuvre.get("side"),
        "rule2_departure": any(bool(e.get("rule2_departure")) for e in mine),
        "compliant": all(judged) if judged else None,
    }
