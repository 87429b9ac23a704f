"""usvtool.report.inference: the rank tests, the effect sizes, their bootstrap and Holm's
correction against figures computed by hand or by exact enumeration here."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.stats import rankdata

from usvtool.report import inference
from usvtool.report.inference import compare, holm

INF = math.inf


def exact_mann_whitney(a, b) -> float:
    """Two-sided exact p by enumerating every split of the pooled ranks (doubling the smaller
    tail, capped at 1, as the exact test does)."""
    ranks = rankdata(list(a) + list(b))
    observed = sum(ranks[: len(a)])
    sums = [sum(ranks[list(c)]) for c in itertools.combinations(range(len(ranks)), len(a))]
    lower = sum(s <= observed + 1e-12 for s in sums) / len(sums)
    upper = sum(s >= observed - 1e-12 for s in sums) / len(sums)
    return min(1.0, 2 * min(lower, upper))


def exact_signed_rank(d) -> float:
    """Two-sided exact p by flipping every sign of the nonzero differences' ranks."""
    d = [x for x in d if x != 0]
    ranks = rankdata(np.abs(d))
    observed = sum(r for r, x in zip(ranks, d, strict=True) if x > 0)
    flips = [sum(r for r, s in zip(ranks, signs, strict=True) if s)
             for signs in itertools.product((0, 1), repeat=len(d))]  # fmt: skip
    lower = sum(w <= observed + 1e-12 for w in flips) / len(flips)
    upper = sum(w >= observed - 1e-12 for w in flips) / len(flips)
    return min(1.0, 2 * min(lower, upper))


def test_mann_whitney_by_hand():
    # lower is better: every method value below every rival value; U = 0, p = 2 / C(6, 3)
    c = compare([1, 2, 3], [4, 5, 6], paired=False, better="lower")
    assert c.test == "Mann-Whitney U" and c.effect_name == "Cliff's delta"
    assert c.p == pytest.approx(0.1)
    assert c.effect == 1.0 and (c.low, c.high) == (1.0, 1.0)
    # cross differences rival - method: 1,2,2,3,3,3,4,4,5 -> median 3
    assert c.shift == 3.0
    assert c.n == (3, 3) and c.median == (2.0, 5.0) and c.iqr == (1.0, 1.0)


def test_cliffs_delta_by_hand():
    # pairs (method, rival), lower better: (1,3)+ (1,5)+ (2,3)+ (2,5)+ (4,3)- (4,5)+ -> 4/6;
    # one pair of 6 has the method above: U = 1, P(U <= 1) = 2 / C(5, 2), p = 0.4
    c = compare([1, 2, 4], [3, 5], paired=False, better="lower")
    assert c.effect == pytest.approx(4 / 6)
    assert c.p == pytest.approx(0.4)
    # higher better: the same data judged the other way round
    d = compare([1, 2, 4], [3, 5], paired=False, better="higher")
    assert d.effect == pytest.approx(-4 / 6) and d.p == pytest.approx(0.4)
    assert d.shift == -c.shift


def test_mann_whitney_against_enumeration():
    method, rival = [1.1, 2.5, 0.3, 4.0], [3.0, 5.2, 6.1, 2.2, 7.7]
    c = compare(method, rival, paired=False, better="lower")
    assert c.p == pytest.approx(exact_mann_whitney(method, rival))


def test_mann_whitney_ties_normal_approximation_by_hand():
    # ties: the normal approximation with tie and continuity corrections
    method, rival = [1, 2, 2, 3, 3, 3, 4, 5, 6], [3, 4, 4, 5, 6, 6, 7, 8, 8]
    c = compare(method, rival, paired=False, better="lower")
    m = n = 9
    ranks = rankdata(method + rival)
    u = ranks[:m].sum() - m * (m + 1) / 2
    _, t = np.unique(ranks, return_counts=True)
    var = m * n / 12 * ((m + n + 1) - (t**3 - t).sum() / ((m + n) * (m + n - 1)))
    z = (abs(u - m * n / 2) - 0.5) / math.sqrt(var)
    assert c.p == pytest.approx(math.erfc(z / math.sqrt(2)))


def test_signed_rank_by_hand():
    # improvements rival - method (lower better): 1, 2, -3, 4, 5 -> W- = 3, W+ = 12;
    # sign patterns with W- <= 3: {}, {1}, {2}, {3}, {1,2}: p = 2 * 5 / 32
    rival = [10, 20, 30, 40, 50]
    method = [9, 18, 33, 36, 45]
    c = compare(method, rival, paired=True, better="lower")
    assert c.test == "Wilcoxon signed-rank"
    assert c.effect_name == "matched-pairs rank-biserial r"
    assert c.p == pytest.approx(0.3125)
    assert c.effect == pytest.approx((12 - 3) / 15)
    # Walsh averages of 1, 2, -3, 4, 5 (15 of them) sorted; the 8th is 2
    walsh = sorted((a + b) / 2 for a, b in itertools.combinations_with_replacement(
        [1, 2, -3, 4, 5], 2))  # fmt: skip
    assert c.shift == walsh[7] == 2.0


def test_signed_rank_ties_and_zeros_against_enumeration():
    # a zero (dropped), tied |differences|: scipy's exhaustive sign flips
    rival = [5, 6, 7, 8, 9, 10, 11]
    method = [4, 4, 7, 6, 10, 8, 8]  # improvements 1, 2, 0, 2, -1, 2, 3
    c = compare(method, rival, paired=True, better="lower")
    d = [1, 2, 0, 2, -1, 2, 3]
    assert c.p == pytest.approx(exact_signed_rank(d))
    # ranks of |1, 2, 2, 1, 2, 3|: 1.5, 4, 4, 1.5, 4, 6 -> W+ = 19.5, W- = 1.5
    assert c.effect == pytest.approx(18 / 21)


def test_pairing_matters():
    # a one-unit gain in every scene, scenes far apart: paired it is plain, unpaired it is lost
    rival = [10.0, 20, 30, 40, 50, 60, 70, 80]
    method = [r - 1 for r in rival]
    paired = compare(method, rival, paired=True, better="lower")
    independent = compare(method, rival, paired=False, better="lower")
    assert paired.p == pytest.approx(2 / 2**8) and paired.effect == 1.0
    assert independent.p > 0.5 and independent.effect == pytest.approx(8 / 64)
    assert paired.shift == 1.0


def test_all_equal_is_untestable():
    c = compare([3.0, 3, 3], [3.0, 3, 3], paired=False, better="lower")
    assert c.p is None and c.effect == 0.0 and (c.low, c.high) == (0.0, 0.0)
    d = compare([3.0, 3, 3], [3.0, 3, 3], paired=True, better="lower")
    assert d.p is None and d.effect == 0.0 and d.shift == 0.0
    assert c.iqr == (0.0, 0.0)


def test_a_failure_is_the_worst_outcome():
    # lower better: the method's failure (+inf) loses to every rival run, ties no one
    c = compare([1, INF], [2, 3], paired=False, better="lower")
    assert c.effect == 0.0  # two pairs won, two lost
    assert c.shift is None and c.median == (INF, 2.5) and c.iqr == (INF, 0.5)
    # infinities rank like a number above all: the same p and delta as a huge stand-in
    method, rival = [1, 2, 3, 4, INF], [2.5, 5, 6, INF, INF]
    big = [1e12 if v == INF else v for v in method], [1e12 if v == INF else v for v in rival]
    ours, stand_in = (compare(*pair, paired=False, better="lower") for pair in
                      ((method, rival), big))  # fmt: skip
    assert ours.p == pytest.approx(stand_in.p) and ours.effect == stand_in.effect
    # higher better: failures are -inf and lose
    h = compare([5, 6, -INF], [1, 2, 3], paired=False, better="higher")
    assert h.effect == pytest.approx((6 - 3) / 9)


def test_paired_failures():
    # lower better; pair 3: both failed (a tie, dropped); pair 4: the rival failed (the largest
    # |difference|); pair 5: the method failed. improvements: 1, 2, 0, +inf, -inf
    method = [9.0, 8, INF, 5, INF]
    rival = [10.0, 10, INF, INF, 7]
    c = compare(method, rival, paired=True, better="lower")
    # ranks of |1, 2, inf, inf|: 1, 2, 3.5, 3.5 -> W+ = 6.5, W- = 3.5
    assert c.effect == pytest.approx(3 / 10)
    assert c.p == pytest.approx(exact_signed_rank([1, 2, 1e12, -1e12]))
    assert c.shift is None


def test_bootstrap_is_seeded_and_brackets_the_effect():
    rng = np.random.default_rng(7)
    method, rival = rng.normal(0, 1, 20), rng.normal(0.8, 1, 20)
    a = compare(method, rival, paired=False, better="lower", seed=3)
    b = compare(method, rival, paired=False, better="lower", seed=3)
    c = compare(method, rival, paired=False, better="lower", seed=4)
    assert a == b and (a.low, a.high) != (c.low, c.high)
    assert a.low < a.effect < a.high and a.shift_low < a.shift < a.shift_high
    # without the shift: the same test and effect, the same bootstrap draws
    d = compare(method, rival, paired=False, better="lower", seed=3, shift=False)
    assert d.shift is None and (d.p, d.effect, d.low, d.high) == (a.p, a.effect, a.low, a.high)


def test_resampled_signed_rank_r_matches_expansion():
    # the vectorised ranks of a resample (counts) against ranking the expanded resample
    d = np.array([1.0, -2, 2, 0, 3, -0.5, INF])
    rng = np.random.default_rng(1)
    counts = inference._counts(rng, d.size, 6)
    got = inference._signed_rank_r(d, counts)
    for row, value in zip(counts, got, strict=True):
        sample = np.repeat(d, row.astype(int))
        sample = sample[sample != 0]
        ranks = rankdata(np.abs(sample))
        plus, minus = ranks[sample > 0].sum(), ranks[sample < 0].sum()
        assert value == pytest.approx((plus - minus) / (plus + minus) if plus + minus else 0)


def test_weighted_median_matches_expansion():
    values = np.array([3.0, 1, 2, 5, 4])
    weights = np.array([[1.0, 2, 0, 1, 3], [0, 0, 1, 1, 0], [2, 2, 2, 2, 2]])
    got = inference._weighted_median(values, weights)
    want = [np.median(np.repeat(values, w.astype(int))) for w in weights]
    assert got.tolist() == want


def test_holm_by_hand():
    # sorted 0.01, 0.03, 0.04 of m = 3: 0.03, 0.06, max(0.04, 0.06) = 0.06
    assert holm([0.01, 0.04, None, 0.03]) == pytest.approx([0.03, 0.06, None, 0.06])
    assert holm([0.5, 0.6]) == [1.0, 1.0]
    assert holm([]) == [] and holm([None]) == [None]


def test_bad_input_refused():
    with pytest.raises(ValueError, match="better"):
        compare([1], [2], paired=False, better="smaller")
    with pytest.raises(ValueError, match="size"):
        compare([1, 2], [2], paired=True, better="lower")
    with pytest.raises(ValueError, match="NaN"):
        compare([math.nan], [2], paired=False, better="lower")
    with pytest.raises(ValueError, match="one value"):
        compare([], [2], paired=False, better="lower")
