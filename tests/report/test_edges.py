"""Routes that hug the grid's edges (usvtool/report/edges.py): the share of a route's length
within one cell of the grid's border, by hand on tiny routes, and the counts a claim is told."""

from __future__ import annotations

import json

import numpy as np
import pytest
from affine import Affine

from usvtool.grid import Grid, write_grid
from usvtool.report import edges
from usvtool.report.data import load
from usvtool.report.papers.schema import Claim
from usvtool.results import Row, write_results

BOX = (0.0, 0.0, 10.0, 10.0)  # a 10 x 10 grid of 1 m cells


@pytest.mark.parametrize(("points", "share"), [
    ([[0.5, 0.5], [9.5, 0.5], [9.5, 9.5]], 1.0),  # along two sides, in the outer ring
    ([[0.5, 5.0], [9.5, 5.0]], 1.0 / 9.0),  # across: 0.5 m in the band at each end of 9 m
    ([[2.0, 2.0], [8.0, 8.0]], 0.0),  # inside the ring
    ([[1.0, 5.0], [1.0, 9.0]], 1.0),  # on the band's inner edge (distance 1 cell): in it
    # 4 m along the bottom (in), then 4 m straight up from x = 4 (from y = 1 on: out): 5 of 8
    ([[0.0, 0.5], [4.0, 0.5], [4.0, 4.5]], 4.5 / 8.0),
])
def test_the_share_in_the_edge_band_by_hand(points, share):
    assert edges.band_share(points, BOX, 1.0) == pytest.approx(share)


def test_a_route_of_no_length_is_in_the_band_only_when_its_points_are():
    assert edges.band_share([[0.5, 0.5], [0.5, 0.5]], BOX, 1.0) == 1.0
    assert edges.band_share([[5.0, 5.0]], BOX, 1.0) == 0.0


def _batch(tmp_path, routes: dict[str, list], turns: dict[str, int] | None = None):
    """A table of route jobs in case c, each with its route and the one grid (10 x
    10 cells of 2 m: a band of 2 m), and its turns (1 unless given)."""
    grid = tmp_path / "grids" / "g"
    grid.mkdir(parents=True)
    write_grid(grid / "grid.tif", Grid(np.zeros((10, 10), np.uint8), Affine(2, 0, 0, 0, -2, 20)))
    rows = []
    for key, points in routes.items():
        method = key.rstrip("0123456789")
        folder = tmp_path / "routes" / key
        folder.mkdir(parents=True)
        (folder / "job.json").write_text(json.dumps({"grid": "g"}), encoding="utf-8")
        (folder / "route.geojson").write_text(json.dumps({
            "type": "Feature", "properties": {"map_coordinates": points},
            "geometry": {"type": "LineString", "coordinates": points}}), encoding="utf-8")
        rows.append(Row(key, "routes", "c", method, int(key[-1]), "turns",
                        str((turns or {}).get(key, 1))))
        rows.append(Row(key, "routes", "c", method, int(key[-1]), "collision_free", "True"))
    write_results(tmp_path / "metrics.csv", rows)
    return load([tmp_path / "metrics.csv"])


def test_a_claim_is_told_how_many_routes_of_each_method_hug_the_edges(tmp_path):
    frame = [[1.0, 1.0], [1.0, 19.0], [19.0, 19.0]]  # along the west and north: share 1
    across = [[1.0, 1.0], [19.0, 19.0]]  # the diagonal: 1 m of x and y at each end, 1/9
    just = [[1.0, 1.0], [11.0, 1.0], [11.0, 9.0]]  # 10 m along the south, 1 m up: 11 of 18
    results = _batch(tmp_path, {"a1": frame, "a2": across, "a3": just, "b1": across})
    claim = Claim("x", "", (), "routes", "turns", "median", "lower", "a", ("b",), ("c",))
    a, b = edges.edge_share(results, claim)
    assert (a.method, a.hugging, a.known, a.runs) == ("a", 2, 3, 3)
    assert sorted(a.keys) == ["a1", "a3"]
    assert a.text() == "2 of 3 routes of a in c hug the grid's edges"
    assert (b.method, b.hugging, b.known, b.keys) == ("b", 0, 1, ())
    assert edges.edge_share(results, Claim("y", "", (), "runs", "arrived", "median", "lower",
                                           "a", (), ("c",))) == ()  # fmt: skip
    # a route without its files is unknown, not a route along the edges
    (tmp_path / "routes" / "a1" / "route.geojson").unlink()
    a = edges.edge_share(results, claim)[0]
    assert (a.hugging, a.known, a.runs) == (1, 2, 3)
    assert a.text() == "1 of 2 routes of a in c hug the grid's edges (1 without files)"


def test_the_planning_section_counts_each_methods_routes_along_the_edges(tmp_path):
    from usvtool.report.sections import planning

    frame, across = [[1.0, 1.0], [1.0, 19.0], [19.0, 19.0]], [[1.0, 1.0], [19.0, 19.0]]
    results = _batch(tmp_path, {"a1": frame, "a2": across, "b1": across})
    jobs = {m: results.select("routes", "c", m) for m in ("a", "b")}
    assert planning.edge_counts(jobs) == {"a": (1, 2)}  # b: none, left out
    assert planning.edge_paragraph({"a": (1, 2)}).startswith(
        "Routes that hug the grid's edges (more than 50 % of their length within 1 cell of its "
        "border): a 1 of 2.")  # fmt: skip


def test_a_claim_decided_by_routes_along_the_edges_says_so(tmp_path):
    from usvtool.report import judging

    frame = [[1.0, 1.0], [1.0, 19.0], [19.0, 19.0]]  # along two sides: hugs
    inside = [[5.0, 5.0], [15.0, 15.0]]  # the middle: does not
    # a: six routes along the frame turning once, two inside turning 5 times; b: six inside, 5
    routes = {**{f"a{i}": frame for i in range(6)}, "a6": inside, "a7": inside,
              **{f"b{i}": inside for i in range(6)}}
    turns = {**{f"a{i}": 1 for i in range(6)}, "a6": 5, "a7": 5, **{f"b{i}": 5 for i in range(6)}}
    results = _batch(tmp_path, routes, turns)
    claim = Claim("fewer", "", (), "routes", "turns", "median", "lower", "a", ("b",), ("c",))
    # with them: a's six 1s below all of b's 5s (the two 5s tie): U test p < 0.05, holds
    (v,) = judging.flag_edges(results, judging.judge_family(results, [claim]))
    assert v.verdict == judging.HOLDS
    # without them a turns 5, 5 against b's six 5s: nothing left to tell them apart
    assert v.edges.startswith("6 of 8 routes of a in c hug the grid's edges: without them the "
                              'verdict would be "')
    assert not v.edges.endswith('"holds"')
    # b's six inside routes turning 9 times: a holds with its edge routes and would not without
    same = _batch(tmp_path / "same", routes, {**turns, **{f"b{i}": 9 for i in range(6)}})
    (v,) = judging.flag_edges(same, judging.judge_family(same, [claim]))
    assert v.verdict == judging.HOLDS  # eight against six, every a below every b
    # without the edge routes a's 5, 5 against b's six 9s: exact U p = 2 / C(8, 2) = 1 / 14,
    # a shift of 4 turns, beyond the margin of 1: inconclusive
    assert v.edges.endswith(': without them the verdict would be "inconclusive"')
    plain = _batch(tmp_path / "plain", {k: inside for k in routes}, turns)
    (v,) = judging.flag_edges(plain, judging.judge_family(plain, [claim]))
    assert v.edges == ""
