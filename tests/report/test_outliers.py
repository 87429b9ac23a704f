"""The rule for an axis a few far values would squash (usvtool/report/figures/outliers.py), on
hand-made values."""

from __future__ import annotations

import numpy as np
import pytest

from usvtool.report.figures.outliers import label, limits


def test_one_far_value_is_beyond_and_the_axis_spans_the_rest_padded():
    # astar's 33 turns beside 1-5: the gap 28 exceeds the rest's range 4
    found = limits([3, 3, 2, 1, 5, 33, 3])
    assert (found.below, found.above) == (None, 5.0)
    assert (found.low, found.high) == pytest.approx((1 - 0.12 * 4, 5 + 0.12 * 4))


def test_a_pair_of_far_values_is_beyond_a_cluster_of_many_is_not():
    rest = list(np.linspace(0.0, 10.0, 41))
    assert limits([*rest, 100.0, 105.0]).above == 10.0  # gap 90 > 10
    # 25 runs of one algorithm far from the others are its box, never beyond (at most 3)
    assert not limits([*rest, *np.linspace(50.0, 60.0, 25)]).clipped
    # 4 far values are more than a few
    assert not limits([*rest, 100.0, 101.0, 102.0, 103.0]).clipped


def test_no_gap_wider_than_the_rest_or_no_rest_range_keeps_every_value():
    assert not limits([0, 1, 2, 3, 5]).clipped  # gap 2 < the rest's 3
    assert not limits([3, 3, 3, 3, 5]).clipped  # the rest has no range
    assert limits([]) is None


def test_values_far_on_both_sides():
    # udwa+ at +105 s and one scene at -200 s beside -5..5 s
    found = limits([-200.0, *range(-5, 6), 105.0])
    assert (found.below, found.above) == (-5.0, 5.0)


def test_the_label_gives_the_furthest_and_how_many():
    assert label([104.8]) == "105"
    assert label([33.0, 40.5]) == "2: to 40.5"
    assert label([-0.00123, -0.0004]) == "2: to -0.00123"
