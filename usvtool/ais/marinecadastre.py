"""NOAA / BOEM MarineCadastre AIS CSV (marinecadastre.gov/ais), both of its layouts.

- 2009-2023: ``MMSI,BaseDateTime,LAT,LON,SOG,COG,Heading,VesselName,IMO,CallSign,VesselType,
  Status,Length,Width,Draft,Cargo,TransceiverClass``, times ``2022-01-03T00:00:07``;
- 2024 on: ``mmsi,base_date_time,longitude,latitude,sog,cog,heading,vessel_name,imo,call_sign,
  vessel_type,status,length,width,draft,cargo,transceiver``, times ``2025-01-01 00:00:00``
  (longitude before latitude).

Times are UTC, SOG knots, COG and heading degrees (heading 511: not available), length and
width metres, the vessel type the AIS code. Plain, gzip, zstd (the newer files' ``.csv.zst``) or
a zip holding the one CSV (the older files' ``.zip``).
"""

from __future__ import annotations

from usvtool.ais.fixes import Fixes
from usvtool.ais.table import read_columns

#: Each layout's column of each role.
LAYOUTS = {
    "upper": {"mmsi": "MMSI", "time": "BaseDateTime", "lat": "LAT", "lon": "LON", "sog": "SOG",
              "cog": "COG", "heading": "Heading", "name": "VesselName",
              "ship_type": "VesselType", "length": "Length", "beam": "Width"},
    "lower": {"mmsi": "mmsi", "time": "base_date_time", "lat": "latitude", "lon": "longitude",
              "sog": "sog", "cog": "cog", "heading": "heading", "name": "vessel_name",
              "ship_type": "vessel_type", "length": "length", "beam": "width"},
}  # fmt: skip
#: The columns that tell a layout.
SIGNATURE = {"upper": ("MMSI", "BaseDateTime", "LAT", "LON"),
             "lower": ("mmsi", "base_date_time", "latitude", "longitude")}  # fmt: skip


def layout(names: list[str]) -> str | None:
    """The layout (``upper`` or ``lower``) of a header, or None."""
    return next((k for k, cols in SIGNATURE.items() if all(c in names for c in cols)), None)


def read(path, names: list[str], bbox=None, guard=None) -> Fixes:
    """The fixes of a MarineCadastre file whose header is ``names`` (inside ``bbox``, ``guard``
    refusing more than the budget holds)."""
    columns = {role: c for role, c in LAYOUTS[layout(names)].items() if c in names}
    return read_columns(path, columns, bbox=bbox, guard=guard)
