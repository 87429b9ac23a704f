"""``vo``: velocity obstacles with COLREGs constraints, after Kuwata, Wolf, Zarzhitsky and
Huntsberger, "Safe maritime autonomous navigation with COLREGS, using velocity obstacles", IEEE
Journal of Oceanic Engineering 39(1), 2014 (the paper, below). Not a DWA: it chooses a velocity
(a course and a speed) among candidates, and the course-and-speed autopilot
(:func:`usvtool.sim.controllers.process.autopilot`) turns it into the next period's (v, omega).

One control step, every candidate at once (numpy, no per-candidate loop):

1. **Preferred velocity** ``v_pref``: the full speed toward the sub-goal along the route (the
   route's next vertex not yet reached or passed, :class:`~.critics.RouteProgress`; the goal on
   open water without a route).
2. **Candidates** (the paper's discretised velocity space): ``speeds`` speeds x ``headings``
   courses, within what the vessel reaches in ``reach`` seconds (the speed by its
   accelerations, the course by its yaw rate and yaw acceleration, at most all round), plus
   the present velocity and ``v_pref`` when within reach.
3. **Velocity obstacles** (the paper's VO, in Fiorini and Shiller's form): for a target B of
   velocity ``v_B`` at ``p_B`` and the own ship A at ``p_A``, the VO is the set of ``v_A`` whose
   relative ray ``lambda(p_A, v_A - v_B) = {p_A + t (v_A - v_B), t >= 0}`` meets the disc of radius
   ``R`` about ``p_B`` (``B (+) -A``, both hulls as discs of half their lengths, plus a safety
   ``margin``): the collision cone of the relative position, shifted by ``v_B``. The paper treats
   only collisions that matter soon: the ray is cut at ``horizon`` seconds (a collision beyond it
   does not bar the velocity). The worst-case VO for a target velocity known to within
   ``uncertainty`` m/s (the union of the VOs of every ``v_B`` in that disc) is the VO grown by
   ``uncertainty`` in velocity space: ``|p - w t| <= R + u t`` for some ``t`` in ``[0, horizon]``,
   ``w = v_A - v_B``, ``p = p_B - p_A``, which is a quadratic in ``t`` solved for every candidate
   (:func:`first_contact`).
4. **COLREGs constraints** (the paper's section on COLREGs, its regions V1, V2, V3 about the
   VO): outside the VO, a velocity passes the target with her on the own ship's port side (V1:
   the relative velocity to the right of the line of sight, ``[p x w]_z < 0`` with ``z`` up),
   moves away (V2: ``p . w < 0``), or passes with her on the own ship's starboard side (V3:
   ``[p x w]_z > 0`` and ``p . w >= 0``, crossing ahead of a give-way target or turning to port
   in a head-on). In a head-on, a crossing where the own ship gives way and an overtaking
   (Rules 14, 15, 13) the constraint is ``v_A not in V3``. The entry conditions: the target's
   COLREGs class (:func:`usvtool.encounter.assess`, its sectors: docs/colregs.md) is one of
   those three and its CPA is close, ``0 < t_CPA <= colregs_time`` and ``d_CPA <=
   colregs_distance`` own ship lengths. The stand-on vessel (crossing from port, being
   overtaken) has no COLREGs constraint, only the VOs (the paper's hazard avoidance).
5. **Hysteresis**: a target's COLREGs mode, once entered, is kept for ``hold`` seconds after
   its entry conditions last held (the class is not re-read in that time), so a rule that
   flickers at a border (a d_CPA that grows as the own ship turns away) does not drop the
   constraint halfway through the manoeuvre and turn her back.
6. **Grounding** (on a grid): a candidate whose straight track over ``ground_time`` seconds
   meets a cell whose clearance (:mod:`usvtool.clearance`) is at most half the own ship's
   length is refused; per course the first such distance along the ray is found once, and every
   speed that runs that far within ``ground_time`` is refused.
7. **Selection**: the admissible candidates are those outside every VO, outside every
   constraint of step 4 and not grounding; the cost is the distance to the preferred velocity,
   ``|v_A - v_pref|`` (course and speed deviation together, in m/s), and the cheapest is
   taken. When none is admissible the COLREGs constraints go first (safety before the rules:
   an event ``colregs-dropped``); when still none, every non-grounding candidate is ranked by
   ``|v_A - v_pref| + w_time / t_c`` (``t_c`` its time to the first contact within the
   horizon), the penalty of an imminent contact (event ``all-candidates-in-vo``).

The readings where the paper leaves a figure or a detail open: docs/controllers.md, section
"vo". Only the paper's abstract and introduction could be read through the stored-text search:
no equation number is cited, and its own figures could not be checked
(docs/controllers.md says which figures are usvtool's and why). Angles inside are mathematical
radians (counter-clockwise from east), as everywhere in the controllers.
"""

from __future__ import annotations

import math

import numpy as np

from usvtool.encounter import (
    CROSSING_GIVE_WAY,
    HEAD_ON,
    NONE,
    OVERTAKING,
    classify_angles,
)
from usvtool.params import NON_NEGATIVE, POSITIVE, Param, Range
from usvtool.sim.controllers.base import Controller, Decision, Encounter, Own, Targets, World
from usvtool.sim.controllers.critics import RouteProgress
from usvtool.sim.controllers.process import autopilot

#: The classes whose COLREGs constraint the paper adds: head-on, crossing (give-way), overtaking.
CONSTRAINED = (HEAD_ON, CROSSING_GIVE_WAY, OVERTAKING)


def first_contact(p: np.ndarray, w: np.ndarray, radius: np.ndarray, spread: float,
                  horizon: float) -> np.ndarray:
    """(N, K) the first time in ``[0, horizon]`` at which ``|p_k - w_nk t| <= radius_k +
    spread t`` (the worst-case velocity obstacle of target ``k``: inside it when finite), inf
    when there is none. ``p``: (K, 2) relative positions (target minus own); ``w``: (N, K, 2)
    relative velocities (own minus target).

    >>> p = np.array([[100.0, 0.0]])
    >>> w = np.array([[[10.0, 0.0]], [[10.0, 1.0]], [[10.0, 2.0]], [[0.0, 10.0]]])
    >>> first_contact(p, w, np.array([10.0]), 0.0, 60.0)[:, 0].round(6).tolist()
    [9.0, 9.80198, inf, inf]
    """
    return _first_contact(p[:, 0], p[:, 1], w[..., 0], w[..., 1], radius, spread, horizon)


def _first_contact(px, py, wx, wy, radius, spread: float, horizon: float) -> np.ndarray:
    """:func:`first_contact` on the components (``px``, ``py``: (K,); ``wx``, ``wy``: (N, K)):
    the smaller root of ``(|w|^2 - u^2) t^2 - 2 (p.w + R u) t + |p|^2 - R^2 = 0``."""
    a = wx * wx + wy * wy - spread * spread
    half_b = px * wx + py * wy + radius * spread  # -b / 2
    c = px * px + py * py - radius * radius
    disc = half_b * half_b - a * c
    # a contact ahead: closing (hb > 0), or the spread outrunning the relative speed (a < 0:
    # the grown disc swallows the own ship in the end); its time is the smaller positive root,
    # c / (hb + sqrt(disc)) (accurate when a is small), whose denominator is then positive
    ok = (disc >= 0.0) & ((half_b > 0.0) | (a < 0.0))
    t = c / np.where(ok, half_b + np.sqrt(np.where(ok, disc, 0.0)), 1.0)
    t = np.where(ok & (t <= horizon), t, np.inf)
    return np.where(c <= 0.0, 0.0, t)  # already inside


def passes_to_port(p: np.ndarray, w: np.ndarray) -> np.ndarray:
    """(N, K) bool: region V3 of the paper about target ``k``: the relative velocity ``w`` is to
    the left of the line of sight ``p`` (``[p x w]_z > 0``) while closing (``p . w >= 0``), so
    the target would pass on the own ship's starboard side (she crosses ahead of it or turns to
    port of it).

    >>> p = np.array([[0.0, 100.0]])  # a target dead ahead (north)
    >>> passes_to_port(p, np.array([[[1.0, 10.0]], [[-1.0, 10.0]], [[-1.0, -10.0]]]))[:, 0].tolist()
    [False, True, False]
    """
    cross = p[:, 0] * w[..., 1] - p[:, 1] * w[..., 0]
    dot = p[:, 0] * w[..., 0] + p[:, 1] * w[..., 1]
    return (cross > 0.0) & (dot >= 0.0)


class VelocityObstacle(Controller):
    """Velocity obstacles with the COLREGs constraints of Kuwata et al. (2014): module docstring.

    Parameters: ``horizon`` (s, the VO's time cut), ``margin`` (own ship lengths added to the
    two half lengths), ``uncertainty`` (m/s, the worst-case VO's target speed error),
    ``colregs_time`` (s) and ``colregs_distance`` (own ship lengths: the entry conditions of a
    COLREGs mode), ``hold`` (s, the hysteresis), ``speeds`` and ``headings`` (the candidates),
    ``reach`` (s, the candidates' span), ``ground_time`` (s, the grounding look-ahead),
    ``w_time`` (m, the contact penalty of the fallback) and ``heading_gain`` (1/s, the
    autopilot's).
    """

    name = "vo"
    parameters = {
        "horizon": Param(30.0, "the velocity obstacles' time horizon, s", POSITIVE),
        "margin": Param(1.0, "the safety margin added to the two half lengths, own ship lengths",
                        NON_NEGATIVE),
        "uncertainty": Param(0.25, "the targets' velocity uncertainty of the worst-case VO, m/s",
                             NON_NEGATIVE),
        "colregs_time": Param(60.0, "a COLREGs mode's entry: time to CPA at most, s", POSITIVE),
        "colregs_distance": Param(4.0, "a COLREGs mode's entry: distance at CPA at most, own "
                                       "ship lengths", POSITIVE),
        "hold": Param(10.0, "the hysteresis: a COLREGs mode is kept this long after its entry "
                            "conditions last held, s", NON_NEGATIVE),
        "speeds": Param(7, "speeds among the candidates", Range(2)),
        "headings": Param(37, "courses among the candidates", Range(3)),
        "reach": Param(10.0, "the candidates span what the vessel reaches in this time, s",
                       POSITIVE),
        "ground_time": Param(10.0, "a candidate's straight track is checked against the grid "
                                   "this far ahead, s", POSITIVE),
        "w_time": Param(20.0, "the fallback's penalty of an imminent contact, m (/ t_c)",
                        NON_NEGATIVE),
        "heading_gain": Param(0.5, "the autopilot's proportional gain, 1/s", POSITIVE),
    }  # fmt: skip

    def reset(self, world: World) -> None:
        from usvtool.lazy_kernels import load
        from usvtool.sim import rollout_kernels  # numba's start-up: here, not in the first step

        super().reset(world)
        self.kernels = rollout_kernels
        load(rollout_kernels, "vo_candidates", "vo_contacts", "vo_near")
        p, ship = self.params, world.vessel
        self.progress = RouteProgress(None, float(p["reach"]))
        self.progress.reset(world)
        self.time = 0.0
        #: target index -> (COLREGs class code, the last time its entry conditions held)
        self.modes: dict[int, tuple[int, float]] = {}
        # the course change the vessel reaches in `reach` s from a steady course: yaw
        # acceleration up to the yaw rate, then the rate
        t, accel, rate = float(p["reach"]), ship.max_yaw_accel, ship.max_yaw_rate
        ramp = min(t, rate / accel)
        self.turn = min(math.pi, 0.5 * accel * ramp * ramp + rate * (t - ramp))
        n = int(p["headings"])
        full = self.turn >= math.pi
        # all round: n courses, -pi included and pi left out (the same course)
        offsets = np.linspace(-self.turn, self.turn, n + 1 if full else n)
        self.offsets = np.ascontiguousarray(offsets[:n])
        self.radius = 0.5 * ship.length
        if world.clearance is not None:
            # a point every cell (or every ship radius, when less): every cell the track
            # crosses lies within its threshold of some point
            step = min(float(world.clearance.grid.cell_size), self.radius)
            far = ship.max_speed * float(p["ground_time"])
            self.ray = np.arange(step, far + step, step)  # distances along a course

    # -- the step ----------------------------------------------------------------------------

    def decide(self, own: Own, targets: Targets, encounter: Encounter | None = None) -> Decision:
        world, p, ship = self.world, self.params, self.world.vessel
        self.time += world.period
        goal = self.progress.subgoal(own)
        dx, dy = float(goal[0]) - own.x, float(goal[1]) - own.y
        pref_course = math.atan2(dy, dx) if dx or dy else own.psi
        speed, course, heads, index = self.candidates(own, pref_course)
        vx, vy = speed * np.cos(course), speed * np.sin(course)
        cost = np.hypot(vx - ship.max_speed * math.cos(pref_course),
                        vy - ship.max_speed * math.sin(pref_course))  # fmt: skip
        grounded = self.grounds(own, speed, heads, index)
        contact, wrong_side = self.obstacles(own, targets, vx, vy)
        free = ~grounded & (contact == np.inf)
        ok = free & ~wrong_side
        events = []
        # np.count_nonzero: ndarray.any's wrapper costs more on these few hundred
        if not np.count_nonzero(ok) and np.count_nonzero(free):
            ok = free
            events.append({"kind": "colregs-dropped", "candidates": int(speed.size)})
        if np.count_nonzero(ok):
            best = int(np.argmin(np.where(ok, cost, np.inf)))
        else:
            with np.errstate(divide="ignore"):
                penalised = cost + float(p["w_time"]) / contact
            if not grounded.all():
                best = int(np.argmin(np.where(grounded, np.inf, penalised)))
            else:  # every course meets the grid within the look-ahead: the slowest, then cost
                best = int(np.lexsort((cost, speed))[0])
            events.append({"kind": "all-candidates-in-vo", "candidates": int(speed.size),
                           "grounding": int(np.count_nonzero(grounded)),
                           "contact_s": round(float(contact[best]), 3)})  # fmt: skip
        v, omega = autopilot(own, float(course[best]), float(speed[best]), ship, world.period,
                             float(p["heading_gain"]))  # fmt: skip
        return Decision(v, omega, events)

    def candidates(self, own: Own, pref_course: float):
        """(N,) speeds and courses: the grid of speeds x courses within reach, the present
        velocity, and the preferred course at each speed when it is within reach; and the
        courses (H,) with each candidate's index among them."""
        p, ship = self.params, self.world.vessel
        t = float(p["reach"])
        lo = max(ship.min_speed, own.v - ship.max_decel * t)
        hi = min(ship.max_speed, own.v + ship.max_accel * t)
        off = math.remainder(pref_course - own.psi, 2 * math.pi)
        # np.linspace(lo, hi, speeds) x the courses psi + [offsets, 0, off (when within
        # reach)], then the present velocity: compiled (rollout_kernels.vo_candidates)
        speed, heads, index, course = self.kernels.vo_candidates(
            float(own.psi), float(own.v), self.offsets, off, abs(off) <= self.turn, float(lo),
            float(hi), int(p["speeds"]))  # fmt: skip
        return speed, course, heads, index

    def grounds(self, own: Own, speed: np.ndarray, heads: np.ndarray, index: np.ndarray
                ) -> np.ndarray:  # fmt: skip
        """(N,) bool: the straight track of candidate ``n`` (course ``heads[index[n]]``) over
        ``ground_time`` meets the grid (a clearance at most half the own ship's length), or the
        ship is already there. Each course's first such distance along it is found once."""
        clearance = self.world.clearance
        if clearance is None:
            return np.zeros(speed.size, bool)
        ray = self.ray
        blocked = clearance.at(own.x + np.cos(heads)[:, None] * ray,
                               own.y + np.sin(heads)[:, None] * ray) <= self.radius  # fmt: skip
        first = np.where(blocked.any(axis=1), ray[np.argmax(blocked, axis=1)], np.inf)
        return speed * float(self.params["ground_time"]) >= first[index]

    def obstacles(self, own: Own, targets: Targets, vx: np.ndarray, vy: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
        """(N,) the first contact time within the horizon over every target's worst-case VO
        (inf outside them all), and (N,) bool: in region V3 of a target whose COLREGs mode
        applies (with the hysteresis)."""
        n, k = vx.size, targets.pos.shape[0]
        if k == 0:
            return np.full(n, np.inf), np.zeros(n, bool)
        p, ship = self.params, self.world.vessel
        px, py = targets.pos[:, 0] - own.x, targets.pos[:, 1] - own.y  # (K,)
        radius = 0.5 * (ship.length + targets.length) + float(p["margin"]) * ship.length
        vel = np.ascontiguousarray(targets.vel, float).reshape(-1, 2)
        # _first_contact of every candidate and target, its minimum over the targets, compiled
        contact = self.kernels.vo_contacts(vx, vy, px, py, vel, np.ascontiguousarray(
            radius, float), float(p["uncertainty"]), float(p["horizon"]))  # fmt: skip
        active = self.colregs(own, targets)
        if not np.count_nonzero(active):
            return contact, np.zeros(n, bool)
        px, py = px[active], py[active]
        wx = vx[:, None] - vel[active, 0]  # (N, K active)
        wy = vy[:, None] - vel[active, 1]
        wrong = (px * wy - py * wx > 0.0) & (px * wx + py * wy >= 0.0)  # V3 (passes_to_port)
        return contact, wrong.any(axis=1)

    def colregs(self, own: Own, targets: Targets) -> np.ndarray:
        """(K,) bool: the targets whose COLREGs constraint applies now: entered (class in
        :data:`CONSTRAINED`, ``0 < t_CPA <= colregs_time``, ``d_CPA <= colregs_distance``
        lengths) or held by the hysteresis (``hold`` s after the entry last held). The CPA is
        tested first; only the targets it admits are classified."""
        p, ship = self.params, self.world.vessel
        k = targets.pos.shape[0]
        rel = targets.pos - (own.x, own.y)
        # the CPA of the targets' relative velocity (usvtool.encounter.cpa's, in the
        # components), compiled: rollout_kernels.vo_near
        near = self.kernels.vo_near(
            np.ascontiguousarray(targets.pos, float).reshape(-1, 2),
            np.ascontiguousarray(targets.vel, float).reshape(-1, 2), float(own.x), float(own.y),
            own.v * math.cos(own.psi), own.v * math.sin(own.psi), float(p["colregs_time"]),
            float(p["colregs_distance"] * ship.length))  # fmt: skip
        cls = np.full(k, NONE, np.int8)
        if np.count_nonzero(near):  # the relative bearings of usvtool.encounter (compass degrees)
            px, py = rel[near, 0], rel[near, 1]
            tx, ty = targets.vel[near, 0], targets.vel[near, 1]
            beta = np.degrees(own.psi - np.arctan2(py, px)) % 360.0
            alpha = np.degrees(np.arctan2(ty, tx) - np.arctan2(-py, -px)) % 360.0
            cls[near] = classify_angles(beta, alpha, True)
        entry = near & ((cls == HEAD_ON) | (cls == CROSSING_GIVE_WAY) | (cls == OVERTAKING))
        active = np.zeros(k, bool)
        if not np.count_nonzero(entry) and not self.modes:
            return active
        for j in range(k):  # per target (a handful), not per candidate
            if entry[j]:
                held = self.modes.get(j)
                # a mode held keeps its class; a fresh entry takes the present one
                mode = held[0] if held and self.time - held[1] <= p["hold"] else int(cls[j])
                self.modes[j] = (mode, self.time)
                active[j] = True
            elif j in self.modes:
                if self.time - self.modes[j][1] <= p["hold"]:
                    active[j] = True
                else:
                    del self.modes[j]
        return active

    def mode(self, j: int) -> int | None:
        """The COLREGs class code held for target ``j`` (None when none is)."""
        held = self.modes.get(j)
        return held[0] if held else None
