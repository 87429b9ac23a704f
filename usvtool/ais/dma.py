"""The Danish Maritime Authority's AIS CSV (web.ais.dk/aisdata, ``aisdk-YYYY-MM-DD.csv``).

Header ``# Timestamp,Type of mobile,MMSI,Latitude,Longitude,Navigational status,ROT,SOG,COG,
Heading,IMO,Callsign,Name,Ship type,Cargo type,Width,Length,Type of position fixing device,
Draught,Destination,ETA,Data source type,A,B,C,D``; timestamps ``dd/mm/yyyy HH:MM:SS`` (UTC).
Only the rows of ``Class A`` and ``Class B`` transponders are fixes (base stations, aids to
navigation, SAR aircraft ... are counted as ``not_vessels``). The ship type is text, turned into
the AIS code of its class (:data:`SHIP_TYPES`, ITU-R M.1371-5 table 53: the first code of each
range; a text not listed is 0, not available).
"""

from __future__ import annotations

from usvtool.ais.fixes import Fixes
from usvtool.ais.table import read_columns

COLUMNS = {"time": "# Timestamp", "mmsi": "MMSI", "lat": "Latitude", "lon": "Longitude",
           "sog": "SOG", "cog": "COG", "heading": "Heading", "name": "Name",
           "ship_type": "Ship type", "length": "Length", "beam": "Width"}  # fmt: skip
MOBILE = "Type of mobile"
VESSELS = frozenset({"Class A", "Class B"})
TIME_FORMAT = "%d/%m/%Y %H:%M:%S"
#: The DMA's ship type texts (lower case) and their AIS codes.
SHIP_TYPES = {
    "wig": 20, "fishing": 30, "towing": 31, "towing long/wide": 32, "dredging": 33,
    "diving": 34, "military": 35, "sailing": 36, "pleasure": 37, "hsc": 40, "pilot": 50,
    "sar": 51, "tug": 52, "port tender": 53, "anti-pollution": 54, "law enforcement": 55,
    "medical": 58, "not party to conflict": 59, "passenger": 60, "cargo": 70, "tanker": 80,
    "other": 90,
}  # fmt: skip


def detect(names: list[str]) -> bool:
    return bool(names) and names[0] == COLUMNS["time"] and MOBILE in names


def read(path, names: list[str], bbox=None, guard=None) -> Fixes:
    """The fixes of a DMA file whose header is ``names`` (inside ``bbox``, ``guard`` refusing
    more than the budget holds)."""
    columns = {role: c for role, c in COLUMNS.items() if c in names}
    return read_columns(path, columns, time_formats=(TIME_FORMAT,), ship_types=SHIP_TYPES,
                        keep=(MOBILE, VESSELS, "not_vessels"), bbox=bbox,
                        guard=guard)  # fmt: skip
