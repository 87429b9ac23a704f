"""``gdwa``: the route-guided DWA of IWSO-DWA (eqs. 22-25).

F'(v, omega) = sigma (alpha vel + beta head' + gamma dist + eta path)   (eq. 25)

- the sub-goal: the first vertex of the global route not yet reached (within ``reach`` metres,
  by default the distance the ship covers in one horizon at full speed, or passed: the ship's
  projection on the route leg beyond it); the goal once the route is done. Without a route the
  route is the straight line to the goal;
- ``head'`` (eq. 23) = |theta_c - theta_st|, theta_c the bearing from the own ship to the
  sub-goal (eq. 22, whose "tan" is the arctangent of the two coordinate differences, read as
  ``atan2``) and theta_st the rollout's final heading; as a reward, pi less it;
- ``path`` (eq. 24): the distance from the rollout's closest point to the sub-goal (the end of
  a rollout through the sub-goal lies beyond it); as a reward, the largest over the samples less
  it;
- ``sigma``, the smoothing factor, scales every score alike and so does not change the choice:
  the normalisation (UDWA eqs. 2-4) stands in for it, as in Fox et al. 1997.

Weights from the paper's section 5.2: alpha 0.3 (speed), beta 0.06 (heading), gamma 0.4
(clearance); the paper gives no figure for eta: 0.06, the heading's weight, is usvtool's choice.
In an encounter the IWSO-DWA paper's section 4.1 actions (the ``iwso`` side table) are preferred
with ``priority`` 0.5.
"""

from __future__ import annotations

import numpy as np

from usvtool.errors import UsvError
from usvtool.sim.controllers.base import Controller, Own, Rollouts, World


class GDWA(Controller):
    name = "gdwa"
    defaults = {
        "w_velocity": 0.3,
        "w_heading": 0.06,
        "w_distance": 0.4,
        "w_path": 0.06,
        "reach": None,
    }

    def __init__(self, **params):
        super().__init__(**{"sides": "iwso", "priority": 0.5, **params})
        if self.params["reach"] is not None and not self.params["reach"] > 0:
            raise UsvError(f"gdwa: reach must be > 0, not {self.params['reach']}")

    def reset(self, world: World) -> None:
        super().reset(world)
        route = world.route if world.route is not None else np.zeros((1, 2))
        self.route = np.vstack([route, world.goal])  # the goal closes the route
        self.next = min(1, len(self.route) - 1)
        reach = self.params["reach"]
        self.reach = reach if reach is not None else world.vessel.max_speed * self.params["horizon"]

    def subgoal(self, own: Own) -> np.ndarray:
        """The current sub-goal, advancing past the vertices reached or passed."""
        here = np.array([own.x, own.y])
        while self.next < len(self.route) - 1:
            a, b = self.route[self.next - 1], self.route[self.next]
            leg = b - a
            passed = np.dot(here - a, leg) >= np.dot(leg, leg)
            if np.linalg.norm(b - here) > self.reach and not passed:
                break
            self.next += 1
        return self.route[self.next]

    def terms(self, own: Own, r: Rollouts) -> list[tuple[float, np.ndarray]]:
        p = self.params
        sub = self.subgoal(own)
        theta_c = np.arctan2(sub[1] - own.y, sub[0] - own.x)  # eq. 22
        path = np.sqrt((np.square(r.x - sub[0]) + np.square(r.y - sub[1])).min(axis=0))  # eq. 24
        return [
            (p["w_velocity"], self.velocity(r)),
            (p["w_heading"], self.heading(r, theta_c)),  # eq. 23
            (p["w_distance"], self.distance(r)),
            (p["w_path"], path.max() - path),
        ]
