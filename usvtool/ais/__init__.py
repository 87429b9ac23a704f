"""Real traffic: AIS files read into tracks, the close-quarters encounters found in them, and
any of them written as a scenario that every controller runs (docs/ais.md).

A stage of its own: it reads AIS files and the tracks contract (:mod:`usvtool.tracks`), and
classifies with :mod:`usvtool.encounter` (the simulation's classifier); it imports no other
stage.
"""

from usvtool.ais.clean import CleanOptions
from usvtool.ais.read import ReadOptions, ReadResult, read_ais

__all__ = ["CleanOptions", "ReadOptions", "ReadResult", "read_ais"]
