"""``dwa``: the traditional Dynamic Window Approach toward the goal (IWSO-DWA eq. 21).

F(v, omega) = alpha vel + beta head + gamma dist, with the IWSO-DWA paper's section 5.2 weights
(alpha 0.3 on the speed, beta 0.06 on the heading, gamma 0.4 on the clearance), each term
normalised as in the UDWA paper's eqs. 2-4. ``head`` is pi less the angle between the heading
and the bearing to the goal where the rollout comes closest to the goal (its end unless it
passes the goal; Fox et al. 1997: :class:`~usvtool.sim.controllers.critics.GoalHeading`). The
one-period window, no side rule.
"""

from __future__ import annotations

from usvtool.params import Param
from usvtool.sim.controllers.base import DynamicWindow
from usvtool.sim.controllers.critics import Critic, Distance, GoalHeading, Velocity


class DWA(DynamicWindow):
    name = "dwa"
    parameters = {
        "w_velocity": Param(0.3, "the speed critic's scale (alpha)"),
        "w_heading": Param(0.06, "the heading critic's scale (beta)"),
        "w_distance": Param(0.4, "the clearance critic's scale (gamma)"),
    }

    def critics(self) -> list[Critic]:
        p = self.params
        return [
            Velocity(p["w_velocity"], p["weather"]),
            GoalHeading(p["w_heading"]),
            Distance(p["w_distance"], p["dist_max"]),
        ]
