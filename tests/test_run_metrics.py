"""The per-route and per-run figures of usvtool.measures on hand-computed cases, and the
metrics stage's rows on hand-made files (a polyline route, a two-ship trace)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from affine import Affine

from usvtool import measures
from usvtool.grid import Grid
from usvtool.metrics import MetricsOptions, measure
from usvtool.route import Route, write_path_geojson
from usvtool.trace import Trace, write_events, write_trace

# UDWA paper (004) Table 1: average distances (CCDWA, UDWA) and the optimisation rate (%)
TABLE_1 = {"head-on": (54.80, 78.50, 43.25), "crossing": (50.93, 66.90, 31.36),
           "overtaking": (37.93, 63.65, 67.81)}  # fmt: skip


@pytest.mark.parametrize("situation", sorted(TABLE_1))
def test_optimisation_rate_reproduces_table_1(situation):
    ccdwa, udwa, rate = TABLE_1[situation]
    assert round(measures.optimisation_rate(udwa, ccdwa) * 100, 2) == rate


def test_optimisation_rate_and_length_ratio_edge_cases():
    assert measures.optimisation_rate(10.0, 10.0) == 0.0
    assert measures.optimisation_rate(5.0, 10.0) == -0.5
    assert measures.optimisation_rate(None, 10.0) is None
    assert measures.optimisation_rate(1.0, 0.0) is None
    assert measures.length_ratio(110.0, 100.0) == pytest.approx(1.1)
    assert measures.length_ratio(1.0, 0.0) is None
    assert measures.length_ratio(None, 1.0) is None


def two_ship_trace() -> Trace:
    """Own ship north along x = 0 at 1 m/s, t = 0..4 s; the target at x = 3 southbound from
    y = 4 at 1 m/s: distances sqrt(9 + (4 - 2t)^2) = 5, sqrt(13), 3, sqrt(13), 5."""
    t = np.arange(5.0)
    own = [[0.0, ti, 0.0, 1.0, 0.0] for ti in t]
    tgt = [[3.0, 4.0 - ti, 180.0, 1.0, 0.0] for ti in t]
    return Trace.from_states(t, ["own", "target"], np.stack([own, tgt], axis=1))


def test_closest_and_average_distance_by_hand():
    tr = two_ship_trace()
    ox, oy, tx, ty = tr.x[:, 0], tr.y[:, 0], tr.x[:, 1:], tr.y[:, 1:]
    assert measures.closest_distance(ox, oy, tx, ty) == pytest.approx(3.0)
    every = (5 + math.sqrt(13) + 3 + math.sqrt(13) + 5) / 5
    assert measures.average_distance(ox, oy, tx, ty) == pytest.approx(every)
    phase = measures.encounter_steps(tr.t, [(1.0, 4.0)])  # steps 1, 2, 3
    assert phase.tolist() == [False, True, True, True, False]
    assert measures.average_distance(ox, oy, tx, ty, phase) == pytest.approx(
        (2 * math.sqrt(13) + 3) / 3
    )
    assert measures.closest_distance(ox, oy, np.zeros((5, 0)), np.zeros((5, 0))) is None
    assert measures.average_distance(ox, oy, tx, ty, np.zeros(5, bool)) is None


def test_average_is_over_the_nearest_target():
    d = measures.average_distance([0, 0], [0, 0], [[10, 1], [2, 30]], [[0, 0], [0, 0]])
    assert d == pytest.approx((1 + 2) / 2)


def test_track_samples_every_window():
    track = np.column_stack([np.arange(25.0), np.zeros(25)])
    assert measures.track_samples(track, dt=1.0)[:, 0].tolist() == [0, 10, 20, 24]
    assert measures.track_samples(track, dt=0.5)[:, 0].tolist() == [0, 20, 24]
    assert measures.track_samples(track, dt=20.0).shape == (25, 2)  # window below dt: all


def test_a_route_row_by_hand(tmp_path):
    # one right-angle turn: (0, 0) -> (0, 5) -> (6, 5): length 11, one turn, mot = π/2; the
    # any-angle optimum (0, 0) -> (6, 5): sqrt(61)
    d = tmp_path / "chart"
    d.mkdir()
    points = np.array([(0, 0), (0, 5), (6, 5)], float)
    for algo, pts in (("iwso", points), ("anyangle", np.array([(0, 0), (6, 5)], float))):
        route = Route(pts, algo, {}, 1, 0.0, 0, 0.0, 1.5, 0.25, True, [], 1)
        grid = Grid(np.zeros((10, 10), np.uint8), Affine(1, 0, 0, 0, -1, 10))
        write_path_geojson(d / f"{algo}.geojson", route, grid)
    result = measure([d / "iwso.geojson", d / "anyangle.geojson"])
    anyangle, iwso = result.rows  # sorted by path
    assert iwso["chart"] == "chart" and iwso["algorithm"] == "iwso"
    assert iwso["length_m"] == pytest.approx(11.0)
    assert iwso["turns"] == 1 and iwso["mot"] == pytest.approx(math.pi / 2)
    assert iwso["length_ratio"] == pytest.approx(11.0 / math.hypot(6, 5))
    assert anyangle["length_ratio"] == 1.0 and anyangle["turns"] == 0
    assert result.to_csv().splitlines()[2] == "chart,iwso,11.0,1.4084,1,1.5708,1.5,0.25,True,1"


def test_a_run_row_by_hand(tmp_path):
    write_trace(tmp_path / "r.csv", two_ship_trace())
    encounters = [{"target": 0, "class": "head-on", "onset_s": 1.0, "released_s": 4.0,
                   "compliant": False, "failed_rules": ["rule14-starboard"]}]  # fmt: skip
    run = {"scenario": "s", "controller": "dwa", "parameters": {}, "seed": 0, "arrived": True,
           "collision": None, "time_s": 4.0, "dt": 1.0, "goal": [0, 4], "goal_tolerance": 1,
           "own_length": 1, "domain_intrusion_s": 2.0}  # fmt: skip
    write_events(tmp_path / "r.json", {"encounters": encounters, "run": run})
    (row,) = measure([tmp_path / "r.csv"]).rows
    assert row["closest_distance_m"] == pytest.approx(3.0)
    assert row["average_distance_m"] == pytest.approx((2 * math.sqrt(13) + 3) / 3)
    assert row["length_m"] == pytest.approx(4.0) and row["turns"] == 0
    assert row["arrival_time_s"] == 4.0 and row["domain_intrusion_s"] == 2.0
    assert (row["encounters"], row["judged"], row["compliant"]) == (1, 1, 0)
    assert row["failed_rules"] == ["rule14-starboard"]
    table = json.loads(measure([tmp_path / "r.csv"]).to_json())
    assert table["rows"][0]["average_distance_m"] == round((2 * math.sqrt(13) + 3) / 3, 3)


def test_rates_against_a_reference_controller(tmp_path):
    tr = two_ship_trace()
    for name, shift in (("dwa", 0.0), ("udwa", 3.0)):
        moved = Trace(tr.t, tr.ships, tr.x - [[shift, 0]], tr.y, tr.heading, tr.speed,
                      tr.yaw_rate)  # fmt: skip
        write_trace(tmp_path / f"{name}.csv", moved)
        run = {"scenario": "s", "controller": name, "seed": 0, "arrived": False}
        write_events(tmp_path / f"{name}.json", {"encounters": [], "run": run})
    opts = MetricsOptions(reference_controller="dwa")
    dwa, udwa = measure([tmp_path / "udwa.csv", tmp_path / "dwa.csv"], opts).rows
    assert dwa["closest_distance_rate"] == 0.0
    assert udwa["closest_distance_rate"] == pytest.approx((6 - 3) / 3)
    assert udwa["average_distance_m"] is None and udwa["average_distance_rate"] is None
