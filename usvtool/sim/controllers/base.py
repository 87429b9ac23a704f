"""The Dynamic Window Approach core that every controller shares, and the parts it is made of.

A controller is a composition, in the manner of Nav2's DWB: a *trajectory generator* (the
window strategy, :mod:`.windows`: one control period's window or the horizon's), named
*critics* each with a scale (:mod:`.critics`), a *side rule* (:mod:`.side_rule`) and the
*fallback* below. Each controller of the papers is a configuration of these parts
(docs/controllers.md); the core runs them. One control step, all velocity samples at once:

1. the generator samples the dynamic window: the vessel's limits (IWSO-DWA eq. 18) intersected
   with what its accelerations reach in one control period (eq. 19), or within the horizon
   (``window: horizon``), on a regular grid of ``v_samples`` x ``omega_samples`` pairs
   (:func:`usvtool.sim.vessel.samples`);
2. and rolls every pair out over ``horizon`` seconds in steps of ``step``: held at constant
   (v, omega) on exact arcs (eq. 16, :func:`usvtool.sim.vessel.arcs`), or ramping toward the
   pair at the limits (:func:`usvtool.sim.vessel.ramps`), the command then the ramp's first
   period;
3. the rollouts are checked against the grid's clearance field (:mod:`usvtool.clearance`: a
   contact where the clearance falls to the own ship's radius, half her length) and against
   every target's predicted positions (constant velocity; a contact where the centres come
   within half the sum of the two lengths), compiled (:mod:`usvtool.sim.rollout_kernels`;
   targets and horizon rows that cannot come within ``dist_max`` of a contact are skipped by a
   distance bound). A sample's *time to contact* is the first predicted time of either,
   infinite when there is none in the horizon. A sample is *admissible* (eq. 20,
   :func:`usvtool.sim.vessel.admissible`) when it can brake to a stop before its contact, the
   paper's "dist" read as Fox et al.'s distance along the trajectory to the contact;
4. each critic rewards every sample (larger is better); the rewards are normalised by their
   sums over the candidates (the UDWA paper's eqs. 2-4) and added with the critics' scales
   (eq. 1, eq. 21, eq. 25);
5. the candidates are the contact-free samples, less those the side rule removes (CCDWA), and,
   when some remain, less those that bring a target into the own ship's domain (the UDWA
   paper's 7 L x 3 L ellipse: "the predicted trajectory is discarded" within the safe
   distance) and, as the give-way ship of a crossing, less those that cross ahead of the target
   (Rule 15, which both papers name); a side preference (UDWA, gdwa) multiplies the preferred
   side's scores by ``1 + priority`` (with ``safe_priority``, only where the sample's
   clearance reaches ``dist_max``). The best candidate is taken.

No controller picks a sample with a contact while a contact-free one exists: when every sample
the side rule keeps meets a contact, the removed side's free samples are the candidates after
all, and the step logs a ``side-rule-overridden`` event (CCDWA stays rigid until then: it turns
away from its side only once that side holds no free sample within the horizon). When every
sample has one, the fallback takes, in order: an admissible one (it can still stop), the
longest time to contact, the most starboard yaw rate, the lowest speed (COLREGs Rules 8 and
17(b): a clear turn to starboard and slowing), and logs an ``all-samples-collide`` event with the
number of samples each check rejected, the way Nav2's DWB reports which critic rejected the
trajectories.

Angles inside are mathematical radians (counter-clockwise from east); a positive yaw rate turns
to port (:mod:`usvtool.sim.sides`).
"""

from __future__ import annotations

import functools
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from usvtool.encounter import domain_semi_axes
from usvtool.errors import UsvError
from usvtool.params import NON_NEGATIVE, POSITIVE, Param, Range, View, check, declared, defaults
from usvtool.sim import sides as side_rules
from usvtool.sim import vessel as vessel_model
from usvtool.sim.controllers.critics import Critic
from usvtool.sim.controllers.side_rule import SideRule
from usvtool.sim.controllers.windows import WINDOWS

#: Seconds between the rollout points at which the ship domain is checked (a target moves a
#: few metres in that time, the domain is 7 ship lengths long).
DOMAIN_EVERY = 0.5


class ControllerFailed(UsvError):
    """A controller could not decide (a process that crashed, replied late, garbage or out of
    the vessel's limits): the run ends there as ``controller failed``, a failure."""


@dataclass(frozen=True)
class World:
    """What a controller knows for a whole run."""

    vessel: vessel_model.Vessel
    goal: np.ndarray  # (2,) map metres
    clearance: object | None = None  # usvtool.clearance.Clearance, or None on open water
    route: np.ndarray | None = None  # (m, 2) the global route, start to goal
    weather: object | None = None  # a usvtool.sim.weather.Weather, or None for calm water
    period: float = 0.1  # control period (s)
    goal_tolerance: float = 0.0  # m: a rollout passing this close to the goal reaches it
    seed: int = 0  # the run's seed (--seed), for a controller that draws (a process's hello)
    map_file: object | None = None  # the map's file (a Path), for a controller that reads it
    # itself: a process (docs/protocol.md), which has no access to this process's grid


@dataclass(frozen=True)
class Own:
    """The own ship's state: position (m), heading (rad), speed (m/s), yaw rate (rad/s)."""

    x: float
    y: float
    psi: float
    v: float
    omega: float


@dataclass(frozen=True)
class Targets:
    """The targets as the own ship sees them: positions (k, 2), velocities (k, 2), lengths (k,)."""

    pos: np.ndarray
    vel: np.ndarray
    length: np.ndarray

    @classmethod
    def none(cls) -> Targets:
        return cls(np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0))


@dataclass(frozen=True)
class Encounter:
    """The encounter that sets the side rule: its COLREGs class and the target's index."""

    cls: str
    target: int


@dataclass
class Decision:
    """The velocity pair taken, and the events of the step (empty for most steps)."""

    v: float
    omega: float
    events: list[dict] = field(default_factory=list)


@dataclass
class Rollouts:
    """The velocity samples of one step and what the core computed for them; the headings and
    the final positions are worked out when a critic first asks for them (most use none)."""

    v: np.ndarray  # (N,)
    omega: np.ndarray  # (N,)
    contact: np.ndarray  # (N,) time to the first contact, inf when none
    static_hit: np.ndarray  # (N,) bool: the first contact is with the grid
    clearance: np.ndarray  # (N,) smallest distance to anything over the horizon (m): exact
    # below dist_max, at least dist_max elsewhere (what lies farther is not measured)
    intrudes: np.ndarray  # (N,) bool: some target enters the own ship's domain
    x: np.ndarray  # (T, N) the predicted positions, east
    y: np.ndarray  # (T, N) and north
    reached: np.ndarray  # (N,) bool: the rollout passes within the goal tolerance of the goal
    to_goal: np.ndarray  # (N,) the squared distance from the rollout's closest point to the goal
    near: np.ndarray  # (N,) complex: the rollout's point closest to the goal
    near_time: np.ndarray  # (N,) the time it is reached (s)
    horizon: float  # the last rollout time (s)
    own: Own  # the own ship's state they start from
    generator: object  # the trajectory generator that made them (.windows)

    def heading(self, t) -> np.ndarray:
        """The headings at times ``t``, unwrapped (the generator's)."""
        return self.generator.heading(self.own, self.omega, t)

    @cached_property
    def end(self) -> np.ndarray:
        """(N,) complex: the predicted final positions x + iy."""
        return self.x[-1] + 1j * self.y[-1]

    @cached_property
    def psi_end(self) -> np.ndarray:
        """(N,) the predicted final headings (rad, in [-pi, pi)):
        :func:`usvtool.angles.wrap_pi`'s, compiled
        (:func:`usvtool.sim.rollout_kernels.wrap_angles`)."""
        return _kernels().wrap_angles(np.ascontiguousarray(self.heading(self.horizon), float))

    @cached_property
    def psi_near(self) -> np.ndarray:
        """(N,) the heading at :attr:`near` (rad)."""
        return self.heading(self.near_time)


class Controller(ABC):
    """What the simulator asks of a controller, whatever it is made of: :meth:`reset` at the
    start of a run with its :class:`World`, then each control period :meth:`decide` with the own
    ship's state, the targets as she sees them and the encounter that sets the side rule, for a
    :class:`Decision` within the vessel's limits (the simulator applies it as given); and
    :meth:`close` when the run ends, however it ends.

    ``name``: unique in :data:`usvtool.sim.controllers.CONTROLLERS`; ``parameters``: its
    parameters (keyword arguments), a :class:`usvtool.params.Param` each (or a plain default),
    added to its base classes' (:meth:`declarations`); a parameter it has not got or a value
    its declaration does not take is refused here (:func:`usvtool.params.check`), and before,
    naming where it was given, by :func:`usvtool.sim.scenario.controller_params`.
    """

    name: str = ""
    parameters: dict[str, Param] = {}
    #: The older attribute, read from :meth:`declarations` (name -> default).
    defaults = View(defaults)

    def __init__(self, **params):
        self.params = check(self.declarations(), params, str, self.name, complete=True)
        self.world: World | None = None

    @classmethod
    def declarations(cls) -> dict[str, Param]:
        """Its parameters: ``parameters`` (and the older ``common`` and ``defaults``) of each
        class from :class:`Controller` down (:func:`usvtool.params.declared`)."""
        return declared(cls, ("common", "defaults", "parameters"))

    def reset(self, world: World) -> None:
        """Start a run in ``world``."""
        self.world = world

    @abstractmethod
    def decide(self, own: Own, targets: Targets, encounter: Encounter | None = None) -> Decision:
        """The velocity pair for the next control period."""

    def close(self) -> None:  # noqa: B027 (a hook: most controllers hold nothing to let go)
        """The run has ended (arrived, collided, failed or out of time): let go of what
        :meth:`reset` took (a process, a file)."""

    def memory_parts(self) -> list[tuple[int, str, str]]:
        """(bytes, what, remedy) of what one decision holds at once beyond the run's trace
        (:func:`usvtool.sim.memory.run_parts`); none by default."""
        return []

    def log(self) -> str | None:
        """What the controller wrote for people to read during its last run (a process's
        standard error), once :meth:`close` has run; None for one that writes nothing (the
        default). ``usvtool simulate`` writes it to ``--controller-log`` or on its stderr."""
        return None


class DynamicWindow(Controller):
    """A DWA controller: a trajectory generator, critics with scales, a side rule, the fallback.

    Parameters common to all (:attr:`parameters`, each controller adding its own and changing
    these defaults): ``horizon`` (s), ``step`` (s, the rollout's time step), ``v_samples`` and
    ``omega_samples`` (the window's grid), ``window`` (the generator:
    :data:`~usvtool.sim.controllers.windows.WINDOWS`), ``dist_max`` (m, the clearance term's
    cap), ``weather`` (use the attainable speed of UDWA eq. 5 in the velocity term), ``sides``
    (a table of :mod:`usvtool.sim.sides`, or ``none``), ``priority`` (the preferred side's score
    bonus, for the controllers that prefer rather than remove), ``safe_priority`` (the bonus
    only for samples whose clearance reaches ``dist_max``) and ``domain`` (keep the targets out
    of the own ship's domain when some sample can). A controller names its critics
    (:meth:`critics`) and whether its side rule removes the other side (``removes_side``).
    """

    parameters = {
        "horizon": Param(10.0, "the rollouts' horizon, s", POSITIVE),
        "step": Param(0.2, "the rollouts' time step, s", POSITIVE),
        "v_samples": Param(21, "speeds in the dynamic window's grid", Range(2)),
        "omega_samples": Param(21, "yaw rates in the dynamic window's grid", Range(2)),
        "dist_max": Param(30.0, "the clearance critic's cap, m", POSITIVE),
        "weather": Param(False, "score the speed made good in the wind and waves (UDWA eq. 5)"),
        "sides": Param("none", "the side table of an encounter (usvtool.sim.sides)",
                       choices=("none", *side_rules.TABLES)),
        "priority": Param(0.0, "the preferred side's score bonus", NON_NEGATIVE),
        "domain": Param(True, "keep the targets out of the own ship's domain when one can"),
        "window": Param("period", "the trajectory generator", choices=tuple(WINDOWS)),
        "safe_priority": Param(False, "the side bonus only where the clearance reaches "
                                      "dist_max"),
    }  # fmt: skip
    removes_side = False  # CCDWA removes the other side; the others prefer

    def __init__(self, **params):
        super().__init__(**params)
        p = self.params
        self.times = p["step"] * np.arange(1, int(round(p["horizon"] / p["step"])) + 1)
        if not self.times.size:
            raise UsvError(f"{self.name}: horizon ({p['horizon']}) must be at least half a step "
                           f"({p['step']})")  # fmt: skip
        self.objective = self.critics()
        self.side_rule = SideRule(p["sides"], self.removes_side, p["priority"],
                                  p["safe_priority"], p["dist_max"])  # fmt: skip

    @abstractmethod
    def critics(self) -> list[Critic]:
        """The terms of the objective, each with its scale (:mod:`.critics`)."""

    def reset(self, world: World) -> None:
        """Start a run in ``world`` (and load the compiled kernels, numba's start-up, here rather
        than in the run's first step)."""
        from usvtool.lazy_kernels import load
        from usvtool.sim import rollout_kernels

        super().reset(world)
        self.kernels = rollout_kernels
        self._horizon = float(self.times[-1])
        self._scales = np.array([critic.scale for critic in self.objective], float)
        self.generator = WINDOWS[self.params["window"]](world, self.times)
        load(rollout_kernels, *self.generator.kernels, *_STEP_KERNELS)
        for critic in self.objective:
            critic.reset(world)
        p, length = self.params, float(world.vessel.length)
        if world.clearance is not None:
            grid = world.clearance.grid
            left, _, _, top = grid.bounds
            field = (world.clearance.padded, grid.width, float(left), float(top),
                     1.0 / grid.cell_size, float(grid.cell_size))  # fmt: skip
        else:
            field = (_OPEN_WATER, 0, 0.0, 0.0, 1.0, 1.0)
        along, across = domain_semi_axes(length)
        # the domain, a soft rule, is looked at every DOMAIN_EVERY seconds of the horizon
        every = max(1, int(round(DOMAIN_EVERY / p["step"]))) if p["domain"] else 0
        #: the checks' constants of the run (rollout_kernels.contacts)
        self._checks = (*field, length, every, float(along), float(across),
                        along * along * (1 + 1e-9), float(p["dist_max"]))  # fmt: skip
        self._n_v, self._n_omega = int(p["v_samples"]), int(p["omega_samples"])
        self._goal = float(world.goal[0]), float(world.goal[1])
        self._reach2 = world.goal_tolerance**2  # a rollout within it reaches the goal

    def memory_parts(self) -> list[tuple[int, str, str]]:
        """Its rollouts: (v_samples + 1) x (omega_samples + 2) samples (the window's grid, with
        the generator's extra pairs) over the horizon (:mod:`usvtool.sim.memory`)."""
        from usvtool.sim.memory import POINT_BYTES, SAMPLE_BYTES

        n_v = int(self.params["v_samples"]) + 1
        n_omega = int(self.params["omega_samples"]) + 2
        horizon = self.times.size
        return [(n_v * n_omega * (horizon * POINT_BYTES + SAMPLE_BYTES),
                 f"its rollouts: {n_v} x {n_omega} samples x {horizon} horizon steps",
                 "lower v_samples and omega_samples (--param) or the horizon")]  # fmt: skip

    # -- the core --------------------------------------------------------------------------

    def decide(self, own: Own, targets: Targets, encounter: Encounter | None = None) -> Decision:
        """The velocity pair for the next control period."""
        r = self.rollouts(own, targets)
        rule = self.side_rule
        side = rule.side(encounter)
        removed = rule.removed(side, r.omega)
        # the contact-free samples less the removed ones, and less those that bring a target
        # into the domain when one can keep them out (compiled: rollout_kernels.candidates)
        free, candidates = self.kernels.candidates(r.contact, removed, r.intrudes)
        if encounter is not None and encounter.cls == "crossing-give-way" and side:
            astern = ~self._crosses_ahead(own, r, targets, encounter.target)
            if np.count_nonzero(candidates & astern):  # Rule 15: pass astern when one can
                candidates &= astern
        events = []
        some = np.count_nonzero(candidates) > 0  # ndarray.any's wrapper costs more
        if not some and np.count_nonzero(free):  # safety first: the removed side after all
            candidates, some = free, True
            events.append(rule.overridden(side, self.times[-1]))
        if not some:
            return self._fallback(own, r, removed)
        score = rule.favour(side, r, self.score(own, r, candidates))
        score = np.where(candidates, score, -np.inf)
        best = int(np.argmax(score))
        decision = self._command(own, r, best, events)
        if side != side_rules.EITHER and np.sign(r.omega[best]) == -side and not events:
            decision.events.append(rule.departure(encounter, side, r, score, free))
        return decision

    def _command(self, own: Own, r: Rollouts, best: int, events: list[dict]) -> Decision:
        """The velocity pair for the next period from sample ``best``, as the generator
        commands it."""
        v, omega = self.generator.command(own, float(r.v[best]), float(r.omega[best]))
        return Decision(v, omega, events)

    def _crosses_ahead(self, own: Own, r: Rollouts, targets: Targets, j: int) -> np.ndarray:
        """(N,) bool: the rollout crosses target ``j``'s course line ahead of her (the side of
        her line the own ship is on changes while she is ahead of the target's bow)."""
        vel = targets.vel[j]
        speed = float(np.hypot(*vel))
        if speed < 1e-9:
            return np.zeros(r.v.size, bool)
        hx, hy = vel / speed
        now = hx * (own.y - targets.pos[j, 1]) - hy * (own.x - targets.pos[j, 0])
        return self.kernels.crosses_ahead(r.x, r.y, self.times, float(targets.pos[j, 0]),
                             float(targets.pos[j, 1]), float(vel[0]), float(vel[1]), float(hx),
                             float(hy), float(now))  # fmt: skip

    def rollouts(self, own: Own, targets: Targets) -> Rollouts:
        """Sample the window, roll every sample out and find its contacts."""
        generator = self.generator
        # the window, its fan (x, y: (T, N)), the contacts and the points closest to the goal,
        # in one compiled call for the period window (rollout_kernels.period_sweep)
        v, omega, x, y, contact, static_first, clearance, intrudes, row, to_goal, near = \
            generator.sweep(own, self._n_v, self._n_omega,
                            (_rows(targets.pos), _rows(targets.vel),
                             np.ascontiguousarray(targets.length, float)),
                            self._checks, self._goal)  # fmt: skip
        reached = to_goal <= self._reach2
        return Rollouts(v, omega, contact, static_first, clearance, intrudes, x, y, reached,
                        to_goal, near, self.times[row], self._horizon, own,
                        generator)  # fmt: skip

    def score(self, own: Own, r: Rollouts, candidates: np.ndarray) -> np.ndarray:
        """The sum of the critics' normalised rewards (eqs. 2-4) times their scales, over
        ``candidates``: :func:`normalise` of every critic at once, the sums NumPy's (a row's
        sum along the rows' axis is the row's own), the rest compiled
        (:func:`usvtool.sim.rollout_kernels.weighted_shares`)."""
        rewards = np.empty((len(self.objective), r.v.size))
        for i, critic in enumerate(self.objective):
            rewards[i] = critic.reward(own, r)
        shares = np.where(candidates, rewards, 0.0)
        return self.kernels.weighted_shares(shares, shares.sum(axis=1), self._scales)

    # -- when no sample is free ------------------------------------------------------------

    def _fallback(self, own: Own, r: Rollouts, removed: np.ndarray) -> Decision:
        admissible = vessel_model.admissible(r.v, r.omega, self.generator.run(own, r.v, r.contact),
                                             self.world.vessel)  # fmt: skip
        # np.lexsort sorts by the last key first: admissible, contact time, starboard, slow
        order = np.lexsort((r.v, r.omega, -r.contact, ~admissible))
        best = int(order[0])
        event = {
            "kind": "all-samples-collide",
            "samples": int(r.v.size),
            "rejected": {
                "grid": int(np.count_nonzero(r.static_hit)),
                "targets": int(np.count_nonzero(np.isfinite(r.contact) & ~r.static_hit)),
                "side": int(np.count_nonzero(removed & ~np.isfinite(r.contact))),
            },
            "admissible": int(np.count_nonzero(admissible)),
            "contact_s": round(float(r.contact[best]), 3),
        }
        return self._command(own, r, best, [event])


#: The kernels of a step besides the window's, loaded at a reset (the critics', the side rule's
#: and gdwa's included: a few ms each).
_STEP_KERNELS = ("candidates", "weighted_shares", "heading_reward", "offsets", "favour",
                 "wrap_angles")  # fmt: skip


@functools.cache
def _kernels():
    """:mod:`usvtool.sim.rollout_kernels`, imported at the first call (numba's import: a run's,
    not the command line's) and then at the cost of a cached call, not an import's."""
    from usvtool.sim import rollout_kernels

    return rollout_kernels


#: The clearance field of open water: none (the kernel looks nothing up in an empty field).
_OPEN_WATER = np.zeros(0)


def _rows(a: np.ndarray) -> np.ndarray:
    """``a`` as a C-ordered float array of (x, y) rows (no copy when it is one)."""
    return np.ascontiguousarray(a, float).reshape(-1, 2)


def normalise(values: np.ndarray, candidates: np.ndarray) -> np.ndarray:
    """Each candidate's share of the term's sum over the candidates (UDWA eqs. 2-4); zero for
    the others, and for every sample when the sum is zero.

    >>> normalise(np.array([1.0, 3.0, 5.0]), np.array([True, True, False])).tolist()
    [0.25, 0.75, 0.0]
    """
    values = np.where(candidates, values, 0.0)
    total = values.sum()
    return values / total if total > 0 else np.zeros_like(values)
