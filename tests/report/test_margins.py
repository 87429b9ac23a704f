"""usvtool.report.margins: every metric a claim may judge has a positive smallest effect of
interest with a reason, and the margin is the larger of its absolute amount and its share."""

from __future__ import annotations

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
