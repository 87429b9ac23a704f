"""usvtool.report.margins: every metric a claim may judge has a positive smallest effect of
interest with a reason, and the margin is the larger of its absolute amount and its share."""

from __future__ import annotations

from pathlib import Path

import pytest

from usvtool.pipeline import CLAIM_METRICS
from usvtool.report.margins import MARGINS, margin


def test_every_claim_metric_declared_with_a_reason():
    for kind, metrics in CLAIM_METRICS.items():
        for metric in metrics:
            declared = MARGINS[kind][metric]
            assert declared.absolute > 0 or declared.share > 0, (kind, metric)
            assert declared.reason and "\n" not in declared.reason, (kind, metric)
    # and nothing declared that no claim can judge
    for kind, metrics in MARGINS.items():
        assert set(metrics) <= set(CLAIM_METRICS[kind]), kind


def test_margin_is_the_larger_of_absolute_and_share():
    # routes' length: 1 % of the rival's median
    assert margin("routes", "length_m", 836.0) == pytest.approx(8.36)
    # a count: one, whatever the rival's median
    assert margin("runs", "compliant", 7.0) == 1.0
    # a time: a tenth of the rival's, never under 5 ms
    assert margin("routes", "planning_time_s", 0.156) == pytest.approx(0.0156)
    assert margin("routes", "planning_time_s", 0.02) == 0.005
    # a cost: a share of |median| (F8 is negative), never under 1e-8
    assert margin("functions", "final_cost", -12000.0) == pytest.approx(120.0)
    assert margin("functions", "final_cost", 3e-11) == 1e-8


def test_undeclared_metric_refused():
    with pytest.raises(KeyError):
        margin("runs", "fitness", 1.0)


def test_docs_table_lists_every_margin():
    # docs/statistics.md's table of the smallest effects of interest names every declared
    # (kind, metric)
    text = (Path(__file__).parents[2] / "docs" / "statistics.md").read_text()
    section = text.split("### The smallest effects of interest")[1].split("\n### ")[0]
    rows = [line.split("|")[1:3] for line in section.splitlines() if line.startswith("| ")]
    for kind, metrics in MARGINS.items():
        for metric in metrics:
            assert any(kind in k and f"`{metric}`" in m for k, m in rows), (kind, metric)
