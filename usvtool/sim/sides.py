"""Which way to turn for each COLREGs encounter class: the side tables of the controllers.

A side is ``STARBOARD`` (a turn to the right: a negative yaw rate in the simulation's
mathematical, counter-clockwise convention), ``PORT`` (positive yaw rate) or ``EITHER``. The
UDWA paper writes the yaw rate the other way round (its "starboard region (omega > 0)").

Tables, by encounter class (:data:`usvtool.encounter.CLASS_NAMES`):

- ``paper``: the UDWA paper's section 3, read closely. Its priority list sends "the first,
  second, and fourth scenarios in Figure 4" (head-on, crossing from starboard, overtaking) to
  starboard and "the third and fourth scenarios" (crossing from port, overtaking) to port.
  Overtaking is listed under both; its section 4.1 overtaking run pre-steers to starboard, and
  CCDWA there excludes the port side, so overtaking goes to starboard. The crossing from port,
  where the own ship is the stand-on vessel, goes to port: that is the paper's rule, and it is
  against Rule 17(c) (a stand-on vessel that must act shall not turn to port for a vessel on
  her own port side). CCDWA (the UDWA paper's description of it) removes the other side, UDWA
  prefers this one.
- ``colregs``: the rules themselves. Head-on: starboard (Rule 14). Crossing give-way: starboard,
  so as not to cross ahead (Rules 15, 16). Crossing stand-on and being overtaken: starboard if
  she must act, never port (Rule 17(c)); keeping course and speed (Rule 17(a)) is judged by the
  verdicts, not forced by a side. Overtaking: either side (Rule 13).
- ``iwso``: the IWSO-DWA paper's section 4.1, for the route-guided controller: head-on,
  crossing from port and crossing from starboard all "adjust the starboard"; overtaking is
  allowed "from the port side or starboard", and both of its overtaking runs (section 5.3,
  env1 and env2) turn "to the upper right": starboard.
"""

from __future__ import annotations

STARBOARD, EITHER, PORT = -1, 0, 1
NAMES = {STARBOARD: "starboard", EITHER: "either", PORT: "port"}

TABLES: dict[str, dict[str, int]] = {
    "paper": {
        "head-on": STARBOARD,
        "crossing-give-way": STARBOARD,
        "crossing-stand-on": PORT,
        "overtaking": STARBOARD,
        "overtaken": EITHER,
    },
    "colregs": {
        "head-on": STARBOARD,
        "crossing-give-way": STARBOARD,
        "crossing-stand-on": STARBOARD,
        "overtaking": EITHER,
        "overtaken": STARBOARD,
    },
    "iwso": {
        "head-on": STARBOARD,
        "crossing-give-way": STARBOARD,
        "crossing-stand-on": STARBOARD,
        "overtaking": STARBOARD,
        "overtaken": EITHER,
    },
}


def side_for(table: str, encounter: str | None) -> int:
    """The side ``table`` gives an encounter class (``EITHER`` for none or an unlisted class).

    >>> side_for("paper", "crossing-stand-on"), side_for("colregs", "crossing-stand-on")
    (1, -1)
    >>> side_for("paper", None)
    0
    """
    return TABLES[table].get(encounter, EITHER) if encounter else EITHER
