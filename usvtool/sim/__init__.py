"""Simulation stage: own ship (USV) among target ships, COLREGs encounters and their evaluation.

Entry points (docs/api.md): :func:`read_scenario` reads a scenario file (docs/scenario.md,
:mod:`.scenario`) and :func:`simulate` runs it (``usvtool simulate``, :mod:`.run`) as its
:class:`SimOptions` say; its :class:`SimResult` holds the trace, the events and the summary.
"""

from usvtool.sim.run import SimOptions, SimResult, simulate
from usvtool.sim.scenario import Scenario, read_scenario

__all__ = ["Scenario", "SimOptions", "SimResult", "read_scenario", "simulate"]
