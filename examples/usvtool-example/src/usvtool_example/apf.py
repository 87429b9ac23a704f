"""``apf``: an artificial potential field (Khatib, "Real-time obstacle avoidance for manipulators
and mobile robots", IJRR 5(1), 1986) with a vortex repulsion, so that a ship gives way to
starboard (COLREGs Rules 14-15) rather than backing off: the goal pulls with a unit force, and
each target within ``reach`` metres pushes with ``push (reach / d - 1)`` at right angles to the
line of sight, to its right (a target dead ahead pushes the ship to starboard). The ship steers
toward the resulting direction with a yaw rate of ``gain`` times the heading error, at full
speed, within the vessel's limits."""

from __future__ import annotations

import math

import numpy as np

from usvtool.sim.controllers.base import Controller, Decision


class PotentialField(Controller):
    name = "apf"
    defaults = {"reach": 120.0, "push": 2.0, "gain": 1.0}

    def decide(self, own, targets, encounter=None) -> Decision:
        p, world = self.params, self.world
        vessel, period = world.vessel, world.period
        here = np.array([own.x, own.y])
        to_goal = world.goal - here
        force = to_goal / max(float(np.hypot(*to_goal)), 1e-9)
        sight = targets.pos - here  # (k, 2) the lines of sight
        d = np.maximum(np.hypot(sight[:, 0], sight[:, 1]), 1e-9)
        near = d < p["reach"]
        right = np.column_stack([sight[near, 1], -sight[near, 0]]) / d[near, None]
        force = force + ((p["push"] * (p["reach"] / d[near] - 1))[:, None] * right).sum(axis=0)
        error = math.remainder(math.atan2(force[1], force[0]) - own.psi, 2 * math.pi)
        reach = vessel.max_yaw_accel * period
        omega = float(np.clip(p["gain"] * error, own.omega - reach, own.omega + reach))
        omega = float(np.clip(omega, -vessel.max_yaw_rate, vessel.max_yaw_rate))
        v = float(np.clip(vessel.max_speed, own.v - vessel.max_decel * period,
                          own.v + vessel.max_accel * period))
        return Decision(max(v, vessel.min_speed), omega)
