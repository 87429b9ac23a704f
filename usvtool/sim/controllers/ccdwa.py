"""``ccdwa``: the COLREGs-compliant DWA as the UDWA paper's section 3 describes it.

dwa's critics (:mod:`usvtool.sim.controllers.dwa`) with the UDWA paper's eq. 1 and Table 3
weights (alpha 0.2 on the heading, beta 0.5 on the clearance, gamma 0.3 on the speed), over the
dynamic window less one half: in an encounter that asks for a starboard turn the port half (yaw
rates to port) is removed from the search space, and the other way round (the ``paper`` side
table, :mod:`usvtool.sim.sides`; a side rule that removes).
"""

from __future__ import annotations

from usvtool.sim.controllers.dwa import DWA


class CCDWA(DWA):
    name = "ccdwa"
    parameters = {"w_velocity": 0.3, "w_heading": 0.2, "w_distance": 0.5, "sides": "paper"}
    removes_side = True
