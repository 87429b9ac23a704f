"""The tracks contract (usvtool/tracks.py): both files round trip, bad files and tables are
refused in one line naming the line or row and the column, nothing written."""

import numpy as np
import pytest

from usvtool.errors import UsvError
from usvtool.tracks import COLUMNS, NS, REALS, Tracks, read_tracks, to_arrow, write_tracks


def _table(**changes) -> Tracks:
    columns = dict(mmsi=[366000001, 366000001, 211000002], time=[0, 60 * NS, 30 * NS + 500],
                   lon=[-74.0, -73.99, 10.5], lat=[40.6, 40.6, 54.1], sog=[5.5, np.nan, 0.0],
                   cog=[90.0, np.nan, 359.9], heading=[np.nan, 91.0, 0.0],
                   length=[120.0, 120.0, np.nan], beam=[20.0, 20.0, np.nan],
                   name=['ALPHA, "A"', 'ALPHA, "A"', ''], ship_type=[70, 70, 0],
                   track=[0, 0, 1])  # fmt: skip
    return Tracks.from_columns(**(columns | changes))


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_round_trip(tmp_path, suffix):
    t = _table()
    path = tmp_path / f"t{suffix}"
    write_tracks(path, t)
    back = read_tracks(path)
    for c in COLUMNS:
        assert np.array_equal(getattr(back, c), getattr(t, c), equal_nan=c in REALS), c
    if suffix == ".csv":  # the header as the contract has it; nanoseconds kept exactly
        lines = path.read_text().splitlines()
        assert lines[0] == ",".join(COLUMNS)
        assert "1970-01-01T00:00:30.000000500Z" in lines[3]
    else:
        assert str(to_arrow(t).schema.field("time").type) == "timestamp[ns, tz=UTC]"


@pytest.mark.parametrize("change, words", [
    (dict(lat=[40.6, 95.0, 54.1]), "row 2, column lat: 95.0 is not a latitude"),
    (dict(time=[60 * NS, 0, 0]), "row 2, column time: rows must be sorted"),
    (dict(mmsi=[366000001, 366000009, 211000002]), "row 2, column mmsi: track 0 holds two"),
    (dict(cog=[360.0, 0.0, 0.0]), "row 1, column cog: 360.0 is not a course"),
])  # fmt: skip
def test_bad_tables_refused(change, words):
    with pytest.raises(UsvError, match=words):
        _table(**change)


def test_bad_files_name_line_and_column(tmp_path):
    path = tmp_path / "t.csv"
    write_tracks(path, _table())
    text = path.read_text()
    (tmp_path / "lon.csv").write_text(text.replace("-73.99", "east"))
    (tmp_path / "range.csv").write_text(text.replace("-73.99", "-273.99"))
    (tmp_path / "head.csv").write_text(text.replace("ship_type", "type"))
    for name, words in (("lon.csv", "lon.csv: line 3, column lon: 'east' is not a number"),
                        ("range.csv", "range.csv: line 3, column lon: -273.99 is not a longitude"),
                        ("head.csv", "head.csv: line 1: the header must be")):  # fmt: skip
        with pytest.raises(UsvError, match=words):
            read_tracks(tmp_path / name)
    with pytest.raises(UsvError, match="a tracks file is .parquet or .csv"):
        write_tracks(tmp_path / "t.json", _table())
    assert not (tmp_path / "t.json").exists()
