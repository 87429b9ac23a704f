"""The real-traffic section (usvtool/report/sections/traffic.py) on hand-built runs of the
committed New York Harbor encounter 3 (H203 overtaking CYCLONE SHARK, the closest of two
vessels under way; the USV in H203's place): the recorded vessel's course and speed computed
here from the raw parquet fixes, the closest distance to the other vessel (any of her tracks)
from the runs' summaries, failures marked, a moved tracks file refused in one line."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from usvtool.errors import UsvError
from usvtool.report.data import JobResults, Results
from usvtool.report.sections import traffic
from usvtool.results import Row

AIS = Path(__file__).resolve().parents[2] / "charts" / "ais"
ENCOUNTERS, TRACKS = AIS / "nyharbor-encounters.csv", AIS / "nyharbor-tracks.parquet"
CASE = "ny/under-way/s001"
H203, SHARK, OTHER = 367782880, 368139870, 367791540


def run(root: Path, method: str, metrics: dict, closest: dict[str, float],
        tracks: Path = TRACKS, sha256: dict | None = None) -> JobResults:  # fmt: skip
    """A run: its metrics, and its summary.json with the scene's options (every one, as
    ``usvtool simulate --family`` writes them) and the closest distance to each target."""
    d = root / "runs" / method
    d.mkdir(parents=True)
    options = {"encounters": str(ENCOUNTERS), "tracks": str(tracks), "own": "a", "radius": 2000.0,
               "pad": 60.0, "min_speed": 1.0, "vessel": "udwa-usv", "duration": 0.0}
    scene = {"family": "ais", "kind": "under-way", "scene": 1, "options": options}
    per_target = [{"target": t, "closest_distance_m": m} for t, m in closest.items()]
    (d / "summary.json").write_text(json.dumps({"scene": scene, "controller": method,
                                                "per_target": per_target}))  # fmt: skip
    rows = {m: Row("k", "runs", CASE, method, 1, m, str(v)) for m, v in metrics.items()}
    config = {"scene": {"family": "ais", "kind": "under-way", "scene": 1,
                        **({"sha256": sha256} if sha256 else {})}}  # fmt: skip
    return JobResults(f"k-{method}", "runs", CASE, method, 1, d, rows, config=config)


def counts(c, e, n, j) -> dict:
    return {"compliant": c, "compliant_excused": e, "noncompliant": n, "not_judged": j}


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    root = tmp_path_factory.mktemp("traffic")
    # CYCLONE SHARK replayed as two tracks (her second is ais-MMSI-TRACK): the closer counts
    jobs = [run(root, "dwa", {"arrived": True, "arrival_time_s": 401.5, "closest_distance_m": 12.0,
                              **counts(1, 0, 1, 0)},
                {f"ais-{SHARK}": 30.0, f"ais-{SHARK}-7": 25.5, f"ais-{OTHER}": 12.0}),
            run(root, "udwa", {"arrived": False, "collision": f"ais-{SHARK}",
                               "closest_distance_m": 0.0, **counts(0, 0, 0, 2)},
                {f"ais-{SHARK}": 0.0, f"ais-{OTHER}": 40.0})]  # fmt: skip
    return traffic.section(Results(jobs, [], ("dwa", "udwa")))


def _h203_at_start() -> tuple[float, float]:
    """H203's course (deg) and speed (kn) over the fixes of her track around 00:09:20, from
    the parquet's raw rows and the local frame's formula (docs/ais.md)."""
    import pyarrow.parquet as pq

    t = pq.read_table(TRACKS).to_pydict()
    rows = sorted((time, lon, lat) for mmsi, track, time, lon, lat in zip(
        t["mmsi"], t["track"], t["time"], t["lon"], t["lat"], strict=True)
        if mmsi == H203 and track == 137)  # fmt: skip
    times = np.array([r[0].replace(tzinfo=None) for r in rows], "datetime64[ns]")
    start = np.datetime64("2022-01-03T00:09:20")
    j = int(np.searchsorted(times, start, side="right") - 1)
    (_, lon0, lat0), (_, lon1, lat1) = rows[j], rows[j + 1]
    dt = (times[j + 1] - times[j]) / np.timedelta64(1, "s")
    r = 6_371_008.8 * math.pi / 180
    ve = r * math.cos(math.radians(lat0)) * (lon1 - lon0) / dt
    vn = r * (lat1 - lat0) / dt
    return math.degrees(math.atan2(ve, vn)) % 360, math.hypot(ve, vn) / (1852 / 3600)


def test_the_recorded_encounter_and_what_the_vessel_did(built):
    recorded, _ = built.blocks
    (row,) = recorded.rows
    cells = [c.text for c in row]
    assert cells[:8] == [CASE, "3", f"H203 ({H203})", f"CYCLONE SHARK ({SHARK})", "overtaking",
                         "270", "3", "16.3"]  # fmt: skip
    course, speed = _h203_at_start()
    assert cells[8].startswith(f"{course:.0f} → ") and cells[9].startswith(f"{speed:.1f} → ")


def test_every_run_beside_the_recorded_vessel(built):
    _, runs = built.blocks
    recorded, dwa, udwa = ([c.text for c in r] for r in runs.rows)
    assert recorded[1:5] == ["recorded", "-", "-", "16.3"]
    assert dwa[1:] == ["dwa", "arrived (402 s)", "12.0", "25.5", "1", "0", "1", "0"]
    assert runs.rows[1][2].css == "holds" and runs.rows[1][7].css == "num fails"
    assert udwa[1:] == ["udwa", f"collided (ais-{SHARK})", "0.0", "0.0", "0", "0", "0", "2"]
    assert runs.rows[2][2].css == "fails" and runs.rows[2][8].css == "num untested"
    assert "2 runs: 1 arrived, 1 failed" in built.paragraphs[0]


def test_no_ais_runs_no_section_and_moved_files_are_refused(tmp_path):
    assert traffic.section(Results([], [], ())) is None
    job = run(tmp_path, "dwa", {"arrived": True}, {}, tracks=tmp_path / "gone.parquet")
    with pytest.raises(UsvError) as e:
        traffic.section(Results([job], [], ("dwa",)))
    assert str(e.value) == (f"{job.dir / 'summary.json'}: scene.options.tracks "
                            f"{tmp_path / 'gone.parquet'}: no such file (moved or removed since "
                            "the run?)")  # fmt: skip


def test_a_file_changed_since_the_run_is_refused(tmp_path):
    """job.json records the SHA-256 of the files the run read (usvtool batch writes it): a
    tracks file of other bytes at the same path is refused in one line; the same bytes read."""
    import shutil

    from usvtool.digest import sha256

    copy = tmp_path / "tracks.parquet"
    shutil.copy(TRACKS, copy)
    digests = {"encounters": sha256(ENCOUNTERS), "tracks": sha256(copy)}
    job = run(tmp_path / "a", "dwa", {"arrived": True}, {}, tracks=copy, sha256=digests)
    assert traffic.recorded(job).at.other == SHARK  # the same bytes: read
    copy.write_bytes(copy.read_bytes() + b"\0")
    traffic._sha256.cache_clear()
    with pytest.raises(UsvError) as e:
        traffic.recorded(job)
    assert str(e.value) == (f"{job.dir / 'summary.json'}: scene.options.tracks {copy}: changed "
                            "since the run (not the bytes its job.json records): run the batch "
                            "again")  # fmt: skip
