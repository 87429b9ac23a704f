"""``udwa``: the utility DWA of the UDWA paper (section 3).

ccdwa's critics and weights (UDWA eq. 1, Table 3), with two changes:

- side priorities instead of removal: in an encounter the preferred half of the window (the
  ``paper`` side table, :mod:`usvtool.sim.sides`) scores ``1 + priority`` times higher, and the
  other half stays available when the preferred one is blocked or scores lower (COLREGs Rule 2;
  such a step is logged as a ``rule2-departure``). The paper gives no figure for the priority:
  0.5 is usvtool's choice (docs/simulate.md);
- the speed critic scores the speed the sample makes good in the wind and waves (eq. 5) rather
  than its calm-water speed (``weather``, on by default).
"""

from __future__ import annotations

from usvtool.sim.controllers.dwa import DWA


class UDWA(DWA):
    name = "udwa"
    parameters = {
        "w_velocity": 0.3,
        "w_heading": 0.2,
        "w_distance": 0.5,
        "sides": "paper",
        "priority": 0.5,
        "weather": True,
    }
