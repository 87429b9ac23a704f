"""The Dynamic Window Approach core that every controller shares.

One control step, all velocity samples at once (no per-sample Python loop):

1. the dynamic window: the vessel's limits (IWSO-DWA eq. 18) intersected with what its
   accelerations reach in one control period (eq. 19), sampled on a regular grid of
   ``v_samples`` x ``omega_samples`` pairs (:func:`usvtool.sim.vessel.samples`);
2. every pair is rolled out at constant (v, omega) over ``horizon`` seconds in steps of
   ``step`` (eq. 16, :func:`usvtool.sim.vessel.arcs`). With ``window: horizon`` (the variant
   ``udwa+``) the window is what the accelerations reach within the horizon, each rollout
   ramps toward its pair at the limits (:func:`usvtool.sim.vessel.ramps`), and the command is
   the ramp's first period;
3. the rollouts are checked against the grid's clearance field (:mod:`usvtool.clearance`: a
   contact where the clearance falls to the own ship's radius, half her length) and against
   every target's predicted positions (constant velocity; a contact where the centres come
   within half the sum of the two lengths). A sample's *time to contact* is the first predicted
   time of either, infinite when there is none in the horizon. A sample is *admissible* (eq. 20,
   :func:`usvtool.sim.vessel.admissible`) when it can brake to a stop before its contact, the
   paper's "dist" read as Fox et al.'s distance along the trajectory to the contact;
4. the controller's terms are computed for each sample, each normalised by its sum over the
   candidates (the UDWA paper's eqs. 2-4) and combined with the controller's weights (eq. 1,
   eq. 21, eq. 25); every term is a reward (larger is better);
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
sample has one, the controller takes, in order: an admissible one (it can still stop), the
longest time to contact, the most starboard yaw rate, the lowest speed (COLREGs Rules 8 and
17(b): a clear turn to starboard and slowing), and logs an ``all-samples-collide`` event with the
number of samples each check rejected, the way Nav2's DWB reports which critic rejected the
trajectories.

Angles inside are mathematical radians (counter-clockwise from east); a positive yaw rate turns
to port (:mod:`usvtool.sim.sides`).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import numpy as np

from usvtool.angles import wrap_pi
from usvtool.encounter import domain_ellipse, domain_semi_axes
from usvtool.errors import UsvError
from usvtool.sim import sides as side_rules
from usvtool.sim import vessel as vessel_model

#: The dynamic windows: ``period``, what one control period's accelerations reach, every sample
#: held from now on (IWSO-DWA eq. 19 with the control period, Fox et al. 1997); ``horizon``,
#: what they reach within the horizon, each sample approached at the limits and then held
#: (trajectory rollout, Gerkey and Konolige 2008: :func:`usvtool.sim.vessel.ramps`).
WINDOWS = ("period", "horizon")

#: Seconds between the rollout points at which the ship domain is checked (a target moves a
#: few metres in that time, the domain is 7 ship lengths long).
DOMAIN_EVERY = 0.5


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
    """The velocity samples of one step and what the core computed for them."""

    v: np.ndarray  # (N,)
    omega: np.ndarray  # (N,)
    end: np.ndarray  # (N,) complex: the predicted final positions x + iy
    psi_end: np.ndarray  # (N,) the predicted final headings (rad)
    contact: np.ndarray  # (N,) time to the first contact, inf when none
    static_hit: np.ndarray  # (N,) bool: the first contact is with the grid
    clearance: np.ndarray  # (N,) smallest distance to anything over the horizon (m)
    intrudes: np.ndarray  # (N,) bool: some target enters the own ship's domain
    x: np.ndarray  # (T, N) the predicted positions, east
    y: np.ndarray  # (T, N) and north
    reached: np.ndarray  # (N,) bool: the rollout passes within the goal tolerance of the goal
    near: np.ndarray  # (N,) complex: the rollout's point closest to the goal
    psi_near: np.ndarray  # (N,) the heading there (rad)


class Controller(ABC):
    """A DWA controller: the core above, its terms and weights, and its side rule.

    Parameters common to all (keyword arguments, each controller adding its own ``defaults``):
    ``horizon`` (s), ``step`` (s, the rollout's time step), ``v_samples`` and
    ``omega_samples`` (the window's grid), ``dist_max`` (m, the clearance term's cap),
    ``weather`` (use the attainable speed of UDWA eq. 5 in the velocity term), ``sides`` (a
    table of :mod:`usvtool.sim.sides`, or ``none``), ``priority`` (the preferred side's score
    bonus, for the controllers that prefer rather than remove), ``safe_priority`` (the bonus
    only for samples whose clearance reaches ``dist_max``), ``domain`` (keep the targets out
    of the own ship's domain when some sample can) and ``window`` (:data:`WINDOWS`).
    """

    name: str = ""
    common: dict = {
        "horizon": 10.0,
        "step": 0.2,
        "v_samples": 21,
        "omega_samples": 21,
        "dist_max": 30.0,
        "weather": False,
        "sides": "none",
        "priority": 0.0,
        "domain": True,
        "window": "period",
        "safe_priority": False,
    }
    defaults: dict = {}
    removes_side = False  # CCDWA removes the other side; the others prefer

    def __init__(self, **params):
        options = {**self.common, **self.defaults}
        unknown = set(params) - set(options)
        if unknown:
            known = ", ".join(sorted(options))
            raise UsvError(f"{self.name}: unknown parameter(s) {sorted(unknown)} (known: {known})")
        self.params = {**options, **params}
        p = self.params
        for key in ("horizon", "step", "dist_max"):
            if not p[key] > 0:
                raise UsvError(f"{self.name}: {key} must be > 0, not {p[key]}")
        for key in ("v_samples", "omega_samples"):
            if int(p[key]) != p[key] or p[key] < 2:
                raise UsvError(f"{self.name}: {key} must be an integer >= 2, not {p[key]}")
        if p["sides"] != "none" and p["sides"] not in side_rules.TABLES:
            known = ", ".join(["none", *side_rules.TABLES])
            raise UsvError(f"{self.name}: unknown sides {p['sides']!r} (known: {known})")
        if p["window"] not in WINDOWS:
            raise UsvError(f"{self.name}: window must be one of {', '.join(WINDOWS)}, "
                           f"not {p['window']!r}")  # fmt: skip
        if not p["priority"] >= 0:
            raise UsvError(f"{self.name}: priority must be >= 0, not {p['priority']}")
        self.times = p["step"] * np.arange(1, int(round(p["horizon"] / p["step"])) + 1)
        self.world: World | None = None

    def reset(self, world: World) -> None:
        """Start a run in ``world``."""
        self.world = world

    # -- the core --------------------------------------------------------------------------

    def decide(self, own: Own, targets: Targets, encounter: Encounter | None = None) -> Decision:
        """The velocity pair for the next control period."""
        r = self.rollouts(own, targets)
        side = self.side(encounter)
        free = ~np.isfinite(r.contact)
        removed = np.zeros_like(free)
        if side != side_rules.EITHER and self.removes_side:
            removed = np.sign(r.omega) == -side
        candidates = free & ~removed
        if (candidates & ~r.intrudes).any():  # keep the targets out of the domain when one can
            candidates &= ~r.intrudes
        if encounter is not None and encounter.cls == "crossing-give-way" and side:
            astern = ~self._crosses_ahead(own, r, targets, encounter.target)
            if (candidates & astern).any():  # Rule 15: and pass astern of her when one can
                candidates &= astern
        events = []
        if not candidates.any() and free.any():  # safety first: the removed side after all
            candidates = free
            events.append({
                "kind": "side-rule-overridden",
                "preferred": side_rules.NAMES[side],
                "reason": f"every {side_rules.NAMES[side]} sample meets a contact within "
                f"{self.times[-1]:g} s",
            })  # fmt: skip
        if not candidates.any():
            return self._fallback(own, r, removed)
        score = self.score(own, r, candidates)
        if side != side_rules.EITHER and self.params["priority"] > 0:
            bonus = np.sign(r.omega) == side
            if self.params["safe_priority"]:  # only where no target or shore comes near
                bonus &= r.clearance >= self.params["dist_max"]
            score = np.where(bonus, score * (1 + self.params["priority"]), score)
        score = np.where(candidates, score, -np.inf)
        best = int(np.argmax(score))
        decision = self._command(own, r, best, events)
        if side != side_rules.EITHER and np.sign(r.omega[best]) == -side and not events:
            decision.events.append(self._departure(encounter, side, r, score, free))
        return decision

    def _command(self, own: Own, r: Rollouts, best: int, events: list[dict]) -> Decision:
        """The velocity pair for the next period from sample ``best``: the sample itself (a
        ``period`` window holds only what one period reaches), or, with a ``horizon`` window,
        the first period of the ramp toward it."""
        v, omega = float(r.v[best]), float(r.omega[best])
        if self.params["window"] == "horizon":
            vessel, dt = self.world.vessel, self.world.period
            v = float(vessel_model.toward(own.v, v, vessel.max_decel, vessel.max_accel, dt))
            omega = float(vessel_model.toward(own.omega, omega, vessel.max_yaw_accel,
                                              vessel.max_yaw_accel, dt))  # fmt: skip
        return Decision(v, omega, events)

    def _crosses_ahead(self, own: Own, r: Rollouts, targets: Targets, j: int) -> np.ndarray:
        """(N,) bool: the rollout crosses target ``j``'s course line ahead of her (the side of
        her line the own ship is on changes while she is ahead of the target's bow)."""
        vel = targets.vel[j]
        speed = float(np.hypot(*vel))
        if speed < 1e-9:
            return np.zeros(r.v.size, bool)
        hx, hy = vel / speed
        px = targets.pos[j, 0] + vel[0] * self.times
        py = targets.pos[j, 1] + vel[1] * self.times
        rx, ry = r.x - px[:, None], r.y - py[:, None]
        now = hx * (own.y - targets.pos[j, 1]) - hy * (own.x - targets.pos[j, 0])
        across = hx * ry - hy * rx
        return ((np.sign(across) != np.sign(now)) & (hx * rx + hy * ry > 0)).any(axis=0)

    def rollouts(self, own: Own, targets: Targets) -> Rollouts:
        """Sample the window, roll every sample out and find its contacts."""
        world, p = self.world, self.params
        vessel = world.vessel
        ramped = p["window"] == "horizon"
        span = self.times[-1] if ramped else world.period
        window = vessel_model.window(vessel, own.v, own.omega, span)
        speeds, rates = vessel_model.samples(
            window, int(p["v_samples"]), int(p["omega_samples"]), current=(own.v, own.omega)
        )
        v, omega = np.repeat(speeds, rates.size), np.tile(rates, speeds.size)
        if ramped:
            fan = vessel_model.ramps(own.x, own.y, own.psi, own.v, own.omega, speeds, rates,
                                     vessel, p["step"], len(self.times))  # fmt: skip
        else:
            fan = vessel_model.arcs(own.x, own.y, own.psi, speeds, rates, p["step"],
                                    len(self.times))  # fmt: skip
        radius = vessel.length / 2
        n, t = v.size, self.times.size
        x, y = fan.x, fan.y  # (T, N)
        # hit: (T, N) contacts, made only when some rollout has one (most steps have none)
        hit = static = None
        if world.clearance is not None:
            static_gap = world.clearance.at(x, y)
            static_gap -= radius
            clearance = static_gap.min(axis=0)
            if clearance.min() <= 0:
                static = static_gap <= 0
                hit = static.copy()
        else:
            clearance = np.full(n, np.inf)
        # one target at a time: (T, N) temporaries, small enough to stay in the allocator's
        # cache (fresh (k, T, N) arrays cost more in page faults than in arithmetic)
        ahead = targets.pos[:, None, :] + targets.vel[:, None, :] * self.times[:, None]
        intrudes = np.zeros(n, bool)
        a = domain_semi_axes(vessel.length)[0]  # the domain's longer semi-axis
        # the domain, a soft rule, is looked at every DOMAIN_EVERY seconds of the horizon
        rows = slice(None, None, max(1, int(round(DOMAIN_EVERY / p["step"]))))
        ux = uy = None  # each period's direction per sample, made when a domain test needs it
        for j, length in enumerate(targets.length):
            dx, dy = ahead[j, :, 0, None] - x, ahead[j, :, 1, None] - y
            d2 = np.square(dx)
            d2 += np.square(dy)
            closest2 = d2.min(axis=0)
            nearest2 = closest2.min()
            reach = (vessel.length + length) / 2
            if nearest2 <= reach * reach:
                touch = d2 <= reach * reach
                hit = touch if hit is None else np.logical_or(hit, touch, out=hit)
            np.minimum(clearance, np.sqrt(closest2) - reach, out=clearance)
            # the target in the own ship's domain, along and across her heading: never farther
            # than a (the margin keeps the skip clear of round-off in the ellipse's terms)
            if p["domain"] and nearest2 <= a * a * (1 + 1e-9):
                if ux is None:  # (T', N)
                    u = np.tile(fan.u[rows], speeds.size)
                    ux, uy = np.ascontiguousarray(u.real), np.ascontiguousarray(u.imag)
                inside = domain_ellipse(dx[rows], dy[rows], ux, uy, vessel.length) <= 1
                intrudes |= inside.any(axis=0)
        columns = np.arange(n)
        if hit is None:
            contact = np.full(n, np.inf)
            static_first = np.zeros(n, bool)
        else:
            first = np.where(hit.any(axis=0), hit.argmax(axis=0), t)
            at = np.minimum(first, t - 1)
            contact = np.where(first < t, self.times[at], np.inf)
            static_first = (first < t) & (static[at, columns] if static is not None else False)
        to_goal = np.square(x - world.goal[0])
        to_goal += np.square(y - world.goal[1])
        closest = to_goal.argmin(axis=0)
        reached = to_goal[closest, columns] <= world.goal_tolerance**2
        near = x[closest, columns] + 1j * y[closest, columns]
        if ramped:  # the heading turned while the yaw rate ramps toward the sample's
            yaw = vessel.max_yaw_accel
            psi_end = own.psi + vessel_model.travelled(own.omega, omega, yaw, yaw, self.times[-1])
            psi_end = wrap_pi(psi_end)
            psi_near = own.psi + vessel_model.travelled(own.omega, omega, yaw, yaw,
                                                        self.times[closest])  # fmt: skip
        else:
            psi_end = wrap_pi(own.psi + omega * self.times[-1])
            psi_near = own.psi + omega * self.times[closest]
        end = x[-1] + 1j * y[-1]
        return Rollouts(v, omega, end, psi_end, contact, static_first, clearance, intrudes, x, y,
                        reached, near, psi_near)  # fmt: skip

    def side(self, encounter: Encounter | None) -> int:
        """The side the rule asks for in ``encounter``."""
        table = self.params["sides"]
        if encounter is None or table == "none":
            return side_rules.EITHER
        return side_rules.side_for(table, encounter.cls)

    def score(self, own: Own, r: Rollouts, candidates: np.ndarray) -> np.ndarray:
        """The weighted sum of the normalised terms (eqs. 2-4), over ``candidates``."""
        total = np.zeros(r.v.size)
        for weight, values in self.terms(own, r):
            total += weight * normalise(values, candidates)
        return total

    @abstractmethod
    def terms(self, own: Own, r: Rollouts) -> list[tuple[float, np.ndarray]]:
        """(weight, reward per sample) of each term of the controller's objective."""

    # -- shared terms ----------------------------------------------------------------------

    def velocity(self, r: Rollouts) -> np.ndarray:
        """The speed term: the sampled speed, or with ``weather`` the speed it makes good in
        the wind and waves at the own ship (UDWA eq. 5) on the rollout's final heading."""
        world = self.world
        if not self.params["weather"] or world.weather is None:
            return r.v
        return world.weather.attainable_speed(
            r.v, r.psi_end, r.end.real, r.end.imag, world.vessel.deadweight
        )

    def distance(self, r: Rollouts) -> np.ndarray:
        """The clearance term: the smallest distance to the grid or a target over the horizon,
        capped at ``dist_max``."""
        return np.clip(r.clearance, 0.0, self.params["dist_max"])

    @staticmethod
    def heading(r: Rollouts, bearing: np.ndarray | float) -> np.ndarray:
        """The heading term: pi less the angle between the rollout's final heading and
        ``bearing`` (rad); pi for a rollout that reaches the goal (its end may lie beyond it,
        looking away)."""
        return np.where(r.reached, np.pi, np.pi - np.abs(wrap_pi(bearing - r.psi_end)))

    def toward_goal(self, r: Rollouts) -> np.ndarray:
        """Fox et al.'s heading term toward the goal, taken where the rollout comes closest to
        it (its end, unless it passes the goal on the way): pi less the angle between the
        heading there and the bearing from there to the goal; pi for a rollout that reaches the
        goal. Taken at the end, the rollouts of a ship near the goal end beyond it looking away,
        and the best score goes to turning back: with a 10 s horizon the ship circled the goal."""
        goal = self.world.goal[0] + 1j * self.world.goal[1]
        off = wrap_pi(np.angle(goal - r.near) - r.psi_near)
        return np.where(r.reached, np.pi, np.pi - np.abs(off))

    # -- when no sample is free ------------------------------------------------------------

    def _fallback(self, own: Own, r: Rollouts, removed: np.ndarray) -> Decision:
        vessel = self.world.vessel
        if self.params["window"] == "horizon":  # the distance run on the speed's ramp
            run = vessel_model.travelled(own.v, r.v, vessel.max_decel, vessel.max_accel,
                                         r.contact)  # fmt: skip
        else:
            run = r.v * r.contact
        admissible = vessel_model.admissible(r.v, r.omega, run, vessel)
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

    def _departure(self, encounter, side, r, score, free) -> dict:
        """A Rule 2 departure: the step turned away from the side the rule prefers."""
        own_side = np.sign(r.omega) == side
        if not (own_side & free).any():
            reason = f"every {side_rules.NAMES[side]} sample meets a contact within the horizon"
        else:
            best_own = float(np.max(np.where(own_side, score, -np.inf)))
            reason = (
                f"best {side_rules.NAMES[side]} score {best_own:.4g} below "
                f"{float(np.max(score)):.4g} on the other side"
            )
        return {
            "kind": "rule2-departure",
            "target": encounter.target,
            "class": encounter.cls,
            "preferred": side_rules.NAMES[side],
            "reason": reason,
        }


def normalise(values: np.ndarray, candidates: np.ndarray) -> np.ndarray:
    """Each candidate's share of the term's sum over the candidates (UDWA eqs. 2-4); zero for
    the others, and for every sample when the sum is zero.

    >>> normalise(np.array([1.0, 3.0, 5.0]), np.array([True, True, False])).tolist()
    [0.25, 0.75, 0.0]
    """
    values = np.where(candidates, values, 0.0)
    total = values.sum()
    return values / total if total > 0 else np.zeros_like(values)
