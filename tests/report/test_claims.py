"""Claims and published tables (usvtool/report/sections/claims.py, published.py) on hand-made
results tables: verdicts, ties, missing runs, absolute claims, statistics and the optimisation
rate."""

from __future__ import annotations

from dataclasses import replace

import pytest

from usvtool.report.data import load, statistic
from usvtool.report.papers import UDWA_TABLE_1, Claim, Quote
from usvtool.report.sections import claims, published
from usvtool.results import Row, write_results


def _results(tmp_path, rows):
    write_results(tmp_path / "metrics.csv", [Row(*r) for r in rows])
    return load([tmp_path / "metrics.csv"])


def _claim(**kw) -> Claim:
    base = dict(id="c", paper="iwso-dwa", quotes=(Quote("5.2", "q"),), kind="routes",
                metric="length_m", statistic="median", better="lower", method="iwso",
                rivals=("wso",), cases=("env1", "env2"))  # fmt: skip
    return Claim(**{**base, **kw})


ROUTES = [  # key, kind, case, method, seed, metric, value
    ("a1", "routes", "env1", "iwso", 1, "length_m", "700"),
    ("a2", "routes", "env1", "iwso", 2, "length_m", "720"),
    ("a3", "routes", "env1", "iwso", 3, "length_m", "800"),  # median 720
    ("b1", "routes", "env1", "wso", 1, "length_m", "730"),
    ("b2", "routes", "env1", "wso", 2, "length_m", "740"),  # median 735
    ("c1", "routes", "env2", "iwso", 1, "length_m", "500"),
    ("d1", "routes", "env2", "wso", 1, "length_m", "500"),  # a tie
]


def test_a_claim_holds_only_when_strictly_better_in_every_case(tmp_path):
    results = _results(tmp_path, ROUTES)
    v = claims.judge(results, _claim(cases=("env1",)))
    assert v.verdict == claims.HOLDS and v.evidence == ["env1: iwso 720 against wso 735"]
    assert claims.judge(results, _claim()).verdict == claims.FAILS  # the env2 tie
    assert claims.judge(results, _claim(better="higher", cases=("env1",))).verdict == claims.FAILS


def test_a_case_without_runs_is_not_tested_but_a_failure_elsewhere_still_fails(tmp_path):
    results = _results(tmp_path, ROUTES)
    assert claims.judge(results, _claim(cases=("env1", "env3"))).verdict == claims.UNTESTED
    assert claims.judge(results, _claim(cases=("env3", "env2"))).verdict == claims.FAILS


def test_statistics_as_the_papers_state_them(tmp_path):
    rows = ROUTES + [("a1", "routes", "env1", "iwso", 1, "fitness", "9"),
                     ("a2", "routes", "env1", "iwso", 2, "fitness", "7"),
                     ("a3", "routes", "env1", "iwso", 3, "fitness", "8")]  # fmt: skip
    results = _results(tmp_path, rows)
    stat = lambda name: statistic(results, "routes", "env1", "iwso", "length_m", name)  # noqa: E731
    assert (stat("min"), stat("max"), stat("median"), stat("value")) == (700, 800, 720, 720)
    assert stat("mean") == pytest.approx(740)
    assert stat("variance") == pytest.approx(((40**2) + (20**2) + (60**2)) / 2)  # ddof 1: 2800
    assert stat("of-best") == 720  # the length of the seed with the lowest fitness (7)


def test_absolute_claims_count_every_run_and_an_absent_collision_is_none(tmp_path):
    rows = [("r1", "runs", "s1", "gdwa", 1, "judged", "2"), ("r1", "runs", "s1", "gdwa", 1,
            "compliant", "2"), ("r2", "runs", "s2", "gdwa", 1, "judged", "1"),
            ("r2", "runs", "s2", "gdwa", 1, "compliant", "0"),
            ("r2", "runs", "s2", "gdwa", 1, "collision", "target")]  # fmt: skip
    results = _results(tmp_path, rows)
    compliant = _claim(kind="runs", metric="compliant", statistic="every", better="higher",
                       method="gdwa", rivals=(), target="judged")  # fmt: skip
    assert claims.judge(results, replace(compliant, cases=("s1",))).verdict == claims.HOLDS
    v = claims.judge(results, replace(compliant, cases=("s1", "s2")))
    assert v.verdict == claims.FAILS and v.evidence == ["s1: 1/1 runs", "s2: 0/1 runs"]
    collision = _claim(kind="runs", metric="collision", statistic="every", method="gdwa",
                       rivals=(), target=0.0)  # fmt: skip
    v = claims.judge(results, replace(collision, cases=("s1", "s2")))
    assert v.evidence == ["s1: 1/1 runs", "s2: 0/1 runs"]


def test_the_optimisation_rate_is_computed_from_our_medians_when_runs_lack_it(tmp_path):
    rows = [("u1", "runs", "emergency-head-on", "udwa", 1, "average_distance_m", "78.5"),
            ("c1", "runs", "emergency-head-on", "ccdwa", 1, "average_distance_m", "54.8")]
    results = _results(tmp_path, rows)
    column = UDWA_TABLE_1.column("average_distance_rate")
    rate = published.ours(results, UDWA_TABLE_1, "udwa", "emergency-head-on", column)
    assert rate == pytest.approx(100 * (78.5 - 54.8) / 54.8)  # 43.25 %, the paper's Table 1
    assert published.ours(results, UDWA_TABLE_1, "ccdwa", "emergency-head-on", column) is None
    table = published.table(results, UDWA_TABLE_1)
    row = next(r for r in table.rows if [c.text for c in r[:2]] == ["udwa", "emergency-head-on"])
    assert [c.text for c in row[2:]] == ["-", "59.48", "78.50", "78.50", "43.25", "43.25"]


def test_a_variant_run_in_the_claims_cases_is_judged_beside_the_papers_method(tmp_path):
    rows = ROUTES + [("e1", "routes", "env1", "iwso+g", 1, "length_m", "690"),
                     ("e2", "routes", "env2", "iwso+g", 1, "length_m", "480"),
                     ("f1", "routes", "grid20", "wso+s", 1, "length_m", "30")]  # fmt: skip
    results = _results(tmp_path, rows)
    assert claims.variants(results, _claim()) == ["iwso+g"]
    judged = {v.claim.id: v.verdict for v in claims.verdicts(results)}
    shorter = [k for k in judged if k.startswith("iwso-shorter")]
    assert shorter == ["iwso-shorter", "iwso-shorter (iwso+g)"]
    assert judged["iwso-shorter (iwso+g)"] == claims.HOLDS  # 690 < 735, 480 < 500
    assert judged["iwso-shorter"] == claims.FAILS  # the env2 tie
