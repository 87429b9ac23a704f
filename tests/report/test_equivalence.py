"""usvtool.report.equivalence: TOST by shifted rank tests against scipy and by its properties,
the vectorised rank statistics of the power simulation against scipy, and the n needed:
seeded, growing as the effect shrinks, giving up above the cap."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from scipy.special import ndtr
from scipy.stats import mannwhitneyu, wilcoxon

from usvtool.report import equivalence
from usvtool.report.effects import bootstrap_difference
from usvtool.report.equivalence import sample_size, tost
from usvtool.report.named_statistic import compare_statistic


def test_identical_samples_are_equivalent():
    x = np.random.default_rng(1).normal(40, 5, 20)
    for paired in (True, False):
        e = tost(x, x, paired=paired, better="higher", margin=2.0)
        assert e.equivalent and e.p < 0.05
        assert -2 < e.interval.low <= e.interval.high < 2
        assert e.interval.confidence == pytest.approx(0.9)


def test_shifted_samples_are_not_equivalent():
    x = np.random.default_rng(2).normal(40, 1, 20)
    for paired in (True, False):
        e = tost(x, x + 3, paired=paired, better="higher", margin=0.5)
        assert not e.equivalent and e.p > 0.5
        assert e.interval.high < -0.5  # the method 3 lower, higher better: an improvement of -3


def test_tost_one_sided_p_match_scipy():
    rng = np.random.default_rng(3)
    x, y = rng.normal(10, 1, 15), rng.normal(10.2, 1, 15)
    m = 0.7
    e = tost(x, y, paired=True, better="higher", margin=m)
    d = x - y
    assert e.p_lower == pytest.approx(wilcoxon(d + m, alternative="greater", method="exact").pvalue)
    assert e.p_upper == pytest.approx(wilcoxon(d - m, alternative="less", method="exact").pvalue)
    assert e.p == max(e.p_lower, e.p_upper) and e.exact
    f = tost(x, y, paired=False, better="lower", margin=m)
    a, b = -x, -y  # lower better: the oriented values
    want_low = mannwhitneyu(a + m, b, alternative="greater", method="exact").pvalue
    want_up = mannwhitneyu(a - m, b, alternative="less", method="exact").pvalue
    assert (f.p_lower, f.p_upper) == pytest.approx((want_low, want_up))


def test_tost_agrees_with_the_90_percent_interval():
    # where the HL interval is well inside the margin, equivalent; well across it, not
    rng = np.random.default_rng(4)
    for shift, margin in ((0.0, 1.0), (0.2, 1.0), (0.9, 0.5), (0.0, 0.05)):
        x = rng.normal(0, 0.5, 30)
        y = x + shift + rng.normal(0, 0.1, 30)
        e = tost(x, y, paired=True, better="lower", margin=margin)
        inside = -margin < e.interval.low and e.interval.high < margin
        assert e.equivalent == inside


def test_margin_must_be_positive():
    with pytest.raises(ValueError, match="margin"):
        tost([1, 2], [1, 2], paired=True, better="lower", margin=0)


def test_vectorised_rank_z_matches_scipy():
    rng = np.random.default_rng(5)
    d = np.round(rng.normal(0.3, 1, (4, 25)), 1)  # ties and zeros
    z = equivalence._signed_rank_z(d)
    for row, value in zip(d, z, strict=True):
        want = wilcoxon(row, method="approx", correction=True).pvalue
        assert 2 * ndtr(-abs(value)) == pytest.approx(want)
    x, y = np.round(rng.normal(0, 1, (3, 12)), 1), np.round(rng.normal(0.5, 1, (3, 12)), 1)
    z = equivalence._rank_sum_z(x, y)
    for rx, ry, value in zip(x, y, z, strict=True):
        want = mannwhitneyu(rx, ry, method="asymptotic").pvalue
        assert 2 * ndtr(-abs(value)) == pytest.approx(want)


@pytest.mark.parametrize("seed", range(4))
def test_ranks_by_counting_are_the_sorted_ranks_bit_for_bit(seed):
    """The simulation's counted ranks (equivalence._Coded) give the floats of the sorted
    ones on the drawn values: ties, zero differences (paired), one value repeated, one side
    all below the other."""
    rng = np.random.default_rng(40 + seed)
    for paired in (True, False):
        for spread in (0.0, 0.1, 1.0, 100.0):
            a = np.round(rng.normal(0.3, 1, int(rng.integers(1, 30))) * spread, 1)
            b = np.round(rng.normal(0, 1, int(rng.integers(1, 30))) * spread, 1) - 5 * (seed == 3)
            n = int(rng.integers(1, 40))
            if paired:
                d = np.concatenate([a, [0.0, 0.0]]) if seed % 2 else a
                drawn = rng.integers(0, d.size, (7, n))
                got = equivalence._Coded(d).signed_rank_z(drawn)
                want = equivalence._signed_rank_z(d[drawn])
            else:
                ia, ib = rng.integers(0, a.size, (7, n)), rng.integers(0, b.size, (7, n + 3))
                got = equivalence._Coded(a, b).rank_sum_z(ia, ib)
                want = equivalence._rank_sum_z(a[ia], b[ib])
            assert got.tobytes() == want.tobytes(), (paired, spread)


def test_sample_size_is_seeded_and_reaches_the_power():
    rng = np.random.default_rng(6)
    x, y = rng.normal(0, 1, 15), rng.normal(0.6, 1, 15)
    a = sample_size(x, y, paired=False, better="lower", simulations=200, cap=2000)
    b = sample_size(x, y, paired=False, better="lower", simulations=200, cap=2000)
    assert a == b and a.n is not None and a.power >= 0.8
    assert a.test == "Mann-Whitney U" and a.target == 0.8
    # a smaller observed effect needs more runs
    c = sample_size(x, y - 0.3, paired=False, better="lower", simulations=200, cap=2000)
    assert c.n is not None and c.n > a.n


def test_sample_size_gives_up_above_the_cap():
    rng = np.random.default_rng(7)
    d = rng.normal(0.02, 1, 20)
    s = sample_size(d, np.zeros(20), paired=True, better="higher", simulations=100, cap=64)
    assert s.n is None and s.power < 0.8 and "64" in s.reason
    z = sample_size([1.0, 2, 3], [1.0, 2, 3], paired=True, better="higher", cap=64)
    assert z.n is None and "no observed effect" in z.reason


def test_sample_size_small_when_already_decisive():
    x = np.arange(30.0)
    s = sample_size(x, x + 5, paired=True, better="lower", simulations=100, cap=1000)
    assert s.n is not None and s.n <= 30 and s.test == "Wilcoxon signed-rank"


def test_same_seed_same_bytes():
    # every seeded primitive, twice with one seed: the same pickled bytes
    rng = np.random.default_rng(8)
    x, y = rng.normal(0, 1, 14), rng.normal(0.5, 1, 14)
    runs = [
        lambda: sample_size(x, y, paired=True, better="lower", simulations=50, cap=200, seed=2),
        lambda: bootstrap_difference(
            x, y, statistic="max", paired=False, better="lower", seed=2, interval="bca"
        ),
        lambda: compare_statistic(
            x, y, statistic="mean", paired=False, better="lower", seed=2, permutations=300
        ),
        lambda: tost(x, y, paired=False, better="lower", margin=0.3),
    ]
    for run in runs:
        assert pickle.dumps(run()) == pickle.dumps(run())


def test_noether_by_hand_and_beside_the_simulation():
    from scipy.special import ndtri

    from usvtool.report.equivalence import noether

    z = ndtri(0.975) + ndtri(0.8)  # 2.8016
    # independent: every a above every b, q = 1: N = z^2 / (3 / 4) for both groups, half each
    a, b = np.array([1.0, 2.0]), np.array([0.0, 0.0])
    assert noether(a, b, paired=False, power=0.8, alpha=0.05) == pytest.approx(z * z / 0.75 / 2)
    # paired: d = 1, 1, -1: Walsh sums over i < j are 2, 0, 0: q = (1 + 0.5 * 2) / 3 = 2 / 3
    d = np.array([1.0, 1.0, -1.0])
    got = noether(d, np.zeros(3), paired=True, power=0.8, alpha=0.05)
    assert got == pytest.approx(z * z / (3 * (2 / 3 - 0.5) ** 2))
    assert noether(np.array([1.0, -1.0]), np.zeros(2), paired=True, power=0.8,
                   alpha=0.05) == float("inf")  # fmt: skip
    # the search starts there and the simulation lands near it (a shift of 0.3 sd)
    rng = np.random.default_rng(3)
    x, y = rng.normal(0.3, 1, 40), rng.normal(0, 1, 40)
    s = sample_size(x, y, paired=False, better="higher")
    assert 0.7 < s.n / noether(x, y, paired=False, power=0.8, alpha=0.05) < 1.3
