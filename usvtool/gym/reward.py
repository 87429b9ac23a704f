"""The environment's reward (docs/gym.md, "Reward"): one step's terms and the episode's last.

Per step of ``dt`` seconds, with ``d`` the own ship's distance to the goal before and after
the step, ``d0`` at the episode's start:

- ``progress * (d_before - d_after) / d0``: the whole run to the goal earns ``progress``;
- ``- domain * dt * sum_j max(0, 1 - sqrt(q_j))``: ``q_j`` the domain's quadratic form of
  target ``j`` after the step (:func:`usvtool.encounter.domain_ellipse`, <= 1 inside the own
  ship's 7 L x 3 L domain), so a target on the domain's edge costs nothing and one at its
  centre ``domain`` a second;
- ``- shore * dt * max(0, 1 - c / L)`` on a map: ``c`` the map's clearance at the own ship
  after the step, ``L`` her length;
- ``- colregs * dt * violation``: the command against the side the most urgent latched
  encounter sets (:func:`violation`);
- ``- collision`` on a collision, ``+ arrival`` on arrival;
- at the episode's end (terminated or truncated), ``- verdict * n``: ``n`` the encounters of
  the run so far that the verdicts (:func:`usvtool.sim.verdicts.evaluate`, the summary's and
  the report's) judge non-compliant.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from usvtool.encounter import domain_semi_axes


@dataclass(frozen=True)
class Reward:
    """The reward's weights (docs/gym.md): each >= 0, 0 leaves its term out."""

    progress: float = 1.0
    domain: float = 0.5  # per second, at the domain's centre
    shore: float = 0.5  # per second, at the obstacles
    colregs: float = 0.2  # per second, at the largest violation
    verdict: float = 0.5  # per non-compliant encounter, at the episode's end
    collision: float = 2.0
    arrival: float = 1.0

    def __post_init__(self):
        for name, value in self.__dict__.items():
            if not (isinstance(value, int | float) and math.isfinite(value) and value >= 0):
                raise ValueError(f"reward weight {name} must be a finite number >= 0, "
                                 f"not {value!r}")  # fmt: skip


#: Classes whose own ship gives way: her command must not turn to port (Rules 14, 15, 8).
GIVE_WAY = ("head-on", "crossing-give-way")
#: Classes whose own ship stands on: course and speed kept beyond the critical range (Rule
#: 17(a)), then no turn to port (Rule 17(c)).
STAND_ON = ("crossing-stand-on", "overtaken")
#: The critical range of the verdicts (docs/colregs.md: ``r_crit`` = 10 L).
CRITICAL_LENGTHS = 10.0


def violation(encounter, own, targets, vessel, dt: float, v: float, omega: float) -> float:
    """How far the command ``(v, omega)`` (after the window's clip) goes against the rule the
    encounter ``encounter`` (the most urgent latched, or None) sets, in [0, 1]:

    - give-way (head-on, crossing give-way): a turn to port, ``max(0, omega) / max_yaw_rate``
      (the verdicts' ``rule14-starboard``; Rule 15's starboard alteration);
    - stand-on (crossing stand-on, overtaken) while the target is at least 10 L away: any
      change of course or speed, the larger of ``|omega| / max_yaw_rate`` and ``|v - v_own|``
      over the period's reach (``max_accel dt`` up, ``max_decel dt`` down)
      (``rule17-keep-course-speed``); closer, a turn to port (``rule17c-port-turn``);
    - overtaking, or no encounter: 0 (either side; keeping clear is the domain term's).

    >>> from usvtool.sim.controllers import Encounter, Own, Targets
    >>> from usvtool.sim.vessel import preset
    >>> ship, far = preset("udwa-usv"), Targets(np.array([[0.0, 500.0]]), np.zeros((1, 2)),
    ...                                          np.array([15.0]))
    >>> own = Own(0.0, 0.0, math.pi / 2, 7.0, 0.0)
    >>> violation(Encounter("head-on", 0), own, far, ship, 0.1, 7.0, ship.max_yaw_rate / 2)
    0.5
    >>> round(violation(Encounter("crossing-stand-on", 0), own, far, ship, 0.1, 6.9, 0.0), 9)
    0.5
    """
    if encounter is None:
        return 0.0
    cls, yaw = encounter.cls, omega / vessel.max_yaw_rate
    if cls in GIVE_WAY:
        return max(0.0, yaw)
    if cls not in STAND_ON:
        return 0.0
    p = targets.pos[encounter.target]
    if math.hypot(p[0] - own.x, p[1] - own.y) < CRITICAL_LENGTHS * vessel.length:
        return max(0.0, yaw)
    dv = v - own.v
    reach = (vessel.max_accel if dv > 0 else vessel.max_decel) * dt
    return min(1.0, max(abs(yaw), abs(dv) / reach))


def intrusion(x: float, y: float, psi: float, pos: np.ndarray, length: float) -> float:
    """``sum_j max(0, 1 - sqrt(q_j))`` of the targets at ``pos`` ``(k, 2)`` in the domain of
    the own ship at ``(x, y)`` heading ``psi`` (mathematical radians), of ``length``: ``q`` the
    form of :func:`usvtool.encounter.domain_ellipse`, here in Python floats (a few targets).

    >>> # 5 m ahead of 8.75 (1 - 5 / 8.75), on the beam's edge (1.5 L: 0), half-way abeam (0.5)
    >>> intrusion(0.0, 0.0, 0.0, np.array([[5.0, 0.0], [0.0, 3.75], [0.0, 1.875]]), 2.5)
    0.9285714285714286
    """
    along, across = domain_semi_axes(length)
    c, s = math.cos(psi), math.sin(psi)
    total = 0.0
    for px, py in pos.tolist():
        dx, dy = px - x, py - y
        if dx * dx + dy * dy > along * along:  # beyond the semi-major axis: outside
            continue
        q = ((dx * c + dy * s) / along) ** 2 + ((dx * s - dy * c) / across) ** 2
        if q < 1.0:
            total += 1.0 - math.sqrt(q)
    return total
