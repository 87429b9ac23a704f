"""A paper's table beside ours (usvtool/report/sections/published.py) on a hand-made results
table: the reference controller's optimisation rate is shown as the reference, not 0."""

from __future__ import annotations

from usvtool.report.data import load
from usvtool.report.papers import TABLES
from usvtool.report.sections import published
from usvtool.results import Row, write_results


def results(tmp_path):
    rows = []
    # one run each in emergency-head-on; both carry a rate against ccdwa, ccdwa's against itself
    for key, method, average, rate in (("c", "ccdwa", "50.0", "0.0"), ("u", "udwa", "60.0", "0.2")):
        rows += [Row(key, "runs", "emergency-head-on", method, 1, metric, value)
                 for metric, value in (("arrived", "True"), ("closest_distance_m", "30.0"),
                                       ("average_distance_m", average),
                                       ("average_distance_rate", rate))]  # fmt: skip
    write_results(tmp_path / "metrics.csv", rows)
    return load([tmp_path / "metrics.csv"])


def test_the_reference_controllers_rate_is_the_reference_not_zero(tmp_path):
    table = published.table(results(tmp_path), TABLES["udwa-table-1"])
    rate = table.columns.index("optimization rate (%)")
    by_method = {r[0].text: r for r in table.rows if r[1].text == "emergency-head-on"}
    assert by_method["ccdwa"][rate].text == published.REFERENCE_MARK  # its runs say 0.0
    assert by_method["udwa"][rate].text == "20.00"  # 0.2 x 100, at the paper's 2 decimals
    assert "against the reference controller ccdwa" in table.caption


def test_a_rate_the_runs_lack_is_computed_against_the_reference_but_its_own(tmp_path):
    found = results(tmp_path)
    for job in found.jobs:
        del job.metrics["average_distance_rate"]
    column = TABLES["udwa-table-1"].column("average_distance_rate")
    # (60 - 50) / 50 = 0.2, in % 20
    assert published.ours(found, TABLES["udwa-table-1"], "udwa", "emergency-head-on",
                          column) == 20.0  # fmt: skip
    assert published.ours(found, TABLES["udwa-table-1"], "ccdwa", "emergency-head-on",
                          column) is None  # fmt: skip
