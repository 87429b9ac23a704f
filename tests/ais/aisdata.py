"""Helpers of the AIS tests: the bundled sample, NMEA lines made with pyais's encoder, and
tracks built from positions in metres."""

from pathlib import Path

import numpy as np

from usvtool.tracks import NS, Tracks
from usvtool.traffic import EARTH_RADIUS

AIS = Path(__file__).resolve().parents[2] / "charts" / "ais"
NY = AIS / "AIS_2022_01_03_NYharbor_0000-0030.csv"
EXTRACT = AIS / "AIS_2022_01_03_first99999.csv.gz"
#: Metres per degree of latitude on the mean Earth sphere (the stage's local frame).
M_PER_DEG = EARTH_RADIUS * np.pi / 180.0
#: 2022-01-03T00:00:00Z, a multiple of every grid step used (seconds since the epoch).
T0 = 1_641_168_000


def tag(line: str, seconds: int) -> str:
    """``line`` behind an NMEA 4.10 tag block carrying the receiver time ``c:seconds``."""
    body = f"c:{seconds}"
    check = 0
    for ch in body.encode():
        check ^= ch
    return f"\\{body}*{check:02X}\\{line}"


def encode(fields: dict, seq_id=None) -> list[str]:
    """The sentences of one AIS message (pyais's encoder)."""
    import pyais

    return pyais.encode_dict(fields, talker_id="AI", sentence_type="VDM", seq_id=seq_id)


def tracks_from_metres(vessels: list[tuple[int, list[tuple[float, float, float]]]],
                       lat0: float = 0.0, lon0: float = 0.0, **static) -> Tracks:  # fmt: skip
    """Tracks of vessels ``(mmsi, [(t s from T0, x m east, y m north), ...])``, one track each,
    placed at (lon0, lat0) through the local east/north frame of the encounter search."""
    rows = []
    for track, (mmsi, fixes) in enumerate(sorted(vessels)):
        for t, x, y in fixes:
            lat = lat0 + y / M_PER_DEG
            lon = lon0 + x / (M_PER_DEG * np.cos(np.radians(lat)))
            rows.append((mmsi, (T0 + t) * NS, lon, lat, track))
    mmsi, time, lon, lat, track = (np.array(c) for c in zip(*rows, strict=True))
    return Tracks.from_columns(mmsi=mmsi, time=time.astype(np.int64), lon=lon, lat=lat,
                               track=track, **static)  # fmt: skip
