"""Real traffic: AIS files read into tracks, the close-quarters encounters found in them, and
any of them written as a scenario that every controller runs (docs/ais.md).

A stage of its own: it reads AIS files and the tracks contract (:mod:`usvtool.tracks`), and
classifies with :mod:`usvtool.encounter` (the simulation's classifier); it imports no other
stage.
"""

from usvtool.ais.clean import CleanOptions
from usvtool.ais.encounters import EncounterOptions, EncounterResult, find_encounters
from usvtool.ais.read import ReadOptions, ReadResult, read_ais
from usvtool.ais.scenario import ScenarioOptions, ScenarioResult, make_scenario

__all__ = ["CleanOptions", "EncounterOptions", "EncounterResult", "ReadOptions", "ReadResult",
           "ScenarioOptions", "ScenarioResult", "find_encounters", "make_scenario",
           "read_ais"]  # fmt: skip
