"""``dwa``: the traditional Dynamic Window Approach toward the goal (IWSO-DWA eq. 21).

F(v, omega) = alpha vel + beta head + gamma dist, with the IWSO-DWA paper's section 5.2 weights
(alpha 0.3 on the speed, beta 0.06 on the heading, gamma 0.4 on the clearance), each term
normalised as in the UDWA paper's eqs. 2-4. ``head`` is pi less the angle between the rollout's
final heading and the bearing from its end to the goal (Fox et al. 1997). No side rule.
"""

from __future__ import annotations

import numpy as np

from usvtool.sim.controllers.base import Controller, Own, Rollouts


class DWA(Controller):
    name = "dwa"
    defaults = {"w_velocity": 0.3, "w_heading": 0.06, "w_distance": 0.4}

    def terms(self, own: Own, r: Rollouts) -> list[tuple[float, np.ndarray]]:
        p = self.params
        return [
            (p["w_velocity"], self.velocity(r)),
            (p["w_heading"], self.heading(r, bearing(r.end, self.world.goal))),
            (p["w_distance"], self.distance(r)),
        ]


def bearing(points: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """Mathematical bearing (rad) from each point ``x + iy`` ``(N,)`` to ``goal`` ``(2,)``."""
    return np.angle(goal[0] + 1j * goal[1] - points)
