"""usvtool ais read: every format on small files written here, the cleaning's counts computed by
hand, bad files refused in one line naming file, line and column, with nothing written."""

import gzip
import json

import numpy as np
import pytest

from usvtool.ais import CleanOptions, ReadOptions, read_ais
from usvtool.ais.read import detect
from usvtool.errors import UsvError
from usvtool.tracks import NS, read_tracks

from .aisdata import EXTRACT, NY, T0, encode, tag

UPPER = ("MMSI,BaseDateTime,LAT,LON,SOG,COG,Heading,VesselName,IMO,CallSign,VesselType,Status,"
         "Length,Width,Draft,Cargo,TransceiverClass")  # fmt: skip
LOWER = ("mmsi,base_date_time,longitude,latitude,sog,cog,heading,vessel_name,imo,call_sign,"
         "vessel_type,status,length,width,draft,cargo,transceiver")  # fmt: skip
DMA = ("# Timestamp,Type of mobile,MMSI,Latitude,Longitude,Navigational status,ROT,SOG,COG,"
       "Heading,IMO,Callsign,Name,Ship type,Cargo type,Width,Length,"
       "Type of position fixing device,Draught,Destination,ETA,Data source type,"
       "A,B,C,D")  # fmt: skip


def test_marinecadastre_upper_layout_gzip(tmp_path):
    path = tmp_path / "AIS_2022_01_03.csv.gz"
    rows = [UPPER,
            "367000001,2022-01-03T00:01:00,40.60000,-74.00000,10.0,90.0,511,TUG ONE,,WX,31.0,0,"
            "25,8,,52,A",
            "367000001,2022-01-03T00:00:00,40.60000,-74.01000,10.0,90.0,91,TUG ONE,,WX,31,0,25,"
            "8,,52,A"]  # fmt: skip
    path.write_bytes(gzip.compress(("\n".join(rows) + "\n").encode()))
    assert detect(path) == "marinecadastre"
    t = read_ais([path]).tracks
    assert t.time.tolist() == [(T0 + 0) * NS, (T0 + 60) * NS]  # put in order
    assert t.lon.tolist() == [-74.01, -74.0]
    assert np.isnan(t.heading[1]) and t.heading[0] == 91.0  # 511: not available
    assert t.name.tolist() == ["TUG ONE"] * 2 and t.ship_type.tolist() == [31, 31]
    assert t.length.tolist() == [25.0, 25.0] and t.beam.tolist() == [8.0, 8.0]


def test_marinecadastre_lower_layout(tmp_path):
    path = tmp_path / "ais-2025-01-01.csv"
    path.write_text(f"{LOWER}\n368000002,2025-01-01 00:00:00,-76.43,36.96,4.7,321.6,327,"
                    "PATRICIA B. MORAN,IMO1079618,WDP7519,52,0,26,11,5.0,52,A\n")  # fmt: skip
    t = read_ais([path]).tracks
    assert (t.lon[0], t.lat[0], t.sog[0], t.cog[0], t.heading[0]) == (-76.43, 36.96, 4.7, 321.6,
                                                                       327.0)  # fmt: skip
    assert t.time[0] == 1_735_689_600 * NS and t.name[0] == "PATRICIA B. MORAN"


def test_dma_keeps_vessels_and_reads_day_first_times(tmp_path):
    path = tmp_path / "aisdk-2022-01-03.csv"
    names = DMA.split(",")

    def row(**values):
        return ",".join(str(values.get(n.replace(" ", "_").replace("#_", ""), "")) for n in names)

    path.write_text("\n".join([
        DMA,
        row(Timestamp="03/01/2022 00:00:05", Type_of_mobile="Class A", MMSI=219000001,
            Latitude=55.6, Longitude=12.6, SOG=8.0, COG=180.0, Heading=181, Name="NORDIC FERRY",
            Ship_type="Passenger", Width=20, Length=120),
        row(Timestamp="03/01/2022 00:00:06", Type_of_mobile="Base Station", MMSI=2190047,
            Latitude=55.7, Longitude=12.61, Ship_type="Undefined"),
        row(Timestamp="03/01/2022 00:01:05", Type_of_mobile="Class B", MMSI=219000002,
            Latitude=55.61, Longitude=12.62, SOG=3.0, COG=90.0, Name="LILLE BAAD",
            Ship_type="Sailing", Width=3, Length=10),
    ]) + "\n")  # fmt: skip
    assert detect(path) == "dma"
    result = read_ais([path])
    t = result.tracks
    assert t.mmsi.tolist() == [219000001, 219000002]
    assert t.time.tolist() == [(T0 + 5) * NS, (T0 + 65) * NS]  # 03/01 is 3 January
    assert t.ship_type.tolist() == [60, 36] and t.length.tolist() == [120.0, 10.0]
    assert result.files[0]["not_vessels"] == 1


def test_nmea_tag_blocks_multi_sentence_static_joined(tmp_path):
    own = 366000001
    pos = [encode({"type": 1, "mmsi": own, "lat": 40.6 + i * 0.001, "lon": -74.0, "speed": 6.2,
                   "course": 0.0, "heading": 1})[0] for i in range(3)]  # fmt: skip
    static = encode({"type": 5, "mmsi": own, "shipname": "SEA HAWK", "ship_type": 70,
                     "to_bow": 80, "to_stern": 20, "to_port": 6, "to_starboard": 8}, seq_id=3)
    assert len(static) == 2  # a two-sentence message
    bad = pos[2][:-2] + ("00" if not pos[2].endswith("00") else "11")  # a wrong checksum
    lines = [tag(pos[0], T0), tag(static[0], T0 + 10), static[1],  # the second has no time
             "$GPGGA,000000.00,4036.000,N,07400.000,W,1,08,0.9,10.0,M,,,,*47",
             tag(pos[1], T0 + 30), tag(bad, T0 + 40), tag(pos[2], T0 + 60)]  # fmt: skip
    path = tmp_path / "log.nmea"
    path.write_text("\n".join(lines) + "\n")
    assert detect(path) == "nmea"
    result = read_ais([path])
    t = result.tracks
    assert t.time.tolist() == [(T0 + s) * NS for s in (0, 30, 60)]
    assert np.allclose(t.lat, [40.6, 40.601, 40.602], atol=2e-6)
    assert t.sog.tolist() == [6.2] * 3 and t.heading.tolist() == [1.0] * 3
    assert t.name.tolist() == ["SEA HAWK"] * 3 and t.length.tolist() == [100.0] * 3
    assert t.beam.tolist() == [14.0] * 3 and t.ship_type.tolist() == [70] * 3
    counts = result.files[0]
    assert (counts["bad_checksum"], counts["not_ais"], counts["incomplete"]) == (1, 1, 0)


def test_nmea_leading_time_column_class_b_and_type_24(tmp_path):
    mmsi = 338000001
    b = encode({"type": 18, "mmsi": mmsi, "lat": 40.5, "lon": -74.1, "speed": 3.0, "course": 90.0,
                "heading": 511})[0]  # fmt: skip
    a = encode({"type": 24, "mmsi": mmsi, "partno": 0, "shipname": "LITTLE ONE"})[0]
    part_b = encode({"type": 24, "mmsi": mmsi, "partno": 1, "ship_type": 37, "to_bow": 5,
                     "to_stern": 3, "to_port": 1, "to_starboard": 2})[0]  # fmt: skip
    path = tmp_path / "rx.txt"
    path.write_text(f"2022-01-03T00:00:00Z,{b}\n{T0 + 5}.5 {a}\n2022-01-03T00:00:09+00:00;"
                    f"{part_b}\n")  # fmt: skip
    t = read_ais([path]).tracks
    assert t.time.tolist() == [T0 * NS] and np.isnan(t.heading[0])
    assert (t.name[0], t.ship_type[0], t.length[0], t.beam[0]) == ("LITTLE ONE", 37, 8.0, 3.0)


def test_generic_csv_semicolons_usual_names_and_columns_option(tmp_path):
    path = tmp_path / "export.csv"
    path.write_text("Ship ID;When;Latitude;Longitude;Speed;Ship name\n"
                    f"211000001;{T0};54.1;10.2;12.5;MS TEST\n"
                    f"211000001;{T0 + 30};54.1;10.21;12.5;MS TEST\n")  # fmt: skip
    with pytest.raises(UsvError, match="no column for mmsi, time .*--columns"):
        read_ais([path])
    options = ReadOptions(columns={"mmsi": "Ship ID", "time": "When"})
    t = read_ais([path], options).tracks
    assert t.time.tolist() == [T0 * NS, (T0 + 30) * NS]  # Unix seconds
    assert t.lon.tolist() == [10.2, 10.21] and t.sog.tolist() == [12.5, 12.5]
    assert t.name.tolist() == ["MS TEST"] * 2


def test_cleaning_counts_by_hand(tmp_path):
    """Vessel 1: fixes at 0, 60, 120 s 300 m apart (5 m/s), the 60 s one twice (a duplicate),
    30 s after 120 s in the file (out of order), a jump of 10 km at 180 s (too fast), 240 s back
    on her line, 2000 s after a 1760 s gap (a new track); MMSI 0 (invalid), latitude 91 and
    0,0 (invalid positions); vessel 2: one fix."""
    lat0, dlat = 40.0, 300.0 / 111_195.08  # 300 m of latitude
    rows = ["mmsi,time,lat,lon"]
    for t, k in ((0, 0), (60, 1), (60, 1), (120, 2), (30, 0.5), (180, 40), (240, 4),
                 (2000, 10)):  # fmt: skip
        rows.append(f"366000001,{T0 + t},{lat0 + k * dlat:.7f},-74.0")
    rows += [f"0,{T0},40.0,-74.0", f"366000002,{T0},91,-74.0", f"366000002,{T0 + 5},0,0",
             f"366000002,{T0 + 9},40.1,-74.1"]  # fmt: skip
    path = tmp_path / "fixes.csv"
    path.write_text("\n".join(rows) + "\n")
    result = read_ais([path], ReadOptions(clean=CleanOptions(max_gap=600, max_speed=50)))
    c = result.counts
    assert (c["fixes_read"], c["invalid_mmsi"], c["invalid_position"], c["out_of_order"],
            c["duplicates"], c["too_fast"], c["gaps"]) == (12, 1, 2, 1, 1, 1, 1)  # fmt: skip
    t = result.tracks
    assert (t.time // NS - T0).tolist() == [0, 30, 60, 120, 240, 2000, 9]
    assert t.track.tolist() == [0, 0, 0, 0, 0, 1, 2]
    assert (c["fixes"], c["vessels"], c["tracks"]) == (7, 2, 3)


@pytest.mark.parametrize("name, text, words", [
    ("lat.csv", f"{UPPER}\n367000001,2022-01-03T00:00:00,40.6,-74.0,1,2,3,A,,,31,0,2,1,,,A\n"
                "367000001,2022-01-03T00:01:00,north,-74.0,1,2,3,A,,,31,0,2,1,,,A\n",
     "lat.csv: line 3, column LAT: 'north' is not a number"),
    ("time.csv", f"{UPPER}\n367000001,2022-01-03T00:00:00,40.6,-74.0,1,2,3,A,,,31,0,2,1,,,A\n"
                 "367000001,yesterday,40.6,-74.0,1,2,3,A,,,31,0,2,1,,,A\n",
     "time.csv: line 3, column BaseDateTime: 'yesterday' is not a time"),
    ("ragged.csv", "mmsi,time,lat,lon\n1,2022-01-03T00:00:00,1,2\n1,2022-01-03T00:01:00,1\n",
     "ragged.csv: line 3: 3 fields, expected 4"),
    ("dma.csv", f"{DMA}\n03/13/2022 00:00:05,Class A,219000001,55.6,12.6" + "," * 21 + "\n",
     "dma.csv: line 2, column # Timestamp: '03/13/2022 00:00:05' is not a time"),
])  # fmt: skip
def test_bad_files_refused_in_one_line_nothing_written(usv, tmp_path, name, text, words):
    path = tmp_path / name
    path.write_text(text)
    out = tmp_path / "tracks.parquet"
    result = usv("ais", "read", path, "-o", out)
    assert result.exit_code == 1
    line = result.stderr.strip()
    assert "\n" not in line and words in line, line
    assert not out.exists() and list(tmp_path.iterdir()) == [path]


def test_nmea_message_without_time_refused(usv, tmp_path):
    sentence = encode({"type": 1, "mmsi": 366000001, "lat": 40.6, "lon": -74.0})[0]
    path = tmp_path / "log.nmea"
    path.write_text(tag(sentence, T0) + "\n" + sentence + "\n")
    result = usv("ais", "read", path, "-o", tmp_path / "t.csv")
    assert result.exit_code == 1 and "log.nmea: line 2: no time" in result.stderr
    assert not (tmp_path / "t.csv").exists()


def test_cli_reads_the_new_york_sample(usv, tmp_path):
    out = tmp_path / "ny.parquet"
    result = usv("ais", "read", NY, "-o", out, "--summary", tmp_path / "s.json")
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary == json.loads((tmp_path / "s.json").read_text())
    assert (summary["fixes"], summary["vessels"], summary["files"][0]["format"]) == (
        2411, 187, "marinecadastre")  # the PROVENANCE's counts
    t = read_tracks(out)
    assert t.n_rows == 2411 and np.unique(t.mmsi).size == 187


def test_bbox_reads_the_new_york_subset_out_of_the_extract(tmp_path):
    """The New York file is the extract's rows inside its box (PROVENANCE.md): read through
    --bbox, the extract gives the same tracks."""
    box = (-74.30, 40.45, -73.85, 40.75)
    result = read_ais([EXTRACT], ReadOptions(bbox=box))
    assert result.files[0]["positions"] == 2411
    assert result.files[0]["outside_bbox"] == 99_999 - 2411
    whole = read_ais([NY]).tracks
    for column in ("mmsi", "time", "lon", "lat", "track", "name"):
        assert np.array_equal(getattr(result.tracks, column), getattr(whole, column)), column
    bad = tmp_path / "bad.csv"  # a fault inside the box is named at its own line
    bad.write_text("mmsi,time,lat,lon\n1,2022-01-03T00:00:00,10,10\n2,2022-01-03T00:00:00,40.5,"
                   "-74\n3,noon,40.5,-74\n")  # fmt: skip
    with pytest.raises(UsvError, match="bad.csv: line 4, column time: 'noon'"):
        read_ais([bad], ReadOptions(bbox=box))
