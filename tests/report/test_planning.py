"""The planning section's tables (usvtool/report/sections/planning.py) on a hand-made results
table: medians over the collision-free routes, the colliding ones counted as failures in the
collision-free column, never as short routes."""

from __future__ import annotations

from usvtool.report.data import load
from usvtool.report.sections import planning
from usvtool.results import Row, write_results


def _results(tmp_path):
    rows = []
    # wso: lengths 700, 800, 900 collision-free and 100 through land (median over the three:
    # 800; over all four it would be 750); astar once, 650
    for seed, (length, free) in enumerate([(700, True), (800, True), (900, True), (100, False)]):
        key = f"w{seed}"
        rows += [Row(key, "routes", "env1", "wso", seed, "length_m", str(length)),
                 Row(key, "routes", "env1", "wso", seed, "length_ratio", str(length / 650)),
                 Row(key, "routes", "env1", "wso", seed, "collision_free", str(free))]
    rows += [Row("a", "routes", "env1", "astar", None, "length_m", "650"),
             Row("a", "routes", "env1", "astar", None, "length_ratio", "1"),
             Row("a", "routes", "env1", "astar", None, "collision_free", "True")]
    # pso: its one route collides: no median at all
    rows += [Row("p", "routes", "env1", "pso", 0, "length_m", "90"),
             Row("p", "routes", "env1", "pso", 0, "collision_free", "False")]
    write_results(tmp_path / "metrics.csv", rows)
    return load([tmp_path / "metrics.csv"])


def test_route_medians_are_over_the_collision_free_routes(tmp_path):
    results = _results(tmp_path)
    table = planning.metrics_table(results, "env1", ["wso", "pso", "astar"])
    cells = {r[0].text: [c.text for c in r] for r in table.rows}
    assert cells["wso"][1] == "800.00" and cells["wso"][-2:] == ["75", "4"]
    assert cells["pso"][1] == "-" and cells["pso"][-2:] == ["0", "1"]
    assert cells["astar"][1] == "650.00"
    overview = planning.overview_table(results, ["env1"])
    ratio = {r[0].text: r[1].text for r in overview.rows}
    assert ratio["wso"] == f"{800 / 650:.3f}" and ratio["pso"] == "-"


def test_a_label_says_how_many_routes_are_collision_free(tmp_path):
    results = _results(tmp_path)
    assert planning._free_label("wso", results.select("routes", "env1", "wso")) == "wso (3 of 4)"
    assert planning._free_label("astar", results.select("routes", "env1", "astar")) == "astar"
