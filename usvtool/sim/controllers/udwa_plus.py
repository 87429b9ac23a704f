"""``udwa+``: UDWA (:mod:`usvtool.sim.controllers.udwa`) on a trajectory-rollout window, its side
bonus kept for the samples that pass at a safe distance. A variant, not in the papers
(docs/controllers.md, "udwa+"): a configuration of parts, udwa's critics and side table with
the horizon's generator and a side rule that prefers only where it is safe.

The faithful ``udwa`` samples the window of one control period (IWSO-DWA eq. 19, Fox et al.
1997) and holds every sample over the horizon. For the UDWA paper's boat (5 deg/s² of yaw
acceleration) a 0.1 s period reaches 0.5 deg/s either way, so over a 10 s horizon every rollout
runs within 5 degrees of the present course: nothing tells the sides apart until the encounter
is close, and once she turns, her window holds no yaw rate of the other sign. Two parts change,
the rest (critics, scales, side table, priority) is udwa's:

- the generator ``window: horizon`` (:class:`~usvtool.sim.controllers.windows.HorizonWindow`):
  the samples span what the limits reach within the horizon (eq. 19 with the horizon for Delta
  t); each rollout accelerates from the present velocity toward its sample at the limits and
  then holds it (Gerkey and Konolige 2008, the trajectory rollout of ROS base_local_planner:
  :func:`usvtool.sim.vessel.ramps`), and the command for the next period is that ramp's first
  step;
- the side rule's ``safe_priority: true``: the preferred side's bonus goes only to samples whose
  clearance reaches ``dist_max`` (the UDWA paper's "safe distance", beyond which "there is no
  risk of collision"): "when there is an obstacle in the starboard direction ... the scores
  obtained will be lower", and the other side wins on its merits.
"""

from __future__ import annotations

from usvtool.sim.controllers.udwa import UDWA


class UDWAPlus(UDWA):
    name = "udwa+"
    parameters = {"window": "horizon", "safe_priority": True}  # and UDWA's
