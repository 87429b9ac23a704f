"""The wind section (usvtool/report/sections/wind.py) on hand-built runs: arrivals and failures
counted by hand, a run that did not arrive never an arrival time (even when its table holds
one), the differences paired by scene, the speed made good of a straight run, and the figures
at >= 150 dpi."""

from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from usvtool.report.data import JobResults, Results
from usvtool.report.sections import wind
from usvtool.results import Row
from usvtool.trace import Trace, write_events, write_trace

FIELD = Path(__file__).resolve().parents[2] / "charts/scenarios/wind/southeast-strong.tif"
GOAL = (650.0, 650.0)
#: A bogus arrival time held by a run that did not arrive: it must never be read as one.
BOGUS = 12.75


def job(root, case: str, method: str, arrived: bool, time: float | None) -> JobResults:
    """A run of ``case`` through the bundled south-east field: the own ship from (50, 50)
    straight toward the goal at 5 m/s for 10 s; its table's arrived and arrival time."""
    d = root / "runs" / f"{case.replace('/', '-')}-{method}"
    d.mkdir(parents=True)
    t = np.arange(0.0, 10.01, 0.5)
    s = 50.0 + 5.0 * t / math.sqrt(2.0)
    states = [[[x, x, 45.0, 5.0, 0.0]] for x in s]
    write_trace(d / "trace.csv", Trace.from_states(t, ["own"], states))
    write_events(d / "trace.events.json", {"encounters": [], "run": {
        "ships": [{"name": "own", "length": 15.0}], "map": None, "wind_field": str(FIELD),
        "goal": list(GOAL)}})  # fmt: skip
    metrics = {"arrived": arrived, "arrival_time_s": time}
    rows = {m: Row("k", "runs", case, method, 1, m, str(v)) for m, v in metrics.items()
            if v is not None}  # fmt: skip
    family = case.split("/")
    config = {"scene": {"family": "wind", "kind": family[1], "scene": 0}} if len(family) == 3 \
        else {}
    return JobResults(f"{case}-{method}", "runs", case, method, 1, d, rows, config=config)


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    root = tmp_path_factory.mktemp("wind")
    jobs = [job(root, f"wind/halves/s00{i}", "dwa", True, t) for i, t in enumerate((120, 125, 130))]
    jobs += [job(root, "wind/halves/s000", "udwa", True, 100.0),
             job(root, "wind/halves/s001", "udwa", True, 110.0),
             job(root, "wind/halves/s002", "udwa", False, BOGUS),
             job(root, "wind-test", "dwa", True, 121.5),
             job(root, "wind-test", "udwa", False, BOGUS)]  # fmt: skip
    return wind.section(Results(jobs, [], order=("dwa", "udwa")))


def table(section, table_id: str) -> list[list[str]]:
    found = next(t for t in section.tables() if t.id == table_id)
    return [[c.text for c in row] for row in found.rows]


def data(section, figure_id: str) -> list[list[str]]:
    found = next(f for f in section.figures() if f.id == figure_id)
    return [line.split(",") for line in found.data.splitlines()]


def test_arrivals_and_failures_are_counted_by_hand(built):
    rows = table(built, "wind-wind-halves-arrivals")
    # dwa: 120, 125, 130 (median 125, quartiles 122.5 and 127.5)
    assert rows[0] == ["dwa", "3", "3", "0", "125.0", "5.0", "reference", "", ""]
    # udwa: 100, 110 and a failure, ranked last: median 110; the upper quartile is a failure.
    # Paired improvements over dwa: 20, 15 and the failure's -inf: signed ranks +2, +1, -3,
    # so r = (3 - 3) / 6 = 0; no Hodges-Lehmann shift over a failure
    assert rows[1][:7] == ["udwa", "3", "2", "1", "110.0", "did not arrive", "-"]
    assert rows[1][7].startswith("+0.00 [")


def test_a_run_that_did_not_arrive_is_never_an_arrival_time(built):
    shown = data(built, "wind-wind-halves-differences")
    assert shown[1:] == [["udwa − dwa", "wind/halves/s000", "-20.000", "", ""],
                         ["udwa − dwa", "wind/halves/s001", "-15.000", "", ""],
                         ["udwa − dwa", "estimate", "", "", ""]]  # fmt: skip
    assert table(built, "wind-bundled-arrivals") == [["wind-test", "121.5", "did not arrive", "-"]]
    every = [c for t in built.tables() for row in t.rows for c in row]
    assert not any(f"{BOGUS:.1f}" in c.text for c in every)


def test_a_straight_run_makes_good_its_speed(built):
    rows = data(built, "wind-wind-halves-smg")
    assert rows[0] == ["controller", "t", "under_way", "median", "q25", "q75"]
    assert {r[0] for r in rows[1:]} == {"dwa", "udwa"}
    assert [r[1] for r in rows[1:] if r[0] == "dwa"] == ["1.000", "3.000", "5.000", "7.000",
                                                         "9.000"]  # fmt: skip
    assert {tuple(r[3:]) for r in rows[1:]} == {("5.000", "5.000", "5.000")}


def test_the_tracks_are_the_bundled_scenes_over_their_field(built):
    rows = data(built, "wind-tracks")
    assert {(r[0], r[1]) for r in rows[1:]} == {("wind-test", "dwa"), ("wind-test", "udwa")}
    last = [r for r in rows if r[1] == "dwa"][-1]
    assert last[2:] == ["10.000", "85.355", "85.355", "50.000", "0.000"]


def test_every_figure_is_a_png_of_150_dpi_or_more(built):
    assert {f.id for f in built.figures()} == {"wind-tracks", "wind-wind-halves-smg",
                                               "wind-wind-halves-differences"}  # fmt: skip
    for f in built.figures():
        image = Image.open(io.BytesIO(f.png))
        assert image.format == "PNG" and min(image.info["dpi"]) >= 149.9, f.id


def test_no_wind_run_no_section():
    assert wind.section(Results([], [])) is None
