"""``sbmpc``: simulation-based control behaviour selection with predictive hazard assessment.

Johansen, Perez and Cristofaro, "Ship collision avoidance and COLREGS compliance using
simulation-based control behavior selection with predictive hazard assessment", IEEE Trans.
Intelligent Transportation Systems 17(12), 2016. Not a DWA: a finite set of *control
behaviours*, each a pair (course offset chi_ca, propulsion factor P_ca) applied to the
guidance system's course and speed commands, is simulated over a horizon, each gets a hazard
H(k), and the behaviour of least hazard is commanded to the autopilot and held until the next
re-evaluation (docs/controllers.md, section "sbmpc", says which readings are ours).

The paper's behaviours (its section on control behaviours):

- course offsets chi_ca in {-90, -75, ..., 0, ..., +75, +90} deg (13; positive to starboard,
  the paper counting clockwise, NED);
- propulsion commands P_ca in {1 (nominal speed), 1/2 (slow forward), 0 (stop), -1 (full
  reverse)}: the speed command is P_ca times the nominal speed. Our vessels cannot go astern
  (their ``min_speed`` is the floor), so a speed command below ``min_speed`` is ``min_speed``:
  full reverse is then commanded as stop (``min_speed``), and both stay in the set (52
  behaviours, as the paper's 13 x 4).

The hazard of behaviour k at t0 (the paper's hazard; predicted times t in D(t0) = {t0 + dt,
..., t0 + T}; the paper's equation numbers are not cited: its body could not be re-read in this
round, docs/controllers.md):

    H(k) = max_i [ max_t C_i^k(t) R_i^k(t) + kappa [mu_i^k] + lambda [tau_i^k] ]
           + f(P_k, chi_k) + g(P_k, chi_k) + G(k)

- R_i^k(t) = (t - t0)^-p (d_safe / d_0i^k(t))^q when d_0i^k(t) <= d_safe, else 0: the
  collision risk factor, discounted in time (p) and growing as the distance falls (q);
- C_i^k(t) = K_coll |v_0^k(t) - v_i(t)|^2: the cost of a collision, proportional to the kinetic
  energy of the relative motion;
- [mu_i^k] in {0, 1}: a COLREGS violation somewhere in the prediction: the obstacle CLOSE
  (d <= d_close), closing, on the own ship's STARBOARD side (forward of 22.5 deg abaft her
  beam, of her commanded course), courses crossing or reciprocal, in a situation that made her
  give way at t0 (HEAD-ON, or the obstacle on her starboard side) (:meth:`SBMPC.ships`);
- [tau_i^k] in {0, 1}: the transitional cost of a behaviour that takes the ship out of a
  COLREGS-compliant course of events (our reading, the paper's ~COLREGS: crossing ahead of a
  close obstacle that is not head-on, Rule 15; the stand-on ship of a close crossing turning to
  port, Rule 17(c));
- f(P, chi) = k_P (1 - P) + k_chi chi^2 (k_chi to starboard, k_chi_port to port): leaving the
  nominal speed and course; g = k_dP |P - P_last| + k_dchi |chi - chi_last| (k_dchi_port for a
  change to port): changing the behaviour from the one held;
- G(k): grounding (our addition, the paper leaves land out): the grid treated as an obstacle
  at rest, the same C R with the clearance c(t) of the predicted position for the distance
  (the own ship's speed squared for C), and ``hull_cost`` wherever c(t) <= half the own length
  (contact: the behaviour is refused while any other has none).

Prediction: the targets at constant velocity (the paper's nominal scenario); the own ship under
behaviour k by a kinematic model within the vessel's limits: the heading turns toward the
commanded course at the vessel's yaw rate limit and holds it, the speed ramps toward the
commanded speed at its acceleration or deceleration limit (yaw acceleration neglected); every
behaviour x target x time at once in NumPy.
"""

from __future__ import annotations

import math

import numpy as np

from usvtool.params import NON_NEGATIVE, POSITIVE, Param, Range
from usvtool.sim.controllers.base import Controller, Decision, Encounter, Own, Targets, World
from usvtool.sim.controllers.process import autopilot

#: The paper's course offsets (deg, positive to starboard) and propulsion factors.
OFFSETS_DEG = np.arange(-90.0, 90.0 + 1e-9, 15.0)
PROPULSION = np.array([1.0, 0.5, 0.0, -1.0])
#: HEAD-ON: courses within 22.5 deg of reciprocal; CROSSED: course difference above 68.5 deg
#: (the sidelight and sternlight sectors of Rules 13 and 21).
HEAD_ON_COS = math.cos(math.radians(22.5))
CROSSED_COS = math.cos(math.radians(68.5))
#: forward of 22.5 deg abaft the beam (112.5 deg from ahead): the sector where a crossing ship
#: on the starboard side makes the own ship give way (Rule 15, Rule 13's 22.5 deg).
FORWARD_COS = math.cos(math.radians(112.5))
#: HEAD-ON's "ahead": within the same 22.5 deg of the own ship's heading.
AHEAD_COS = math.cos(math.radians(22.5))


def behaviours() -> tuple[np.ndarray, np.ndarray]:
    """(offsets in rad, positive to starboard; propulsion factors): the 13 x 4 = 52 behaviours,
    offsets the outer order."""
    chi = np.repeat(np.radians(OFFSETS_DEG), PROPULSION.size)
    prop = np.tile(PROPULSION, OFFSETS_DEG.size)
    return chi, prop


class SBMPC(Controller):
    """Simulation-based MPC (Johansen et al. 2016): the least-hazard control behaviour, held
    ``update`` seconds, its course and speed tracked by the autopilot
    (:func:`usvtool.sim.controllers.process.autopilot`)."""

    name = "sbmpc"
    parameters = {
        "horizon": Param(60.0, "the prediction horizon T, s", POSITIVE),
        "step": Param(1.0, "the prediction's time step, s", POSITIVE),
        "update": Param(1.0, "seconds a chosen behaviour is held before re-evaluation",
                        NON_NEGATIVE),
        "speed": Param(None, "the nominal speed, m/s (null: the vessel's max_speed)"),
        "d_safe": Param(None, "the collision risk factor's safe distance, m (null: half the "
                              "two lengths + max(3 L, 3 s x nominal speed))"),
        "d_close": Param(None, "the COLREGS distance d_cl, m (null: 3 d_safe)"),
        "p": Param(0.5, "the collision risk factor's time discount exponent", Range(0.0)),
        "q": Param(4.0, "the collision risk factor's distance exponent", Range(1.0)),
        "k_coll": Param(1.0, "the collision cost per squared relative speed, s^2/m^2",
                        NON_NEGATIVE),
        "kappa": Param(3.0, "the COLREGS violation cost", NON_NEGATIVE),
        "lam": Param(3.0, "the transitional (~COLREGS) cost", NON_NEGATIVE),
        "k_p": Param(2.5, "the cost of leaving the nominal speed (per unit of 1 - P)",
                     NON_NEGATIVE),
        "k_chi": Param(1.3, "the cost of a course offset to starboard, per rad^2",
                       NON_NEGATIVE),
        "k_chi_port": Param(1.6, "the cost of a course offset to port, per rad^2",
                            NON_NEGATIVE),
        "k_dp": Param(0.5, "the cost of a change of the propulsion factor", NON_NEGATIVE),
        "k_dchi": Param(0.2, "the cost of a change of the offset to starboard, per rad",
                        NON_NEGATIVE),
        "k_dchi_port": Param(0.3, "the cost of a change of the offset to port, per rad",
                             NON_NEGATIVE),
        "d_ground": Param(None, "the grounding term's safe clearance, m (null: the own "
                                "length, twice the hull's half length)"),
        "ground_horizon": Param(10.0, "the grounding term's horizon, s", POSITIVE),
        "hull_cost": Param(1.0e9, "the hazard of a predicted contact with the grid", POSITIVE),
        "lookahead": Param(None, "the route guidance's look-ahead distance, m (null: 5 L)"),
        "heading_gain": Param(0.5, "the autopilot's proportional heading gain, 1/s", POSITIVE),
    }  # fmt: skip

    def __init__(self, **params):
        super().__init__(**params)
        p = self.params
        n = max(1, int(round(p["horizon"] / p["step"])))
        self.times = p["step"] * np.arange(1, n + 1)  # D(t0) less t0 (t - t0 > 0)
        self.mid = self.times - 0.5 * p["step"]
        self.chi, self.prop = behaviours()
        self.discount = self.times ** -p["p"]

    # -- a run ---------------------------------------------------------------------------
    def reset(self, world: World) -> None:
        super().reset(world)
        vessel, p = world.vessel, self.params
        self.nominal = float(p["speed"] if p["speed"] is not None else vessel.max_speed)
        length = float(vessel.length)
        self.d_ground = float(p["d_ground"] if p["d_ground"] is not None else length)
        self.n_ground = max(1, int(np.searchsorted(self.times, p["ground_horizon"] + 1e-9)))
        self.lookahead = float(p["lookahead"] if p["lookahead"] is not None else 5 * length)
        route = world.route
        if route is not None and len(route) >= 2:
            pts = np.asarray(route, float)
            seg = np.diff(pts, axis=0)
            self._route = (pts, seg, np.concatenate([[0.0], np.cumsum(np.hypot(*seg.T))]))
        else:
            self._route = None
        self._progress = 0.0
        self._clock = math.inf  # seconds since the last evaluation: evaluate at once
        self.held = 6 * PROPULSION.size  # index of (0 deg, nominal): the last behaviour
        self.last_hazard: np.ndarray | None = None

    def d_safe(self, target_lengths: np.ndarray) -> np.ndarray:
        """(K,) the collision risk factor's safe distance per target (m)."""
        p, length = self.params, float(self.world.vessel.length)
        if p["d_safe"] is not None:
            return np.full(target_lengths.shape, float(p["d_safe"]))
        return (length + target_lengths) / 2 + max(3 * length, 3.0 * self.nominal)

    def d_close(self, d_safe: np.ndarray) -> np.ndarray:
        p = self.params
        return np.full(d_safe.shape, float(p["d_close"])) if p["d_close"] is not None \
            else 3 * d_safe

    def guidance(self, own: Own) -> float:
        """The guidance course (math rad): line of sight to a point ``lookahead`` metres ahead
        along the route (its progress never goes back), or to the goal without a route."""
        goal = self.world.goal
        if self._route is not None:
            pts, seg, s = self._route
            rel = np.array([own.x, own.y]) - pts[:-1]
            ll = np.einsum("ij,ij->i", seg, seg)
            u = np.clip(np.einsum("ij,ij->i", rel, seg) / np.where(ll > 0, ll, 1.0), 0, 1)
            foot = pts[:-1] + u[:, None] * seg
            j = int(np.argmin(np.hypot(*(foot - [own.x, own.y]).T)))
            self._progress = max(self._progress, float(s[j] + u[j] * math.sqrt(ll[j])))
            aim = self._progress + self.lookahead
            if aim < s[-1]:
                goal = self._point(np.array([aim]))[0]
        return math.atan2(goal[1] - own.y, goal[0] - own.x)

    # -- the prediction ----------------------------------------------------------------------
    def route_turn(self) -> np.ndarray:
        """(N,) how far the route turns the guidance course over the horizon (rad, at the
        prediction's mid-step times): the direction of the look-ahead chord from the point
        the ship reaches at the nominal speed, less its direction now; zeros without a
        route. The prediction follows the guidance (the paper's behaviours are offsets to
        the guidance course, which follows the route), not one fixed course for T seconds."""
        if self._route is None:
            return np.zeros(self.mid.size)
        pts, seg, s = self._route
        at = self._progress + self.nominal * np.concatenate([[0.0], self.mid])
        here = self._point(np.minimum(at, s[-1]))
        there = self._point(np.minimum(at + self.lookahead, s[-1]))
        chord = there - here
        direction = np.arctan2(chord[:, 1], chord[:, 0])
        done = np.hypot(chord[:, 0], chord[:, 1]) < 1e-9
        turn = np.remainder(direction - direction[0] + math.pi, 2 * math.pi) - math.pi
        turn[done] = 0.0 if done[0] else turn[~done][-1]
        return turn[1:]

    def _point(self, at: np.ndarray) -> np.ndarray:
        """(n, 2) the route's points at the arc lengths ``at``."""
        pts, seg, s = self._route
        k = np.clip(np.searchsorted(s, at, side="right") - 1, 0, len(seg) - 1)
        frac = np.clip((at - s[k]) / np.maximum(s[k + 1] - s[k], 1e-12), 0.0, 1.0)
        return pts[k] + frac[:, None] * seg[k]

    def predict(self, own: Own, course: float):
        """The own ship's predicted trajectories under every behaviour: x, y (B, N) at
        :attr:`times`, and the heading unit vector and speed (B, N) there.

        The commanded course of behaviour k at time t is the guidance course (now, plus the
        route's turn ahead: :meth:`route_turn`) less its offset (to starboard, clockwise); the
        heading closes the initial error at the vessel's yaw rate limit and then follows the
        command; the speed ramps to P_k x nominal at the acceleration limits."""
        vessel = self.world.vessel
        t = self.times[None, :]
        command0 = course - self.chi  # (B,) math rad
        self._command0 = command0
        error = np.remainder(command0 - own.psi + math.pi, 2 * math.pi) - math.pi
        rate = vessel.max_yaw_rate
        turn = self.route_turn()

        def heading(tt, bend):
            left = np.maximum(np.abs(error)[:, None] - rate * tt, 0.0)
            return command0[:, None] + bend[None, :] - np.sign(error)[:, None] * left

        target = np.clip(self.prop * self.nominal, vessel.min_speed, vessel.max_speed)
        dv = (target - own.v)[:, None]

        def speed(tt):
            return own.v + np.clip(dv, -vessel.max_decel * tt, vessel.max_accel * tt)

        m = self.mid[None, :]
        psi_m, v_m = heading(m, turn), speed(m)
        dt = self.params["step"]
        x = own.x + np.cumsum(v_m * np.cos(psi_m), axis=1) * dt
        y = own.y + np.cumsum(v_m * np.sin(psi_m), axis=1) * dt
        psi = heading(t, np.concatenate([turn[1:], turn[-1:]]))
        return x, y, np.cos(psi), np.sin(psi), speed(t)

    def hazard(self, own: Own, targets: Targets, course: float) -> np.ndarray:
        """(B,) the hazard H(k) of every behaviour (module docstring); B x K x N at once."""
        p = self.params
        x, y, ux, uy, v = self.predict(own, course)  # (B, N)
        vx, vy = v * ux, v * uy
        chi, prop = self.chi, self.prop
        # f and g: leaving the nominal behaviour, and changing the held one
        k_chi = np.where(chi >= 0, p["k_chi"], p["k_chi_port"])
        hold_chi, hold_p = chi[self.held], prop[self.held]
        dchi = chi - hold_chi
        k_dchi = np.where(dchi >= 0, p["k_dchi"], p["k_dchi_port"])
        total = (p["k_p"] * (1 - prop) + k_chi * chi * chi
                 + p["k_dp"] * np.abs(prop - hold_p) + k_dchi * np.abs(dchi))
        total = total + self.grounding(x, y, v)
        n = targets.pos.shape[0]
        if n:
            total = total + self.ships(own, targets, x, y, ux, uy, vx, vy, v)
        return total

    def ships(self, own, targets, x, y, ux, uy, vx, vy, v) -> np.ndarray:
        """(B,) max over targets of [max over times of C R, plus kappa if a violation and
        lambda if a transition occurs anywhere in the prediction].

        Only the (behaviour, target, time) triples within reach (d <= max(d_safe, d_close):
        beyond, R, mu and tau are all zero) are looked at, compressed to a flat list."""
        p = self.params
        t = self.times
        n_b = x.shape[0]
        n_k = targets.pos.shape[0]
        px, py = targets.pos[:, 0], targets.pos[:, 1]
        wx, wy = targets.vel[:, 0], targets.vel[:, 1]
        sp_t = np.hypot(wx, wy)
        d_safe = self.d_safe(np.asarray(targets.length, float))  # (K,)
        d_cl = self.d_close(d_safe)
        reach = np.maximum(d_safe, d_cl)
        rx = (px[:, None] + wx[:, None] * t)[None] - x[:, None]  # (B, K, N) own -> obstacle
        ry = (py[:, None] + wy[:, None] * t)[None] - y[:, None]
        d2 = rx * rx + ry * ry
        bi, ki, ni = np.nonzero(d2 <= (reach * reach)[None, :, None])
        if not bi.size:
            return np.zeros(n_b)
        rx, ry = rx[bi, ki, ni], ry[bi, ki, ni]
        d = np.maximum(np.sqrt(d2[bi, ki, ni]), 1e-6)
        vxs, vys, vs = vx[bi, ni], vy[bi, ni], v[bi, ni]
        wxs, wys = wx[ki], wy[ki]
        # the collision risk factor R and the collision cost C
        ds = d_safe[ki]
        inside = d <= ds
        cr = np.zeros(d.size)
        cr[inside] = (p["k_coll"] * ((vxs - wxs)[inside] ** 2 + (vys - wys)[inside] ** 2)
                      * self.discount[ni[inside]] * (ds[inside] / d[inside]) ** p["q"])
        # the situations at each predicted time: the sides and "ahead" from the behaviour's
        # commanded course (its heading once the turn is made: the predicate judges the
        # manoeuvre, not the instants of its turn)
        lx, ly = rx / d, ry / d
        settled = self._command0[bi]
        cx, cy = np.cos(settled), np.sin(settled)
        ahead = cx * lx + cy * ly  # cosine of the obstacle's bearing from the bow
        starboard = (cx * ly - cy * lx < 0) & (ahead > FORWARD_COS)
        dot = vxs * wxs + vys * wys
        meeting = (vs > 0.05) & (sp_t[ki] > 0.05) & (dot < CROSSED_COS * vs * sp_t[ki])
        close = d <= d_cl[ki]
        # ... and closing (the range falling): a ship drawing away holds no risk of collision,
        # Rule 7 (our reading: the paper's predicates alone flag a ship that crossed ahead)
        closing = (wxs - vxs) * lx + (wys - vys) * ly < 0
        # a crossing is the give-way ship's (Rule 15) only if the obstacle is on the starboard
        # side now (t0): one that crossed ahead from port does not make her give way; likewise
        # a head-on situation is the one met ahead at t0 (Rule 14: "ahead or nearly ahead");
        # either is then judged at t on courses crossing or reciprocal
        r0x, r0y = px - own.x, py - own.y
        d0 = np.maximum(np.hypot(r0x, r0y), 1e-6)
        h0x, h0y = math.cos(own.psi), math.sin(own.psi)
        ahead0 = (h0x * r0x + h0y * r0y) / d0
        starboard0 = (h0x * r0y - h0y * r0x < 0) & (ahead0 > FORWARD_COS)
        head_on0 = self._head_on0(own, targets)
        mu = close & closing & starboard & meeting & (head_on0 | starboard0)[ki]
        # the transitional cost: crossing ahead of a close obstacle not met head-on (Rule 15),
        # and the stand-on ship of a close crossing turning to port (Rule 17(c))
        dot0 = own.v * (h0x * wx + h0y * wy)
        norm0 = own.v * sp_t
        moving0 = (own.v > 0.05) & (sp_t > 0.05)
        crossed0 = moving0 & (dot0 < CROSSED_COS * norm0) & ~(dot0 < -HEAD_ON_COS * norm0)
        port0 = (h0x * r0y - h0y * r0x > 0) & (ahead0 > FORWARD_COS)
        stand_on0 = (d0 <= d_cl) & port0 & crossed0  # (K,)
        side0 = wy * r0x - wx * r0y  # cross(w, own - obstacle) at t0, (K,)
        side = wys * rx - wxs * ry  # cross(w, own - obstacle) at t
        in_front = wxs * rx + wys * ry < 0  # the own ship ahead of the obstacle
        crosses = (side * side0[ki] < 0) & in_front & ~head_on0[ki]
        tau = close & (crosses | (stand_on0[ki] & (self.chi[bi] < 0)))
        # per (behaviour, obstacle), then the worst obstacle
        flat = bi * n_k + ki
        worst = np.zeros(n_b * n_k)
        np.maximum.at(worst, flat, cr)
        worst[np.unique(flat[mu])] += p["kappa"]
        worst[np.unique(flat[tau])] += p["lam"]
        return worst.reshape(n_b, n_k).max(axis=1)

    @staticmethod
    def _head_on0(own: Own, targets: Targets) -> np.ndarray:
        """(K,) HEAD-ON at t0: moving on courses within 22.5 deg of reciprocal, the obstacle
        within 22.5 deg of the own ship's heading."""
        r = targets.pos - [own.x, own.y]
        d = np.maximum(np.hypot(r[:, 0], r[:, 1]), 1e-6)
        h = np.array([math.cos(own.psi), math.sin(own.psi)])
        w = targets.vel
        sp = np.hypot(w[:, 0], w[:, 1])
        dot = own.v * (w @ h)
        return ((own.v > 0.05) & (sp > 0.05) & (dot < -HEAD_ON_COS * own.v * sp)
                & ((r @ h) / d > AHEAD_COS))

    def grounding(self, x, y, v) -> np.ndarray:
        """(B,) the grounding term G(k): the grid as an obstacle at rest (our addition)."""
        w, p = self.world, self.params
        if w.clearance is None:
            return np.zeros(x.shape[0])
        n = self.n_ground
        x, y, v = x[:, :n], y[:, :n], v[:, :n]
        c = w.clearance.at(x, y)
        hull = 0.5 * float(w.vessel.length)
        dg = self.d_ground
        r = np.where(c <= dg, self.discount[:n] * (dg / np.maximum(c, 1e-6)) ** p["q"], 0.0)
        g = (p["k_coll"] * v * v * r).max(axis=1)
        return np.where((c <= hull).any(axis=1), p["hull_cost"] + g, g)

    # -- the step ----------------------------------------------------------------------------
    def decide(self, own: Own, targets: Targets, encounter: Encounter | None = None) -> Decision:
        w, p = self.world, self.params
        course = self.guidance(own)
        if self._clock >= p["update"] - 1e-9:
            h = self.hazard(own, targets, course)
            self.last_hazard = h
            self.held = int(np.argmin(h))
            self._clock = 0.0
        self._clock += w.period
        chi, prop = self.chi[self.held], self.prop[self.held]
        vessel = w.vessel
        # the guidance slows on its last metres so that the autopilot's turn (radius about
        # speed / gain) fits within the distance left: no orbit round the goal
        left = math.hypot(w.goal[0] - own.x, w.goal[1] - own.y)
        speed = min(prop * self.nominal, 0.5 * p["heading_gain"] * left)
        speed = min(max(speed, vessel.min_speed), vessel.max_speed)
        v, omega = autopilot(own, course - chi, speed, vessel, w.period, p["heading_gain"])
        return Decision(v, omega)

    def memory_parts(self) -> list[tuple[int, str, str]]:
        """Its prediction: behaviours x targets x times, a few float arrays of it at once."""
        n = self.chi.size * self.times.size
        return [(8 * n * 24, "the sbmpc prediction (behaviours x horizon)",
                 "a shorter horizon or a longer step")]
