"""Any other CSV of AIS fixes: its delimiter detected, its columns recognised by their usual
names or named with ``--columns ROLE=NAME,...``.

The delimiter is the one :class:`csv.Sniffer` finds among ``,`` ``;`` tab and ``|`` in the first
lines (a comma when it finds none). A column plays a role (:data:`usvtool.ais.table.ROLES`) when
``--columns`` names it, else when its name, lower-cased without spaces, ``_``, ``-`` or ``#``, is
one of :data:`ALIASES`; mmsi, time, lat and lon are required. Times are ISO 8601 (UTC unless a
zone is given), ``dd/mm/yyyy HH:MM:SS`` (UTC) or Unix seconds; the ship type an AIS code or a
DMA type text (:data:`usvtool.ais.dma.SHIP_TYPES`). Units: knots, degrees, metres.
"""

from __future__ import annotations

import csv
import re

from usvtool.ais import dma
from usvtool.ais.fixes import Fixes
from usvtool.ais.table import ROLES, header, read_columns
from usvtool.errors import UsvError

#: Usual column names of each role (lower case, without spaces, ``_``, ``-`` or ``#``).
ALIASES = {
    "mmsi": {"mmsi", "userid", "sourcemmsi", "mmsinumber"},
    "time": {"time", "timestamp", "datetime", "basedatetime", "datetimeutc", "timeutc", "utc",
             "t", "ts", "timestamputc", "receivedtime", "date"},
    "lat": {"lat", "latitude", "latdeg"},
    "lon": {"lon", "long", "longitude", "lng", "londeg"},
    "sog": {"sog", "speed", "speedoverground", "sogkn", "sogknots", "speedknots"},
    "cog": {"cog", "course", "courseoverground"},
    "heading": {"heading", "hdg", "trueheading", "truehdg"},
    "length": {"length", "len", "loa", "shiplength", "lengthm"},
    "beam": {"beam", "width", "breadth", "shipwidth", "widthm"},
    "name": {"name", "vesselname", "shipname", "vessel"},
    "ship_type": {"shiptype", "vesseltype", "shipandcargotype", "shiptypecode"},
}  # fmt: skip
DELIMITERS = ",;\t|"
TIME_FORMATS = (dma.TIME_FORMAT, "%Y/%m/%d %H:%M:%S")


def parse_columns(text: str | None) -> dict[str, str]:
    """``ROLE=NAME,...`` (the ``--columns`` option) as a dict; one line naming the fault.

    >>> parse_columns("mmsi=ID,time=When")
    {'mmsi': 'ID', 'time': 'When'}
    """
    if not text:
        return {}
    mapping = {}
    for item in text.split(","):
        role, sep, name = (s.strip() for s in item.partition("="))
        if not sep or not role or not name:
            raise UsvError(f"--columns: {item!r} is not ROLE=NAME")
        if role not in ROLES:
            raise UsvError(f"--columns: {role!r} is not a role ({', '.join(ROLES)})")
        if role in mapping:
            raise UsvError(f"--columns: {role} given twice")
        mapping[role] = name
    return mapping


def sniff(path) -> str:
    """The delimiter of the file's first lines (module docstring)."""
    from usvtool.ais.source import first_lines

    sample = "\n".join(first_lines(path, 20))
    try:
        return csv.Sniffer().sniff(sample, delimiters=DELIMITERS).delimiter
    except csv.Error:
        return ","


def roles(names: list[str], mapping: dict[str, str]) -> dict[str, str]:
    """The column of each role: ``mapping``'s, else the first whose name is an alias."""
    out = dict(mapping)
    taken = set(mapping.values())
    for name in names:
        key = re.sub(r"[\s_\-#]", "", name.lower())
        role = next((r for r, aliases in ALIASES.items() if key in aliases), None)
        if role is not None and role not in out and name not in taken:
            out[role] = name
            taken.add(name)
    return out


def read(path, mapping: dict[str, str], bbox=None, guard=None) -> Fixes:
    """The fixes of a CSV file by ``mapping`` (role: column) and the usual names (inside
    ``bbox``, ``guard`` refusing more than the budget holds)."""
    delimiter = sniff(path)
    names = header(path, delimiter)
    return read_columns(path, roles(names, mapping), delimiter=delimiter,
                        time_formats=TIME_FORMATS, epoch_seconds=True,
                        ship_types=dma.SHIP_TYPES, bbox=bbox, guard=guard)  # fmt: skip
