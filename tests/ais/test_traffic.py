"""usvtool/traffic.py, the contract of real traffic: the committed New York Harbor files are what
the documented commands make, an encounter picked by rank or among those under way (checked
against the CSV read by hand), the scenario's window padded and cut to the own track, and a
vessel's manoeuvre (course and speed changes) computed by hand on straight legs."""

import csv

import numpy as np
import pytest

from usvtool.angles import wrap180
from usvtool.errors import UsvError
from usvtool.tracks import COLUMNS, NS, read_tracks
from usvtool.traffic import (
    KNOT,
    encounters_csv,
    manoeuvre,
    pick_encounter,
    read_encounters,
    scene_encounter,
    summarise,
)

from .aisdata import AIS, NY, T0, tracks_from_metres

ENCOUNTERS = AIS / "nyharbor-encounters.csv"
TRACKS = AIS / "nyharbor-tracks.parquet"


def test_the_committed_files_are_what_ais_read_and_encounters_make():
    from usvtool.ais import ReadOptions, find_encounters, read_ais

    made = read_ais([NY], ReadOptions()).tracks
    committed = read_tracks(TRACKS)
    for c in COLUMNS:
        a, b = getattr(made, c), getattr(committed, c)
        assert a.dtype == b.dtype and (np.array_equal(a, b, equal_nan=a.dtype.kind == "f")), c
    assert find_encounters(committed).to_csv() == ENCOUNTERS.read_text(encoding="utf-8")
    assert encounters_csv(read_encounters(ENCOUNTERS)) == ENCOUNTERS.read_text(encoding="utf-8")


def _by_hand() -> list[dict]:
    with open(ENCOUNTERS, newline="") as f:
        return list(csv.DictReader(f))


def test_an_encounter_by_rank_or_among_those_under_way():
    rows = read_encounters(ENCOUNTERS)
    hand = _by_hand()
    moving = [int(r["rank"]) for r in hand if float(r["sog_a"]) >= 1 and float(r["sog_b"]) >= 1]
    assert len(moving) == 30 and moving[:5] == [3, 6, 9, 10, 11]  # docs/ais.md's 30
    for n, rank in enumerate(moving, 1):
        assert pick_encounter(rows, "under-way", n, 1.0, ENCOUNTERS, "s")["rank"] == rank
    assert pick_encounter(rows, "any", 6, 1.0, ENCOUNTERS, "s")["name_b"] == "OPPORTUNITY"
    slow = [int(r["rank"]) for r in hand if float(r["sog_a"]) >= 5 and float(r["sog_b"]) >= 5]
    assert pick_encounter(rows, "under-way", 2, 5.0, ENCOUNTERS, "s")["rank"] == slow[1]
    for kind, n, words in [("any", 0, "s 0: no such rank"), ("any", 178, "(1 … 177)"),
                           ("under-way", 31, "holds 30 encounters with both vessels making 1 kn"),
                           ("under-way", 0, "(1 … 30)")]:  # fmt: skip
        with pytest.raises(UsvError, match=words.replace("(", r"\(").replace(")", r"\)")):
            pick_encounter(rows, kind, n, 1.0, ENCOUNTERS, "s")


def test_the_window_is_the_encounters_padded_and_cut_to_the_own_track():
    tracks = read_tracks(TRACKS)
    rows = {r["rank"]: r for r in read_encounters(ENCOUNTERS)}
    first, stop = tracks.track_bounds()
    for rank, own in [(1, "a"), (6, "b"), (10, "a")]:
        row = rows[rank]
        at = scene_encounter(tracks, row, own, 60.0, ENCOUNTERS)
        mine = tracks.track[first] == row[f"track_{own}"]
        begin, end = tracks.time[first[mine]][0], tracks.time[stop[mine] - 1][0]
        t0, t1 = (int(np.datetime64(row[k].rstrip("Z"), "ns").astype(np.int64))
                  for k in ("start", "end"))  # fmt: skip
        assert at.times == (t0, t1)
        assert at.window == (max(t0 - 60 * NS, begin), min(t1 + 60 * NS, end))
        assert at.other == row["mmsi_b" if own == "a" else "mmsi_a"]
        assert tracks.mmsi[first[at.own]] == row[f"mmsi_{own}"]
    with pytest.raises(UsvError, match="track 9999 of 367782880 is not in the tracks file"):
        scene_encounter(tracks, {**rows[6], "track_a": 9999}, "a", 60.0, ENCOUNTERS)


def test_a_manoeuvre_by_hand():
    """Fixes every 10 s: north at 5 m/s for 60 s, west at 2 m/s for 30 s, north at 4 m/s for
    40 s, east at 3 m/s for 60 s. A window over the first three legs turns to port and back
    (net 0, largest -90), one over the last two to starboard (net +90)."""
    north = [(t, 0.0, 5.0 * t) for t in range(0, 70, 10)]
    west = [(60 + t, -2.0 * t, 300.0) for t in range(10, 40, 10)]
    again = [(90 + t, -60.0, 300.0 + 4.0 * t) for t in range(10, 50, 10)]
    east = [(130 + t, -60.0 + 3.0 * t, 460.0) for t in range(10, 70, 10)]
    tracks = tracks_from_metres([(366000001, north + west + again + east)])  # on the equator
    m = manoeuvre(tracks, 0, T0 * NS, (T0 + 130) * NS)
    # (compass 0 comes out as 0 or just under 360: the fixes' lon/lat rounded)
    assert (m.course_start, wrap180(m.course_end), m.course_change,
            m.largest_turn) == pytest.approx((0.0, 0.0, 0.0, -90.0), abs=1e-6)  # fmt: skip
    assert (m.speed_start, m.speed_end, m.speed_min, m.speed_max) == pytest.approx(
        (5 / KNOT, 4 / KNOT, 2 / KNOT, 5 / KNOT), rel=1e-9)  # fmt: skip
    m = manoeuvre(tracks, 0, (T0 + 100) * NS, (T0 + 190) * NS)
    assert (wrap180(m.course_start), m.course_end, m.course_change,
            m.largest_turn) == pytest.approx((0.0, 90.0, 90.0, 90.0), abs=1e-6)  # fmt: skip
    assert (m.speed_start, m.speed_end) == pytest.approx((4 / KNOT, 3 / KNOT), rel=1e-9)
    m = manoeuvre(tracks, 0, (T0 + 65) * NS, (T0 + 130) * NS)  # from the westward leg
    assert (m.course_start, m.course_change, m.largest_turn) == pytest.approx((270.0, 90.0, 90.0),
                                                                              abs=1e-6)  # fmt: skip


def test_summarise_ignores_the_course_of_a_ship_standing_still():
    m = summarise([10.0, 350.0, 200.0, 40.0], [2.0, 2.0, 0.0, 2.0], (10.0, 2.0), (40.0, 2.0))
    # 200 deg was the heading of a ship standing still: not a turn; 350 is -20 from 10
    assert (m.course_change, m.largest_turn, m.speed_min) == pytest.approx((30.0, 30.0, 0.0))
    m = summarise([10.0, 340.0, 20.0], [1.0, 1.0, 1.0], (10.0, 1.0), (20.0, 1.0))
    assert m.largest_turn == pytest.approx(-30.0) and m.speed_max == pytest.approx(1 / KNOT)


def test_the_encounters_csv_gives_back_names_a_spreadsheet_shows_as_text(tmp_path):
    """Names are written behind a ``'`` where a spreadsheet would run them as a formula, and
    read back as they were; a spreadsheet's byte order mark is accepted."""
    rows = read_encounters(ENCOUNTERS)[:2]
    rows[0] |= {"name_a": '=HYPERLINK("http://x","click")', "name_b": "+1-2"}
    rows[1] |= {"name_a": "'-cmd", "name_b": "TUG -7"}
    text = encounters_csv(rows)
    cells = list(csv.reader(text.splitlines()))
    assert [cells[1][5:7], cells[2][5:7]] == [["'=HYPERLINK(\"http://x\",\"click\")", "'+1-2"],
                                              ["''-cmd", "TUG -7"]]  # fmt: skip
    path = tmp_path / "e.csv"
    path.write_text("\ufeff" + text, encoding="utf-8")
    assert read_encounters(path) == rows
