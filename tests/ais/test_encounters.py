"""usvtool ais encounters: CPA and TCPA of two straight tracks computed by hand, the bucketed
search against a brute-force all-pairs search on a seeded synthetic harbour, the CSV's round
trip, and the New York Harbor sample."""

import json

import numpy as np
import pytest

from usvtool.ais.encounters import EncounterOptions, find_encounters, segment_min
from usvtool.encounter import CLASS_NAMES, classify
from usvtool.tracks import NS, format_time, read_tracks
from usvtool.traffic import read_encounters

from .aisdata import M_PER_DEG, NY, T0, tracks_from_metres


def test_two_straight_tracks_by_hand():
    """A heads north at 5 m/s through (0, 0) at t = 0; B heads west at 5 m/s through (1500,
    1000) at t = 0. Relative p(t) = (1500 - 5t, 1000 - 5t), v = (-5, -5): tcpa(t) = 250 - t,
    dcpa = |(250, -250)| = 353.553 m at t = 250 s. With --tcpa 905 the first 10 s grid time
    with tcpa <= 905 is t = -650 (tcpa 900, range |(4750, 4250)| = 6373.774 m); the range stays
    within --cpa 400 while t^2 - 500 t + 61800 <= 0, t in [223.5, 276.5]: the window ends at
    270. At detection B bears 48.2 deg on A's starboard bow (A gives way), A 318.2 deg on B's
    port bow (B stands on)."""
    a = (111000001, [(-1000, 0.0, -5000.0), (1000, 0.0, 5000.0)])
    b = (111000002, [(-1000, 6500.0, 1000.0), (1000, -3500.0, 1000.0)])
    result = find_encounters(tracks_from_metres([a, b]), EncounterOptions(cpa=400, tcpa=905))
    assert len(result.rows) == 1
    r = result.rows[0]
    assert r["cpa_m"] == pytest.approx(353.553, abs=0.05)
    assert r["tcpa_s"] == pytest.approx(900.0, abs=0.05)
    assert r["range_m"] == pytest.approx(np.hypot(4750, 4250), abs=0.05)
    assert (r["start"], r["end"], r["cpa_time"]) == tuple(format_time([(T0 + s) * NS])[0]
                                                          for s in (-650, 270, 250))  # fmt: skip
    assert (r["class_a"], r["class_b"]) == ("crossing-give-way", "crossing-stand-on")
    assert r["sog_a"] == pytest.approx(5 / 0.514444, abs=0.01)
    assert r["cog_a"] == pytest.approx(0.0, abs=0.01) and r["cog_b"] == pytest.approx(270.0,
                                                                                       abs=0.01)
    assert not r["censored"]


def test_cpa_between_grid_times_is_refined():
    """Head-on at 10 m/s each, 100 m apart abeam: the closest approach (100 m) falls at t =
    5 s, half-way between two 10 s grid times, where the grid's ranges are 141.4 m."""
    a = (111000001, [(-300, 0.0, -3050.0), (300, 0.0, 2950.0)])
    b = (111000002, [(-300, 100.0, 3050.0), (300, 100.0, -2950.0)])
    r = find_encounters(tracks_from_metres([a, b]), EncounterOptions(cpa=150)).rows[0]
    assert r["cpa_m"] == pytest.approx(100.0, abs=0.05)
    assert r["cpa_time"] == format_time([(T0 + 5) * NS])[0]
    assert r["class_a"] == r["class_b"] == "head-on"


def test_segment_min_by_hand():
    d, f = segment_min(np.array([[0.0, 10.0], [5.0, 0.0]]), np.array([[10.0, 0.0], [6.0, 0.0]]))
    assert d.tolist() == pytest.approx([np.sqrt(50.0), 5.0]) and f.tolist() == [0.5, 0.0]


def _synthetic_harbour(seed: int):
    """30 vessels crossing a 6 km square at 1-12 m/s in straight legs with turns, fixes every
    20-90 s over 40 minutes, and two moored side by side (never an encounter)."""
    rng = np.random.default_rng(seed)
    vessels = []
    for i in range(30):
        t = float(rng.uniform(-600, 600))
        x, y = rng.uniform(0, 6000, 2)
        heading, speed = rng.uniform(0, 2 * np.pi), rng.uniform(1, 12)
        fixes = []
        while t < 2400:
            fixes.append((t, x, y))
            dt = float(rng.uniform(20, 90))
            heading += rng.normal(0, 0.3)
            x, y, t = x + speed * dt * np.sin(heading), y + speed * dt * np.cos(heading), t + dt
        vessels.append((200000000 + i, fixes))
    moored = [(0.0, 3000.0, 3000.0), (2400.0, 3000.3, 3000.0)]
    vessels += [(300000001, moored), (300000002, [(0.0, 3030.0, 3000.0), (2400.0, 3030.0,
                                                                            3000.2)])]  # fmt: skip
    return tracks_from_metres(vessels, lat0=55.0, lon0=12.0)


def _brute_force(tracks, options: EncounterOptions) -> list[tuple]:
    """Every pair, every common grid time, plainly: positions by np.interp, velocities by the
    segment holding each time, the detection rule and the refinement of the module docstring."""
    step = round(options.step * NS)
    first = np.flatnonzero(np.r_[True, np.diff(tracks.track) != 0])
    stop = np.r_[first[1:], tracks.n_rows]
    found = []
    for i in range(len(first)):
        for j in range(i + 1, len(first)):
            ta, tb = tracks.time[first[i]:stop[i]], tracks.time[first[j]:stop[j]]
            lo, hi = max(ta[0], tb[0]), min(ta[-1], tb[-1])
            grid = np.arange(-(-lo // step), hi // step + 1) * step
            if grid.size == 0:
                continue
            states = []
            for rows, t in ((slice(first[i], stop[i]), ta), (slice(first[j], stop[j]), tb)):
                lat = np.interp(grid, t, tracks.lat[rows])
                lon = np.interp(grid, t, tracks.lon[rows])
                k = np.clip(np.searchsorted(t, grid, "right") - 1, 0, t.size - 2)
                dt = (t[k + 1] - t[k]) / NS
                ve = (M_PER_DEG * np.cos(np.radians(lat))
                      * (tracks.lon[rows][k + 1] - tracks.lon[rows][k]) / dt)  # fmt: skip
                vn = M_PER_DEG * (tracks.lat[rows][k + 1] - tracks.lat[rows][k]) / dt
                states.append((lon, lat, ve, vn))
            (lon_a, lat_a, ve_a, vn_a), (lon_b, lat_b, ve_b, vn_b) = states
            mid = np.radians(0.5 * (lat_a + lat_b))
            px, py = M_PER_DEG * np.cos(mid) * (lon_b - lon_a), M_PER_DEG * (lat_b - lat_a)
            vx, vy = ve_b - ve_a, vn_b - vn_a
            vv = vx * vx + vy * vy
            tcpa = np.where(vv > 1e-18, -(px * vx + py * vy) / np.where(vv > 0, vv, 1), 0.0)
            dcpa = np.hypot(px + tcpa * vx, py + tcpa * vy)
            rng_ = np.hypot(px, py)
            on = (rng_ <= options.cpa) | ((px * vx + py * vy < 0) & (dcpa <= options.cpa)
                                          & (tcpa <= options.tcpa))  # fmt: skip
            n = 0
            while n < grid.size:
                if not on[n]:
                    n += 1
                    continue
                e = n
                while e + 1 < grid.size and on[e + 1]:
                    e += 1
                m = n + int(np.argmin(rng_[n:e + 1]))
                best = rng_[m]
                f = np.linspace(0, 1, 20001)  # densely sampled, not the closed form
                for q in (m - 1, m + 1):
                    if 0 <= q < grid.size:
                        best = min(best, np.hypot(px[m] + f * (px[q] - px[m]),
                                                  py[m] + f * (py[q] - py[m])).min())  # fmt: skip
                speed = max(np.hypot(ve_a[m], vn_a[m]), np.hypot(ve_b[m], vn_b[m]))
                if best <= options.cpa and speed >= options.min_speed * 1852 / 3600:
                    speeds = np.hypot(ve_a[n], vn_a[n]), np.hypot(ve_b[n], vn_b[n])
                    # a vessel still (< 0.05 m/s) keeps her reported heading: none here, 0
                    course_a = np.degrees(np.arctan2(ve_a[n], vn_a[n])) % 360 * (
                        speeds[0] >= 0.05)  # fmt: skip
                    course_b = np.degrees(np.arctan2(ve_b[n], vn_b[n])) % 360 * (
                        speeds[1] >= 0.05)  # fmt: skip
                    seen = (classify((0, 0), course_a, speeds[0], [(px[n], py[n])], [course_b],
                                     [speeds[1]])[0],
                            classify((0, 0), course_b, speeds[1], [(-px[n], -py[n])],
                                     [course_a], [speeds[0]])[0])  # fmt: skip
                    found.append((int(tracks.mmsi[first[i]]), int(tracks.mmsi[first[j]]),
                                  int(grid[n]), int(grid[e]), float(best),
                                  tuple(CLASS_NAMES[c] for c in seen)))  # fmt: skip
                n = e + 1
    return found


def test_bucketed_search_matches_brute_force():
    tracks = _synthetic_harbour(seed=7)
    options = EncounterOptions(cpa=300, tcpa=600)
    result = find_encounters(tracks, options)
    expected = _brute_force(tracks, options)
    assert len(expected) >= 10  # the seed gives a busy harbour
    got = {(r["mmsi_a"], r["mmsi_b"], r["start"], r["end"]): r for r in result.rows}
    want = {(a, b, format_time([s])[0], format_time([e])[0]): (d, c)
            for a, b, s, e, d, c in expected}  # fmt: skip
    assert set(got) == set(want)
    for key, (d, classes) in want.items():
        assert got[key]["cpa_m"] == pytest.approx(d, abs=0.01)
        assert (got[key]["class_a"], got[key]["class_b"]) == classes
    assert not any(300000001 in k and 300000002 in k for k in got)  # moored: no encounter
    assert [r["rank"] for r in result.rows] == list(range(1, len(result.rows) + 1))
    assert [r["cpa_m"] for r in result.rows] == sorted(r["cpa_m"] for r in result.rows)
    assert result.figures["candidate_pairs"] < 30 * 31 / 2  # bucketing pruned pairs


def test_csv_round_trip_and_cli(usv, tmp_path):
    tracks = tmp_path / "ny.parquet"
    assert usv("ais", "read", NY, "-o", tracks).exit_code == 0
    out = tmp_path / "enc.csv"
    result = usv("ais", "encounters", tracks, "-o", out, "--bbox", "-74.30,40.45,-73.85,40.75")
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    rows = read_encounters(out)
    assert summary["encounters"] == len(rows) > 0
    assert summary["closest"]["cpa_m"] == pytest.approx(rows[0]["cpa_m"], abs=0.05)
    whole = find_encounters(read_tracks(tracks))
    assert len(whole.rows) == len(rows)  # the box holds the whole subset
    assert rows[0]["mmsi_a"] == whole.rows[0]["mmsi_a"]
    bad = usv("ais", "encounters", tracks, "-o", tmp_path / "x.csv", "--bbox", "1,2,3")
    assert bad.exit_code == 2 and not (tmp_path / "x.csv").exists()


def test_bbox_rows_name_the_files_track_ids():
    """A vessel outside the box drops out of the search; the rows still name the tracks by
    their ids in the tracks given (1 and 2, not the search's renumbered 0 and 1)."""
    far = (111000000, [(-1000, 90000.0, 0.0), (1000, 90000.0, 100.0)])  # track 0, 90 km east
    a = (111000001, [(-1000, 0.0, -5000.0), (1000, 0.0, 5000.0)])
    b = (111000002, [(-1000, 6500.0, 1000.0), (1000, -3500.0, 1000.0)])
    tracks = tracks_from_metres([far, a, b])
    box = (-0.1, -0.1, 0.1, 0.1)  # degrees: some 11 km around (0, 0)
    rows = find_encounters(tracks, EncounterOptions(cpa=400, tcpa=905, bbox=box)).rows
    assert [(r["track_a"], r["track_b"]) for r in rows] == [(1, 2)]
