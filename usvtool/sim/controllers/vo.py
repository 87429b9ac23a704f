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
3. **Velocity obstacles** (the paper's eqs. 1-2): for a target B of velocity ``v_B`` at
   ``p_B`` and the own ship A at ``p_A``, the VO is the set of ``v_A`` whose relative ray
   ``lambda(p_A, v_A - v_B) = {p_A + t (v_A - v_B), t >= 0}`` meets the disc of radius ``R``
   about ``p_B`` (``B (+) -A``, both hulls as discs of half their lengths, plus a safety
   ``margin``): the collision cone of the relative position, shifted by ``v_B``. The paper
   treats only collisions that matter soon: the ray is cut at ``horizon`` seconds (a
   collision beyond it does not bar the velocity). The worst-case VO for a target velocity
   known to within ``uncertainty`` m/s (the union of the VOs of every ``v_B`` in that disc) is
   the VO grown by ``uncertainty`` in velocity space: ``|p - w t| <= R + u t`` for some
   ``t`` in ``[0, horizon]``, ``w = v_A - v_B``, ``p = p_B - p_A``, which is a quadratic in
   ``t`` solved for every candidate (:func:`first_contact`).
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
"vo". Angles inside are mathematical radians (counter-clockwise from east), as everywhere in the
controllers.
"""

from __future__ import annotations

import math

import numpy as np

from usvtool.encounter import CROSSING_GIVE_WAY, HEAD_ON, NONE, OVERTAKING, assess
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
    >>> w = np.array([[[10.0, 0.0]], [[10.0, 2.0]], [[0.0, 10.0]]])
    >>> first_contact(p, w, np.array([10.0]), 0.0, 60.0)[:, 0].round(6).tolist()
    [9.0, 9.258343, inf]
    """
    px, py = p[:, 0], p[:, 1]
    wx, wy = w[..., 0], w[..., 1]
    a = wx * wx + wy * wy - spread * spread
    half_b = px * wx + py * wy + radius * spread  # -b / 2
    c = px * px + py * py - radius * radius
    inside = c <= 0.0
    disc = half_b * half_b - a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(np.maximum(disc, 0.0))
        # the smaller root, in the form that stays accurate when a is small (c / (hb + root))
        t = np.where(half_b > 0, c / (half_b + root), np.inf)
    t = np.where((disc >= 0.0) & (half_b > 0) & (t <= horizon), t, np.inf)
    # a <= 0 (the spread outruns the relative speed): the grown disc swallows the own ship at
    # t = c / (2 half_b) at the latest when half_b > 0; the formula above covers it
    return np.where(inside, 0.0, t)


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
        super().reset(world)
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
        self.offsets = offsets[:n]
        self.radius = 0.5 * ship.length
        if world.clearance is not None:
            step = 0.5 * world.clearance.grid.cell_size
            far = ship.max_speed * float(p["ground_time"])
            self.ray = np.arange(step, far + step, step)  # distances along a course
        self._fixed = None

    # -- the step ----------------------------------------------------------------------------

    def decide(self, own: Own, targets: Targets, encounter: Encounter | None = None) -> Decision:
        world, p, ship = self.world, self.params, self.world.vessel
        self.time += world.period
        goal = self.progress.subgoal(own)
        to = goal - (own.x, own.y)
        pref_course = math.atan2(to[1], to[0]) if np.any(to) else own.psi
        pref = ship.max_speed * np.array([math.cos(pref_course), math.sin(pref_course)])
        speed, course = self.candidates(own, pref_course)
        vel = np.stack([speed * np.cos(course), speed * np.sin(course)], axis=-1)  # (N, 2)
        cost = np.hypot(vel[:, 0] - pref[0], vel[:, 1] - pref[1])
        grounded = self.grounds(own, speed, course)
        contact, wrong_side = self.obstacles(own, targets, vel)
        free = ~grounded & ~np.isfinite(contact)
        ok = free & ~wrong_side
        events = []
        if not ok.any() and free.any():
            ok = free
            events.append({"kind": "colregs-dropped", "candidates": int(speed.size)})
        if ok.any():
            best = int(np.argmin(np.where(ok, cost, np.inf)))
        else:
            with np.errstate(divide="ignore"):
                penalised = cost + float(p["w_time"]) / contact
            if not grounded.all():
                penalised = np.where(grounded, np.inf, penalised)
                best = int(np.argmin(penalised))
            else:  # every course meets the grid within the look-ahead: the slowest, then cost
                best = int(np.lexsort((cost, speed))[0])
            events.append({"kind": "all-candidates-in-vo", "candidates": int(speed.size),
                           "grounding": int(np.count_nonzero(grounded)),
                           "contact_s": round(float(contact[best]), 3)})  # fmt: skip
        v, omega = autopilot(own, float(course[best]), float(speed[best]), ship, world.period,
                             float(p["heading_gain"]))  # fmt: skip
        return Decision(v, omega, events)

    def candidates(self, own: Own, pref_course: float) -> tuple[np.ndarray, np.ndarray]:
        """(N,) speeds and courses: the grid within reach, the present velocity, and the
        preferred course at each speed when it is within reach."""
        p, ship = self.params, self.world.vessel
        t = float(p["reach"])
        lo = max(ship.min_speed, own.v - ship.max_decel * t)
        hi = min(ship.max_speed, own.v + ship.max_accel * t)
        speeds = np.linspace(lo, hi, int(p["speeds"]))
        off = math.remainder(pref_course - own.psi, 2 * math.pi)
        offsets = self.offsets
        if abs(off) <= self.turn:
            offsets = np.append(offsets, off)
        courses = own.psi + np.append(offsets, 0.0)
        speed = np.append(np.repeat(speeds, courses.size), own.v)
        course = np.append(np.tile(courses, speeds.size), own.psi)
        return speed, course

    def grounds(self, own: Own, speed: np.ndarray, course: np.ndarray) -> np.ndarray:
        """(N,) bool: the straight track over ``ground_time`` meets the grid (a clearance at
        most half the own ship's length), or the ship is already there."""
        clearance = self.world.clearance
        if clearance is None:
            return np.zeros(speed.size, bool)
        heads, index = np.unique(course, return_inverse=True)
        ray = self.ray
        x = own.x + np.cos(heads)[:, None] * ray
        y = own.y + np.sin(heads)[:, None] * ray
        blocked = clearance.at(x, y) <= self.radius
        first = np.where(blocked.any(axis=1), ray[np.argmax(blocked, axis=1)], np.inf)
        return speed * float(self.params["ground_time"]) >= first[index.ravel()]

    def obstacles(self, own: Own, targets: Targets, vel: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
        """(N,) the first contact time within the horizon over every target's worst-case VO
        (inf outside them all), and (N,) bool: in region V3 of a target whose COLREGs mode
        applies (with the hysteresis)."""
        n = vel.shape[0]
        k = targets.pos.shape[0]
        if k == 0:
            return np.full(n, np.inf), np.zeros(n, bool)
        p, ship = self.params, self.world.vessel
        rel = targets.pos - (own.x, own.y)  # (K, 2)
        radius = 0.5 * (ship.length + targets.length) + float(p["margin"]) * ship.length
        w = vel[:, None, :] - targets.vel[None, :, :]  # (N, K, 2)
        contact = first_contact(rel, w, radius, float(p["uncertainty"]), float(p["horizon"]))
        active = self.colregs(own, targets)
        if active.any():
            wrong = passes_to_port(rel[active], w[:, active]).any(axis=1)
        else:
            wrong = np.zeros(n, bool)
        return contact.min(axis=1), wrong

    def colregs(self, own: Own, targets: Targets) -> np.ndarray:
        """(K,) bool: the targets whose COLREGs constraint applies now: entered (class in
        :data:`CONSTRAINED`, ``0 < t_CPA <= colregs_time``, ``d_CPA <= colregs_distance``
        lengths) or held by the hysteresis (``hold`` s after the entry last held)."""
        p, ship = self.params, self.world.vessel
        speed = np.hypot(targets.vel[:, 0], targets.vel[:, 1])
        heading = np.degrees(np.arctan2(targets.vel[:, 0], targets.vel[:, 1])) % 360.0
        s = assess((own.x, own.y), (90.0 - math.degrees(own.psi)) % 360.0, own.v, targets.pos,
                   heading, speed)  # fmt: skip
        entry = (np.isin(s.cls, CONSTRAINED) & (s.tcpa > 0) & (s.tcpa <= p["colregs_time"])
                 & (s.dcpa <= p["colregs_distance"] * ship.length))  # fmt: skip
        active = np.zeros(entry.size, bool)
        for j in range(entry.size):  # per target (a handful), not per candidate
            if entry[j]:
                held = self.modes.get(j)
                # a mode held keeps its class; a fresh entry takes the present one
                cls = held[0] if held and self.time - held[1] <= p["hold"] else int(s.cls[j])
                self.modes[j] = (cls, self.time)
                active[j] = True
            elif j in self.modes:
                cls, last = self.modes[j]
                if self.time - last <= p["hold"] and cls != NONE:
                    active[j] = True
                else:
                    del self.modes[j]
        return active

    def mode(self, j: int) -> int | None:
        """The COLREGs class code held for target ``j`` (None when none is)."""
        held = self.modes.get(j)
        return held[0] if held else None
