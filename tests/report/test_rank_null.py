"""usvtool.report.rank_null and usvtool.report.effective_n: the exact and normal rank
distributions against scipy and against enumerations written here, the interval depths against
Hollander and Wolfe's tables, the effective n and the exact rule."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.stats import mannwhitneyu, rankdata, wilcoxon

from usvtool.report import effective_n, rank_null
from usvtool.report.effective_n import EXACT_PAIRS, EXACT_RUNS


def enumerate_signed_rank(d, alternative):
    """One-sided p by flipping every sign of the nonzero differences' (average) ranks."""
    d = [x for x in d if x != 0]
    ranks = rankdata(np.abs(d))
    observed = sum(r for r, x in zip(ranks, d, strict=True) if x > 0)
    sums = [sum(r for r, s in zip(ranks, signs, strict=True) if s)
            for signs in itertools.product((0, 1), repeat=len(d))]  # fmt: skip
    if alternative == "greater":
        return sum(s >= observed - 1e-9 for s in sums) / len(sums)
    return sum(s <= observed + 1e-9 for s in sums) / len(sums)


def enumerate_rank_sum(x, y, alternative):
    """One-sided p by every split of the pooled (average) ranks."""
    ranks = rankdata(list(x) + list(y))
    observed = ranks[: len(x)].sum()
    sums = [ranks[list(c)].sum() for c in itertools.combinations(range(len(ranks)), len(x))]
    if alternative == "greater":
        return sum(s >= observed - 1e-9 for s in sums) / len(sums)
    return sum(s <= observed + 1e-9 for s in sums) / len(sums)


def test_signed_rank_by_hand():
    # d = 1, 2, -3, 4, 5: T+ = 12; sign patterns with T+ >= 12 are those with T- <= 3:
    # {}, {1}, {2}, {3}, {1,2} -> 5 / 32; T+ <= 12 fails only when T- <= 2: {}, {1}, {2}
    d = [1, 2, -3, 4, 5]
    assert rank_null.signed_rank_p(d, "greater", exact=True) == pytest.approx(5 / 32)
    assert rank_null.signed_rank_p(d, "less", exact=True) == pytest.approx(29 / 32)


@pytest.mark.parametrize("alternative", ["greater", "less"])
def test_untied_exact_and_normal_agree_with_scipy(alternative):
    rng = np.random.default_rng(5)
    d = rng.normal(0.4, 1, 18)
    x, y = rng.normal(0.5, 1, 11), rng.normal(0, 1, 9)
    assert rank_null.signed_rank_p(d, alternative, exact=True) == pytest.approx(
        wilcoxon(d, alternative=alternative, method="exact").pvalue, rel=1e-9
    )
    assert rank_null.signed_rank_p(d, alternative, exact=False) == pytest.approx(
        wilcoxon(d, alternative=alternative, method="approx", correction=True).pvalue
    )
    assert rank_null.rank_sum_p(x, y, alternative, exact=True) == pytest.approx(
        mannwhitneyu(x, y, alternative=alternative, method="exact").pvalue, rel=1e-9
    )
    assert rank_null.rank_sum_p(x, y, alternative, exact=False) == pytest.approx(
        mannwhitneyu(x, y, alternative=alternative, method="asymptotic").pvalue
    )


@pytest.mark.parametrize("alternative", ["greater", "less"])
def test_tied_exact_against_enumeration(alternative):
    d = [1, 2, 0, 2, -1, 2, 3, -2]  # a zero (dropped) and tied |d|
    assert rank_null.signed_rank_p(d, alternative, exact=True) == pytest.approx(
        enumerate_signed_rank(d, alternative)
    )
    x, y = [1, 2, 2, 3, 5], [2, 3, 3, 4, 6, 6]
    assert rank_null.rank_sum_p(x, y, alternative, exact=True) == pytest.approx(
        enumerate_rank_sum(x, y, alternative)
    )
    # the larger side first: its sums mirror the smaller side's
    assert rank_null.rank_sum_p(y, x, alternative, exact=True) == pytest.approx(
        enumerate_rank_sum(y, x, alternative)
    )


def test_tied_normal_matches_scipy():
    # scipy's tie-corrected normal approximation, with its continuity correction
    x, y = [1, 2, 2, 3, 3, 3, 4, 5, 6], [3, 4, 4, 5, 6, 6, 7, 8, 8]
    assert rank_null.rank_sum_p(x, y, "less", exact=False) == pytest.approx(
        mannwhitneyu(x, y, alternative="less", method="asymptotic").pvalue
    )
    d = [1, 2, 2, 3, 3, -1, 4, 4, 4, -2, 5, 6]
    assert rank_null.signed_rank_p(d, "greater", exact=False) == pytest.approx(
        wilcoxon(d, alternative="greater", method="approx", correction=True).pvalue
    )


def test_no_evidence_is_p_one():
    assert rank_null.signed_rank_p([0, 0, 0], "greater", exact=True) == 1.0
    assert rank_null.rank_sum_p([2, 2], [2, 2, 2], "less", exact=True) == 1.0
    with pytest.raises(ValueError, match="alternative"):
        rank_null.signed_rank_p([1], "two-sided", exact=True)


def test_depths_match_hollander_wolfe_tables():
    # signed rank: n = 6 reaches 96.9 % with k = 1; n = 5 reaches no 95 % interval; n = 8:
    # P(T+ <= 3) = 5/256 <= 0.025 < P(T+ <= 4) = 7/256 -> k = 4, coverage 1 - 10/256
    assert rank_null.signed_rank_depth(5, 0.025, exact=True) == 0
    assert rank_null.signed_rank_depth(6, 0.025, exact=True) == 1
    assert rank_null.depth_coverage_signed_rank(6, 1) == pytest.approx(1 - 2 / 64)
    assert rank_null.signed_rank_depth(8, 0.025, exact=True) == 4
    assert rank_null.depth_coverage_signed_rank(8, 4) == pytest.approx(1 - 10 / 256)
    # rank sum, 5 + 5: P(U <= 2) = 4/252, P(U <= 3) = 7/252 -> k = 3, coverage 0.968
    assert rank_null.rank_sum_depth(5, 5, 0.025, exact=True) == 3
    assert rank_null.depth_coverage_rank_sum(5, 5, 3) == pytest.approx(1 - 8 / 252)
    assert rank_null.rank_sum_depth(3, 3, 0.025, exact=True) == 0


def test_normal_depth_close_to_exact():
    for n in (20, 40):
        exact, normal = (rank_null.signed_rank_depth(n, 0.025, exact=e) for e in (True, False))
        assert abs(exact - normal) <= 1
    exact, normal = (rank_null.rank_sum_depth(20, 25, 0.025, exact=e) for e in (True, False))
    assert abs(exact - normal) <= 1
    assert rank_null.signed_rank_depth(30, 0.025, exact=False) == math.floor(
        30 * 31 / 4 - 1.959963984540054 * math.sqrt(30 * 31 * 61 / 24) + 0.5
    )


def test_effective_n_paired_drops_zero_differences():
    method = [1.0, 2, 3, 4, math.inf, 6]
    rival = [1.0, 2, 5, 3, math.inf, 4]  # zeros: pairs 1, 2 and the two failures
    e = effective_n.effective_n(method, rival, paired=True)
    assert (e.informative, e.zeros, e.sizes) == (3, 3, (6, 6))
    assert e.tied and e.exact  # |d| = 2, 1, 2
    f = effective_n.effective_n([1, 2, 3], [4, 5, 6], paired=False)
    assert (f.informative, f.zeros, f.tied, f.sizes) == (6, 0, False, (3, 3))


def test_exact_rule_bounds():
    assert effective_n.exact(True, EXACT_PAIRS) and not effective_n.exact(True, EXACT_PAIRS + 1)
    assert effective_n.exact(False, EXACT_RUNS) and not effective_n.exact(False, EXACT_RUNS + 1)
    many = effective_n.effective_n(np.arange(60.0), np.arange(60.0) + 0.5, paired=True)
    assert many.informative == 60 and not many.exact
    with pytest.raises(ValueError, match="size"):
        effective_n.effective_n([1, 2], [1], paired=True)
