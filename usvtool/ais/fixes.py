"""What every format's reader returns: the raw position reports and static reports of one file.

Positions (``mmsi``, ``time`` ns UTC, ``lon``, ``lat``, ``sog`` kn, ``cog`` and ``heading`` compass
degrees) and static data (``mmsi``, ``time``, ``length`` and ``beam`` m, ``name``, ``ship_type``)
in file order, not yet cleaned (:mod:`usvtool.ais.clean`). The AIS codes for "not available"
(ITU-R M.1371-5, message 1 and 5 fields) become NaN, 0 or ``""`` here, once for all formats:
``sog`` 102.3 kn (and anything below 0), ``cog`` 360, ``heading`` 511 (anything outside
[0, 360)), a length or beam of 0 or less, a ship type outside 1 … 255; names lose the padding
``@`` and surrounding spaces.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: Speed over ground at and above this (kn) is "not available" (102.3) or "102.2 or more".
SOG_NOT_AVAILABLE = 102.2


@dataclass
class Fixes:
    """Positions and static reports of one file (module docstring), made by :func:`fixes`;
    ``name`` an object array of ``str``; ``counts`` the format's own tallies (lines skipped)."""

    mmsi: np.ndarray
    time: np.ndarray
    lon: np.ndarray
    lat: np.ndarray
    sog: np.ndarray
    cog: np.ndarray
    heading: np.ndarray
    static_mmsi: np.ndarray
    static_time: np.ndarray
    length: np.ndarray
    beam: np.ndarray
    name: np.ndarray
    ship_type: np.ndarray
    counts: dict = field(default_factory=dict)

    @property
    def n_positions(self) -> int:
        return int(self.mmsi.size)

    def within(self, bbox: tuple[float, float, float, float]) -> Fixes:
        """The positions inside ``bbox`` (lon min, lat min, lon max, lat max; all the static
        reports kept), those outside counted as ``outside_bbox``."""
        with np.errstate(invalid="ignore"):
            inside = ((self.lon >= bbox[0]) & (self.lon <= bbox[2]) & (self.lat >= bbox[1])
                      & (self.lat <= bbox[3]))  # fmt: skip
        kept = {n: getattr(self, n)[inside] for n in ("mmsi", "time", "lon", "lat", "sog", "cog",
                                                      "heading")}  # fmt: skip
        counts = self.counts | {"outside_bbox": self.counts.get("outside_bbox", 0)
                                + int((~inside).sum())}  # fmt: skip
        return Fixes(**kept, static_mmsi=self.static_mmsi, static_time=self.static_time,
                     length=self.length, beam=self.beam, name=self.name,
                     ship_type=self.ship_type, counts=counts)  # fmt: skip

    @classmethod
    def concatenate(cls, parts: list[Fixes]) -> Fixes:
        """The fixes of several files, in the order given; their counts summed."""
        names = ("mmsi", "time", "lon", "lat", "sog", "cog", "heading", "static_mmsi",
                 "static_time", "length", "beam", "name", "ship_type")  # fmt: skip
        counts: dict = {}
        for p in parts:
            for k, v in p.counts.items():
                counts[k] = counts.get(k, 0) + v
        return cls(**{n: np.concatenate([getattr(p, n) for p in parts]) for n in names},
                   counts=counts)  # fmt: skip


def check_bbox(box, option: str = "--bbox") -> tuple[float, float, float, float] | None:
    """``box`` as four floats (lon min, lat min, lon max, lat max; degrees, min < max), or None;
    one line naming ``option`` otherwise.

    >>> check_bbox([-74.3, 40.45, -73.85, 40.75])
    (-74.3, 40.45, -73.85, 40.75)
    """
    from usvtool.errors import UsvError

    if box is None:
        return None
    values = tuple(float(v) for v in box)
    if len(values) != 4 or not (-180 <= values[0] < values[2] <= 180
                                and -90 <= values[1] < values[3] <= 90):  # fmt: skip
        raise UsvError(f"{option}: {tuple(box)} is not LON_MIN,LAT_MIN,LON_MAX,LAT_MAX (degrees, "
                       "min < max)")  # fmt: skip
    return values


def fixes(mmsi, time, lon, lat, sog, cog, heading, static_mmsi, static_time, length, beam,
          name, ship_type, counts=None) -> Fixes:  # fmt: skip
    """:class:`Fixes` of the columns given (arrays, sequences or pyarrow arrays; ``name`` texts
    or None), the "not available" codes replaced (module docstring)."""
    ints = {k: np.asarray(v, np.int64) for k, v in (("mmsi", mmsi), ("time", time),
            ("static_mmsi", static_mmsi), ("static_time", static_time))}  # fmt: skip
    sog, cog, heading, length, beam = (np.asarray(a, float) for a in (sog, cog, heading, length,
                                                                     beam))  # fmt: skip
    ship_type = np.asarray(ship_type, np.int64)
    with np.errstate(invalid="ignore"):
        return Fixes(
            **ints, lon=np.asarray(lon, float), lat=np.asarray(lat, float),
            sog=np.where((sog >= 0) & (sog < SOG_NOT_AVAILABLE), sog, np.nan),
            cog=np.where((cog >= 0) & (cog < 360), cog, np.nan),
            heading=np.where((heading >= 0) & (heading < 360), heading, np.nan),
            length=np.where(length > 0, length, np.nan), beam=np.where(beam > 0, beam, np.nan),
            name=clean_names(name),
            ship_type=np.where((ship_type >= 1) & (ship_type <= 255), ship_type, 0),
            counts=dict(counts or {}),
        )  # fmt: skip


def clean_names(names) -> np.ndarray:
    """The names (a pyarrow array, or any sequence of texts or None) cleaned by
    :func:`_clean_name`, as an object array; a pyarrow array's distinct values are cleaned once."""
    if hasattr(names, "dictionary_encode"):  # pyarrow: clean each distinct value once
        import pyarrow as pa

        encoded = names.dictionary_encode()
        if isinstance(encoded, pa.ChunkedArray):
            encoded = encoded.combine_chunks()
        values = np.array([_clean_name(s) for s in encoded.dictionary.to_pylist()] + [""],
                          dtype=object)  # fmt: skip
        codes = encoded.indices.fill_null(len(values) - 1).to_numpy(zero_copy_only=False)
        return values[codes]
    return np.array([_clean_name(s) for s in names], dtype=object)


def _clean_name(text) -> str:
    """A vessel name without AIS padding (``@``), line breaks or surrounding spaces."""
    s = "" if text is None else str(text)
    return " ".join(s.replace("@", " ").split())


def from_columns(mmsi, time, lon, lat, sog=None, cog=None, heading=None, length=None,
                 beam=None, name=None, ship_type=None, counts=None) -> Fixes:  # fmt: skip
    """Fixes of a table whose every row is a position report carrying the vessel's static data
    (the CSV formats); a column not given (None) is not available."""
    n = len(mmsi)
    nan = np.full(n, np.nan)
    return fixes(
        mmsi, time, lon, lat,
        nan if sog is None else sog, nan if cog is None else cog,
        nan if heading is None else heading, mmsi, time,
        nan if length is None else length, nan if beam is None else beam,
        [""] * n if name is None else name,
        np.zeros(n, np.int64) if ship_type is None else ship_type, counts,
    )  # fmt: skip
