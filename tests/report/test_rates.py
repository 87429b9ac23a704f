"""usvtool.report.rates: exact McNemar and Fisher against scipy, the counts of each cell, and
Newcombe's intervals against the published figures and by their formulas."""

from __future__ import annotations

import math

import pytest
from scipy.stats import binomtest, fisher_exact

from usvtool.report import rates
from usvtool.report.rates import compare_failures

Z = 1.959963984540054


def test_paired_cells_and_exact_mcnemar():
    # pairs (method failed, rival failed): 2 both, 1 method only, 6 rival only, 3 neither
    method = [True, True, True] + [False] * 6 + [False] * 3
    rival = [True, True, False] + [True] * 6 + [False] * 3
    r = compare_failures(method, rival, paired=True)
    assert r.test == "exact McNemar"
    assert (r.cells.both, r.cells.method, r.cells.rival, r.cells.neither) == (2, 1, 6, 3)
    assert r.cells.sizes == (12, 12)
    # the binomial test of 1 of 7 discordant pairs: 2 * (1 + 7) / 128
    assert r.p == pytest.approx(binomtest(1, 7, 0.5).pvalue) == pytest.approx(16 / 128)
    assert (r.method_rate, r.rival_rate) == (3 / 12, 8 / 12)
    assert r.difference == pytest.approx(5 / 12)  # > 0: the method fails less
    assert r.low < r.difference < r.high


def test_no_discordant_pair_is_no_evidence():
    r = compare_failures([True, False, False], [True, False, False], paired=True)
    assert r.p is None and r.difference == 0
    f = compare_failures([False, False], [False, False, False], paired=False)
    assert f.p is None and f.difference == 0


def test_fisher_against_scipy():
    method = [True] * 2 + [False] * 28
    rival = [True] * 14 + [False] * 16
    r = compare_failures(method, rival, paired=False)
    assert r.test == "Fisher's exact"
    assert r.p == pytest.approx(fisher_exact([[2, 28], [14, 16]]).pvalue)
    assert (r.cells.method, r.cells.rival, r.cells.sizes) == (2, 14, (30, 30))
    assert r.cells.both is None and r.cells.neither is None
    assert r.difference == pytest.approx(12 / 30)


@pytest.mark.parametrize(
    ("k1", "n1", "k2", "n2", "low", "high"),
    [
        # Newcombe 1998 (Stat. Med. 17, 873-890), Table II, method 10
        (56, 70, 48, 80, 0.0524, 0.3339),
        (9, 10, 3, 10, 0.1705, 0.8090),
        (6, 7, 2, 7, 0.0582, 0.8062),
        (5, 56, 0, 29, -0.0381, 0.1926),
        (0, 10, 0, 20, -0.1611, 0.2775),
        (10, 10, 0, 20, 0.6791, 1.0),
    ],
)
def test_newcombe_hybrid_published(k1, n1, k2, n2, low, high):
    got = rates.newcombe_hybrid(k1, n1, k2, n2, Z)
    assert got == pytest.approx((low, high), abs=1e-4)


def test_difference_turned_round_for_the_sign():
    # the method's failures 56/70 against the rival's 48/80: the method fails more, so the
    # improvement is negative and its interval is Newcombe's for p1 - p2, negated
    method = [True] * 56 + [False] * 14
    rival = [True] * 48 + [False] * 32
    r = compare_failures(method, rival, paired=False)
    assert r.difference == pytest.approx(-0.2)
    assert (r.low, r.high) == pytest.approx((-0.3339, -0.0524), abs=1e-4)


def test_wilson_by_formula():
    # 0 of 10: (0, z^2 / (10 + z^2)); 5 of 10 symmetric about 1/2
    low, high = rates.wilson(0, 10, Z)
    assert low == 0 and high == pytest.approx(Z * Z / (10 + Z * Z))
    low, high = rates.wilson(5, 10, Z)
    assert low + high == pytest.approx(1.0)


def test_newcombe_paired_by_formula():
    # a d - b c = 108 - 2 = 106 > n/2 = 12: phi = (106 - 12) / sqrt(14 * 10 * 13 * 11)
    a, b, c, d = 12, 2, 1, 9
    n = a + b + c + d
    p1, p2 = (a + b) / n, (a + c) / n
    l1, u1 = rates.wilson(a + b, n, Z)
    l2, u2 = rates.wilson(a + c, n, Z)
    phi = 94 / math.sqrt(14 * 10 * 13 * 11)
    low = p1 - p2 - math.sqrt((p1 - l1) ** 2 - 2 * phi * (p1 - l1) * (u2 - p2) + (u2 - p2) ** 2)
    high = p1 - p2 + math.sqrt((u1 - p1) ** 2 - 2 * phi * (u1 - p1) * (p2 - l2) + (p2 - l2) ** 2)
    assert rates.newcombe_paired(a, b, c, d, Z) == pytest.approx((low, high))


def test_newcombe_paired_without_correlation_is_square_and_add():
    # a d - b c = 5 - 4 = 1 <= n/2: phi = 0, the marginal Wilson intervals squared and added
    a, b, c, d = 1, 2, 2, 5
    got = rates.newcombe_paired(a, b, c, d, Z)
    assert got == pytest.approx(rates.newcombe_hybrid(a + b, 10, a + c, 10, Z))
    # a positive correlation narrows the interval
    assert rates.newcombe_paired(12, 2, 1, 9, Z)[1] - rates.newcombe_paired(12, 2, 1, 9, Z)[0] < (
        rates.newcombe_hybrid(14, 24, 13, 24, Z)[1] - rates.newcombe_hybrid(14, 24, 13, 24, Z)[0]
    )


def test_refusals():
    with pytest.raises(ValueError, match="size"):
        compare_failures([True], [True, False], paired=True)
    with pytest.raises(ValueError, match="one run"):
        compare_failures([], [True], paired=False)
