"""``gdwa``: the route-guided DWA of IWSO-DWA (eqs. 22-25).

F'(v, omega) = sigma (alpha vel + beta head' + gamma dist + eta path)   (eq. 25)

Its critics: :class:`~usvtool.sim.controllers.critics.Velocity`, ``head'``
(:class:`~usvtool.sim.controllers.critics.SubgoalHeading`), the clearance
(:class:`~usvtool.sim.controllers.critics.Distance`) and ``path``
(:class:`~usvtool.sim.controllers.critics.SubgoalPath`), the two of the sub-goal sharing the
route's progress (:class:`~usvtool.sim.controllers.critics.RouteProgress`):

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

from usvtool.params import POSITIVE, Param
from usvtool.sim.controllers.base import DynamicWindow
from usvtool.sim.controllers.critics import (
    Critic,
    Distance,
    RouteProgress,
    SubgoalHeading,
    SubgoalPath,
    Velocity,
)


class GDWA(DynamicWindow):
    name = "gdwa"
    parameters = {
        "w_velocity": Param(0.3, "the speed critic's scale (alpha)"),
        "w_heading": Param(0.06, "the sub-goal heading critic's scale (beta)"),
        "w_distance": Param(0.4, "the clearance critic's scale (gamma)"),
        "w_path": Param(0.06, "the sub-goal path critic's scale (eta)"),
        "reach": Param(None, "a route vertex within this is reached, m (null: one horizon "
                             "at full speed)", POSITIVE),
        "sides": "iwso",
        "priority": 0.5,
    }  # fmt: skip

    def critics(self) -> list[Critic]:
        p = self.params
        self.progress = RouteProgress(p["reach"], p["horizon"])  # shared by heading and path
        return [
            Velocity(p["w_velocity"], p["weather"]),
            SubgoalHeading(p["w_heading"], self.progress),  # eqs. 22-23
            Distance(p["w_distance"], p["dist_max"]),
            SubgoalPath(p["w_path"], self.progress),  # eq. 24
        ]
