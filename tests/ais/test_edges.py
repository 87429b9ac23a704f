"""usvtool ais at its edges: input text never becomes YAML or a spreadsheet formula, bombs and
huge grids refused before memory runs out, bad files refused in one line (exit 1, never a
traceback), and a scenario that removes only what the previous one wrote."""

import csv
import gzip
import io
import json
import zipfile

import numpy as np
import pyarrow as pa
import pytest
import yaml

from usvtool.ais import ReadOptions, read_ais
from usvtool.ais.encounters import find_encounters, write_encounters
from usvtool.ais.source import MAX_LINE
from usvtool.errors import UsvError
from usvtool.tracks import NS, Tracks, read_tracks, spreadsheet_safe, write_tracks

from .aisdata import NY, T0, encode, tag, tracks_from_metres

HEADER = ["MMSI", "BaseDateTime", "LAT", "LON", "SOG", "COG", "Heading", "VesselName", "IMO",
          "CallSign", "VesselType", "Status", "Length", "Width", "Draft", "Cargo",
          "TransceiverClass"]  # fmt: skip
DMA = ("# Timestamp,Type of mobile,MMSI,Latitude,Longitude,Navigational status,ROT,SOG,COG,"
       "Heading,IMO,Callsign,Name,Ship type,Cargo type,Width,Length,"
       "Type of position fixing device,Draught,Destination,ETA,Data source type,"
       "A,B,C,D")  # fmt: skip
#: Names a spreadsheet takes for formulas (OWASP's examples), and harmless ones.
FORMULAS = ['=HYPERLINK("http://x","click")', "+1-2", "-cmd", "@SUM(A1)"]
#: An OWASP-safe cell: the name behind one ' (and a formula name quoted, its quotes doubled).
SAFE = ['"\'=HYPERLINK(""http://x"",""click"")"', "\"'+1-2\"", "\"'-cmd\"", "\"'@SUM(A1)\""]


def mc_text(rows: list[list]) -> str:
    """A MarineCadastre CSV of rows ``[mmsi, seconds from T0, lat, lon, name]``."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(HEADER)
    for mmsi, t, lat, lon, name in rows:
        stamp = np.datetime_as_string(np.datetime64((T0 + t) * NS, "ns"), unit="s")
        writer.writerow([mmsi, stamp, lat, lon, 10.0, 90.0, 511, name, "", "WX", 31, 0, 25, 8,
                         "", 52, "A"])  # fmt: skip
    return out.getvalue()


def one_line_error(result, *words):
    """The command failed with status 1 and one line on stderr holding ``words``."""
    assert result.exit_code == 1, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr, result.stderr
    assert "internal error" not in lines[0]
    for w in words:
        assert w in lines[0], lines[0]
    return lines[0]


@pytest.fixture(scope="module")
def ny(tmp_path_factory):
    """The New York sample's tracks (parquet) and encounters, made once."""
    root = tmp_path_factory.mktemp("ny")
    found = read_ais([NY]).tracks
    write_tracks(root / "ny.parquet", found)
    write_encounters(root / "enc.csv", find_encounters(found))
    return root / "ny.parquet", root / "enc.csv"


# --- 1a. a path in the YAML's comments --------------------------------------------------------


def test_scenario_comment_escapes_a_newline_in_a_path(usv, ny, tmp_path):
    tracks, enc = ny
    sneaky = tmp_path / "enc\nweather: {wind: {speed: 30}}\n#.csv"
    sneaky.write_bytes(enc.read_bytes())
    out = tmp_path / "sc"
    result = usv("ais", "scenario", tracks, "--encounters", sneaky, "--encounter", 1,
                 "--duration", 10, "-o", out)  # fmt: skip
    assert result.exit_code == 0, result.output
    text = (out / "scenario.yaml").read_text()
    assert "weather" not in yaml.safe_load(text)
    first = text.splitlines()[0]
    assert first.startswith("# Real traffic: usvtool ais scenario, encounter 1 of ")
    assert "enc\\nweather: {wind: {speed: 30}}\\n#.csv, 2022-01-03T" in first


# --- 1b. spreadsheet formulas -----------------------------------------------------------------


def test_spreadsheet_safe_prefixes_each_formula_start_once():
    texts = ["=1+1", "+1", "-1", "@A1", "\tx", "\rx", "'=1", "O'HARA", "TUG-1", ""]
    assert spreadsheet_safe(texts) == ["'=1+1", "'+1", "'-1", "'@A1", "'\tx", "'\rx", "''=1",
                                       "O'HARA", "TUG-1", ""]  # fmt: skip


def test_tracks_csv_neutralises_names_keeps_numbers_and_reads_them_back(tmp_path):
    names = [*FORMULAS, "\tTAB", "'=MINE", "O'HARA", "PLAIN"]
    n = len(names)
    t = Tracks.from_columns(mmsi=np.arange(1, n + 1) + 366_000_000, time=np.zeros(n, np.int64),
                            lon=np.full(n, -70.5), lat=np.full(n, 41.0), track=np.arange(n),
                            name=np.array(names, object))  # fmt: skip
    write_tracks(tmp_path / "t.csv", t)
    lines = (tmp_path / "t.csv").read_text().splitlines()
    cells = [line.split(",") for line in lines[1:]]
    assert [c[2] for c in cells] == ["-70.5"] * n  # a number, not text: no quote, no '
    fields = [next(csv.reader([line])) for line in lines[1:]]
    assert [f[9] for f in fields] == ["'" + s for s in FORMULAS] + ["'\tTAB", "''=MINE",
                                                                     "O'HARA", "PLAIN"]
    for line, safe in zip(lines[1:], SAFE, strict=False):
        assert f",{safe}," in line  # the cell quoted, its own quotes doubled
    assert read_tracks(tmp_path / "t.csv").name.tolist() == names


def test_ais_read_csv_output_is_spreadsheet_safe(usv, tmp_path):
    """(An AIS name loses its @, the padding of the AIS character set.)"""
    rows = [[366000001 + i, 0, 41.0, -70.5, name] for i, name in enumerate(FORMULAS[:3])]
    src = tmp_path / "in.csv"
    src.write_text(mc_text(rows))
    result = usv("ais", "read", src, "-o", tmp_path / "x.csv")
    assert result.exit_code == 0, result.output
    text = (tmp_path / "x.csv").read_text()
    for safe in SAFE[:3]:
        assert f",{safe}," in text
    assert text.count(",-70.5,41,") == 3
    assert read_tracks(tmp_path / "x.csv").name.tolist() == FORMULAS[:3]


def test_encounters_csv_names_are_spreadsheet_safe(tmp_path):
    """Two vessels head-on 200 m apart at lon -70.5: their names behind a ', lon a number."""
    t = tracks_from_metres([(366000001, [(0, 0, -1000), (200, 0, 1000)]),
                            (366000002, [(0, 200, 1000), (200, 200, -1000)])],
                           lat0=41.0, lon0=-70.5,
                           name=np.array(["=cmd|' /C calc'!A0"] * 2 + ["@SUM(A1)"] * 2, object))
    write_encounters(tmp_path / "e.csv", find_encounters(t))
    rows = list(csv.DictReader((tmp_path / "e.csv").open()))
    assert len(rows) == 1
    assert (rows[0]["name_a"], rows[0]["name_b"]) == ("'=cmd|' /C calc'!A0", "'@SUM(A1)")
    assert rows[0]["lon"].startswith("-70.49") and float(rows[0]["cpa_m"]) == 200.0


# --- 2. memory guards -------------------------------------------------------------------------


def _rows_text(nbytes: int) -> bytes:
    """A MarineCadastre CSV of some ``nbytes``: one vessel every second."""
    line = mc_text([[366000001, 0, 41.0, -70.5, "X"]]).splitlines()[1] + "\n"
    return (",".join(HEADER) + "\n" + line * (nbytes // len(line))).encode()


def _zstd(path, data: bytes) -> None:
    with pa.CompressedOutputStream(str(path), "zstd") as f:
        f.write(data)


def _zip(path, data: bytes) -> None:
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("day.csv", data)


@pytest.mark.parametrize("suffix, write", [
    (".csv.gz", lambda p, d: p.write_bytes(gzip.compress(d))),
    (".csv.zst", _zstd),
    (".zip", _zip),
])  # fmt: skip
def test_a_bomb_is_refused_while_it_streams(usv, tmp_path, suffix, write):
    """5 MB of rows against a 1 MiB budget: refused past budget / 6 bytes, naming the remedy."""
    bomb = tmp_path / f"bomb{suffix}"
    write(bomb, _rows_text(5 << 20))
    assert bomb.stat().st_size < 100_000
    result = usv("ais", "read", bomb, "--max-memory", "1M", "-o", tmp_path / "t.parquet")
    one_line_error(result, f"{bomb}: expanding past ", "while reading needs about",
                   "budget of 1 MiB (--max-memory); read it by parts with --bbox, or split it")
    assert not (tmp_path / "t.parquet").exists()


def test_a_gzip_of_zeros_is_refused_before_it_is_held(usv, tmp_path):
    """Compressed a MiB at a time: its first line is longer than any table's."""
    bomb = tmp_path / "zeros.csv.gz"
    with gzip.open(bomb, "wb") as f:
        for _ in range(5):
            f.write(bytes(1 << 20))
    result = usv("ais", "read", bomb, "-o", tmp_path / "t.parquet")
    one_line_error(result, f"{bomb}: line 1 is longer than 1 MiB: not a table of AIS fixes")


def test_a_sparse_file_is_refused_at_its_first_long_line(usv, tmp_path):
    sparse = tmp_path / "sparse.csv"
    with open(sparse, "wb") as f:
        f.truncate(2 * 2**30)
    result = usv("ais", "read", sparse, "-o", tmp_path / "t.parquet")
    one_line_error(result, f"{sparse}: line 1 is longer than {MAX_LINE >> 20} MiB")


def test_bbox_rows_kept_past_the_budget_are_refused(tmp_path):
    path = tmp_path / "day.csv"
    path.write_bytes(_rows_text(400_000))  # some 4 000 rows inside the box, 2.4 MB at 600 B
    options = ReadOptions(bbox=(-71.0, 40.0, -70.0, 42.0), max_memory=1 << 20)
    with pytest.raises(UsvError, match=r"day.csv: [\d,]+ fixes inside --bbox needs about .* "
                                       r"give a smaller --bbox or split the file"):
        read_ais([path], options)
    assert read_ais([path], ReadOptions(bbox=(-71.0, 40.0, -70.0, 42.0))).tracks.n_rows == 1


def test_encounters_refuse_a_tracks_file_past_the_budget(usv, ny, tmp_path):
    write_tracks(tmp_path / "ny.csv", read_tracks(ny[0]))  # 2 411 rows: some 250 kB
    result = usv("ais", "encounters", tmp_path / "ny.csv", "--max-memory", "512K",
                 "-o", tmp_path / "e.csv")  # fmt: skip
    one_line_error(result, "ny.csv: expanding past", "split it (usvtool ais read --bbox)")


def test_encounters_estimate_the_time_grid_before_allocating_it(usv, ny, tmp_path):
    """192 tracks over up to 30 minutes every millisecond: some 10^8 samples, 10^10 bytes and
    more; the budget is given so that no machine could allocate it."""
    result = usv("ais", "encounters", ny[0], "--step", 0.001, "--max-memory", "4G",
                 "-o", tmp_path / "e.csv")  # fmt: skip
    line = one_line_error(result, "tracks sampled every 0.001 s (",
                          "budget of 4.00 GiB (--max-memory); give a larger --step")
    samples = int(line.split("s (")[1].split(" samples")[0].replace(",", ""))
    assert samples > 10**8
    assert not (tmp_path / "e.csv").exists()


# --- 3. bad files -----------------------------------------------------------------------------


def test_read_with_no_fix_left_says_what_was_dropped(usv, tmp_path):
    header = tmp_path / "header.csv"
    header.write_text(",".join(HEADER) + "\n")
    one_line_error(usv("ais", "read", header, "-o", tmp_path / "t.csv"),
                   "header.csv: no fix left after cleaning: 0 positions read")
    nowhere = tmp_path / "nowhere.csv"
    nowhere.write_text(mc_text([[366000001, 0, 91, 181, "A"], [366000001, 60, 91, 181, "A"]]))
    line = one_line_error(usv("ais", "read", nowhere, "-o", tmp_path / "t.csv"))
    assert line == (f"Error: {nowhere}: no fix left after cleaning: 2 positions read; dropped: "
                    "invalid_position 2")  # fmt: skip
    sentence = encode({"msg_type": 1, "mmsi": 366000001, "lon": -70.5, "lat": 41.0})[0]
    bad = sentence[:-2] + ("00" if sentence[-2:] != "00" else "11")
    log = tmp_path / "log.nmea"
    log.write_text(f"{tag(bad, T0)}\n{tag(bad, T0 + 10)}\n")
    line = one_line_error(usv("ais", "read", log, "-o", tmp_path / "t.csv"))
    assert line == (f"Error: {log}: no fix left after cleaning: 0 positions read (skipped: "
                    "bad_checksum 2)")  # fmt: skip
    assert not (tmp_path / "t.csv").exists()


@pytest.mark.parametrize("rows", [0, 1])
def test_encounters_of_no_track_to_interpolate_is_one_line(usv, tmp_path, rows):
    t = Tracks.from_columns(mmsi=[366000001] * rows, time=[T0 * NS] * rows, lon=[-70.5] * rows,
                            lat=[41.0] * rows, track=[0] * rows)  # fmt: skip
    write_tracks(tmp_path / "t.csv", t)
    result = usv("ais", "encounters", tmp_path / "t.csv", "-o", tmp_path / "e.csv")
    one_line_error(result, f"t.csv: no track of two fixes or more to interpolate (fixes: {rows}, "
                           f"tracks: {rows})")  # fmt: skip
    assert not (tmp_path / "e.csv").exists()


def test_truncated_gzip_and_corrupt_zip_are_one_line(usv, tmp_path):
    data = _rows_text(200_000)
    packed = gzip.compress(data)
    (tmp_path / "cut.csv.gz").write_bytes(packed[: len(packed) // 2])
    one_line_error(usv("ais", "read", tmp_path / "cut.csv.gz", "-o", tmp_path / "t.csv"),
                   "cut.csv.gz: truncated gzip file")
    _zip(tmp_path / "day.zip", data)
    broken = bytearray((tmp_path / "day.zip").read_bytes())
    broken[100:140] = b"x" * 40  # inside the deflated member: its CRC fails
    (tmp_path / "bad.zip").write_bytes(bytes(broken))
    one_line_error(usv("ais", "read", tmp_path / "bad.zip", "-o", tmp_path / "t.csv"),
                   "bad.zip: corrupt zip file")
    assert not (tmp_path / "t.csv").exists()


def test_a_byte_order_mark_is_accepted_by_every_csv_reader(tmp_path):
    bom = "\ufeff"
    mc = tmp_path / "mc.csv"
    mc.write_text(bom + mc_text([[366000001, 0, 41.0, -70.5, "A"]]), encoding="utf-8")
    names = DMA.split(",")
    values = {"# Timestamp": "03/01/2022 00:00:00", "Type of mobile": "Class A",
              "MMSI": "219021240", "Latitude": "55.5", "Longitude": "10.5", "Name": "B"}
    dma = tmp_path / "aisdk.csv"
    dma.write_text(f"{bom}{DMA}\n" + ",".join(values.get(n, "") for n in names) + "\n",
                   encoding="utf-8")  # fmt: skip
    generic = tmp_path / "g.csv"
    generic.write_text(f"{bom}mmsi;time;lat;lon\n211000001;{T0};54.0;10.0\n", encoding="utf-8")
    log = tmp_path / "log.nmea"
    sentence = encode({"msg_type": 1, "mmsi": 366000009, "lon": -70.5, "lat": 41.0})[0]
    log.write_text(bom + tag(sentence, T0) + "\n", encoding="utf-8")
    result = read_ais([mc, dma, generic, log])
    assert [f["format"] for f in result.files] == ["marinecadastre", "dma", "generic", "nmea"]
    assert sorted(result.tracks.mmsi.tolist()) == [211000001, 219021240, 366000001, 366000009]
    write_tracks(tmp_path / "t.csv", result.tracks)
    text = (tmp_path / "t.csv").read_text()
    (tmp_path / "bom.csv").write_text(bom + text, encoding="utf-8")
    assert read_tracks(tmp_path / "bom.csv").mmsi.tolist() == result.tracks.mmsi.tolist()


def test_an_mmsi_written_as_a_whole_decimal_is_that_integer(usv, tmp_path):
    path = tmp_path / "pandas.csv"
    path.write_text(mc_text([["219021240.0", 0, 55.5, 10.5, "A"]]))
    assert read_ais([path]).tracks.mmsi.tolist() == [219021240]
    half = tmp_path / "half.csv"
    half.write_text(mc_text([[219021241, 0, 55.5, 10.5, "A"], ["219021240.5", 60, 55.5, 10.5,
                                                               "A"]]))  # fmt: skip
    one_line_error(usv("ais", "read", half, "-o", tmp_path / "t.csv"),
                   "half.csv: line 3, column MMSI: 219021240.5 is not an MMSI (an integer)")


@pytest.mark.parametrize("option, known", [
    ("--vessel", "(iwso-dwa-usv, udwa-usv)"),
    ("--controller", "(ccdwa, dwa, exec, gdwa, policy, sbmpc, udwa, udwa+, vo)")])  # fmt: skip
def test_scenario_refuses_an_unknown_vessel_or_controller(usv, ny, tmp_path, option, known):
    tracks, enc = ny
    result = usv("ais", "scenario", tracks, "--encounters", enc, "--encounter", 1, option,
                 "nosuch", "-o", tmp_path / "sc")  # fmt: skip
    assert result.exit_code == 2
    assert f"Invalid value for '{option}': 'nosuch' is not a " in result.stderr
    assert known in result.stderr and "Traceback" not in result.stderr
    assert not (tmp_path / "sc").exists()


def test_a_second_scenario_removes_only_the_first_ones_files(usv, ny, tmp_path):
    tracks, enc = ny
    out = tmp_path / "sc"
    first = usv("ais", "scenario", tracks, "--encounters", enc, "--encounter", 1,
                "--radius", 2000, "-o", out)  # fmt: skip
    assert first.exit_code == 0, first.output
    written = set(json.loads((out / "scenario.manifest.json").read_text())["files"])
    old_targets = {n for n in written if n.startswith("ais-")}
    assert len(old_targets) == json.loads(first.stdout)["targets"] >= 2
    (out / "ais-notes.csv").write_text("mine\n")  # the user's, never listed
    (out / "ais-999999999.csv").write_text("mine too\n")  # named like a target, not listed
    second = usv("ais", "scenario", tracks, "--encounters", enc, "--encounter", 1,
                 "--radius", 50, "-o", out)  # fmt: skip
    assert second.exit_code == 0, second.output
    scenario = yaml.safe_load((out / "scenario.yaml").read_text())
    new_targets = {t["track"] for t in scenario["targets"]}
    assert len(new_targets) < len(old_targets)
    left = {p.name for p in out.iterdir()}
    assert left == {"scenario.yaml", "route.geojson", "scenario.manifest.json", "ais-notes.csv",
                    "ais-999999999.csv"} | new_targets  # fmt: skip
    assert (out / "ais-notes.csv").read_text() == "mine\n"
