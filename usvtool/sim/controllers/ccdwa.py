"""``ccdwa``: the COLREGs-compliant DWA as the UDWA paper's section 3 describes it.

The traditional DWA objective (UDWA eq. 1 with its Table 3 weights: alpha 0.2 on the heading,
beta 0.5 on the clearance, gamma 0.3 on the speed) over the dynamic window less one half: in an
encounter that asks for a starboard turn the port half (yaw rates to port) is removed from the
search space, and the other way round (the ``paper`` side table, :mod:`usvtool.sim.sides`).
"""

from __future__ import annotations

from usvtool.sim.controllers.dwa import DWA


class CCDWA(DWA):
    name = "ccdwa"
    defaults = {"w_velocity": 0.3, "w_heading": 0.2, "w_distance": 0.5}
    removes_side = True

    def __init__(self, **params):
        super().__init__(**{"sides": "paper", **params})
