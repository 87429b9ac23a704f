"""``apf``: an artificial potential field (Khatib, "Real-time obstacle avoidance for manipulators
and mobile robots", IJRR 5(1), 1986) for a ship: the goal attracts with a unit pull, each
target within ``reach`` metres repels with ``push (reach / d - 1)`` along the line from it,
and the resulting direction is turned ``starboard`` degrees to starboard while a target
repels (COLREGs Rules 14-15: alter course to starboard). The ship steers toward that heading
with a yaw rate proportional to the error, at full speed, within the vessel's limits."""

from __future__ import annotations

import math

import numpy as np

from usvtool.sim.controllers.base import Controller, Decision


class PotentialField(Controller):
    name = "apf"
    defaults = {"reach": 120.0, "push": 2.0, "starboard": 30.0, "gain": 1.0}

    def decide(self, own, targets, encounter=None) -> Decision:
        p, world = self.params, self.world
        vessel, period = world.vessel, world.period
        here = np.array([own.x, own.y])
        to_goal = world.goal - here
        pull = to_goal / max(float(np.hypot(*to_goal)), 1e-9)
        away = here - targets.pos  # (k, 2) from each target to the own ship
        d = np.maximum(np.hypot(away[:, 0], away[:, 1]), 1e-9)
        near = d < p["reach"]
        push = (p["push"] * (p["reach"] / d[near] - 1) / d[near])[:, None] * away[near]
        force = pull + push.sum(axis=0)
        course = math.atan2(force[1], force[0]) - near.any() * math.radians(p["starboard"])
        error = math.remainder(course - own.psi, 2 * math.pi)
        reach = vessel.max_yaw_accel * period
        omega = float(np.clip(p["gain"] * error, own.omega - reach, own.omega + reach))
        omega = float(np.clip(omega, -vessel.max_yaw_rate, vessel.max_yaw_rate))
        v = float(np.clip(vessel.max_speed, own.v - vessel.max_decel * period,
                          own.v + vessel.max_accel * period))
        return Decision(max(v, vessel.min_speed), omega)
