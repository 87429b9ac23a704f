"""usvtool.report.effects: the Hodges-Lehmann shift and its distribution-free interval by hand,
the bootstrap of a statistic's difference and the relative change: sign, pairing, seeding."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import bootstrap

from usvtool.report import inference
from usvtool.report.effects import bootstrap_difference, hodges_lehmann


def test_hodges_lehmann_independent_by_hand():
    # higher better: cross differences of [1, 2, 3] - [0] are 1, 2, 3 -> shift 2; 3 + 1 runs
    # reach no 95 % interval (the whole line)
    s = hodges_lehmann([1, 2, 3], [0], paired=False, better="higher")
    assert s.estimate == 2.0 and (s.low, s.high) == (-math.inf, math.inf)
    assert s.coverage == 1.0 and s.n == (3, 1)
    # lower better: the sign flips (the improvement rival - method)
    t = hodges_lehmann([1, 2, 3], [0], paired=False, better="lower")
    assert t.estimate == -2.0


def test_hodges_lehmann_independent_interval_by_hand():
    # 5 + 5, k = 3 (P(U <= 2) = 4/252): the 3rd smallest and 3rd largest of the 25 cross
    # differences; coverage 1 - 8/252
    a, b = [11.0, 13, 14, 17, 20], [1.0, 4, 6, 8, 9]
    diffs = sorted(x - y for x in a for y in b)
    s = hodges_lehmann(a, b, paired=False, better="higher")
    assert s.estimate == diffs[12]
    assert (s.low, s.high) == (diffs[2], diffs[-3])
    assert s.coverage == pytest.approx(1 - 8 / 252) and s.exact


def test_hodges_lehmann_paired_by_hand():
    # improvements 1..8 (higher better): Walsh averages' median 4.5; n = 8 has k = 4:
    # the 4th smallest Walsh average is 2 (1, 1.5, 2, 2), the 4th largest 7
    method = [1.0, 2, 3, 4, 5, 6, 7, 8]
    s = hodges_lehmann(method, [0.0] * 8, paired=True, better="higher")
    assert s.estimate == 4.5 and (s.low, s.high) == (2.0, 7.0)
    assert s.coverage == pytest.approx(1 - 10 / 256)


def test_hodges_lehmann_matches_inference_shift():
    rng = np.random.default_rng(2)
    x, y = rng.normal(10, 2, 12), rng.normal(12, 2, 12)
    for paired in (True, False):
        c = inference.compare(x, y, paired=paired, better="lower", resamples=10)
        s = hodges_lehmann(x, y, paired=paired, better="lower")
        assert s.estimate == pytest.approx(c.shift)
        assert s.low <= s.estimate <= s.high


def test_hodges_lehmann_coverage_by_simulation():
    # a shift of 1: the 95 % interval covers it in about 95 % of 400 samples (at least 93 %)
    rng = np.random.default_rng(11)
    hits = sum(
        (
            s := hodges_lehmann(
                rng.normal(1, 1, 10), rng.normal(0, 1, 10), paired=False, better="higher"
            )
        ).low
        <= 1
        <= s.high  # fmt: skip
        for _ in range(400)
    )
    assert hits / 400 >= 0.93


def test_hodges_lehmann_refuses_failures():
    with pytest.raises(ValueError, match="finite"):
        hodges_lehmann([1, math.inf], [2, 3], paired=False, better="lower")
    with pytest.raises(ValueError, match="better"):
        hodges_lehmann([1], [2], paired=False, better="smaller")


def test_bootstrap_difference_estimate_and_relative_by_hand():
    # lower better: means 2 and 4 -> improvement 2, relative 2 / 4
    d = bootstrap_difference([1, 2, 3], [3, 4, 5], statistic="mean", paired=False,
                             better="lower")  # fmt: skip
    assert d.estimate == 2.0 and d.relative == 0.5
    assert (d.method_value, d.rival_value) == (2.0, 4.0)
    assert d.low <= d.estimate <= d.high and d.relative_low <= 0.5 <= d.relative_high
    # higher better: the same data, the sign flips
    e = bootstrap_difference([1, 2, 3], [3, 4, 5], statistic="mean", paired=False,
                             better="higher")  # fmt: skip
    assert e.estimate == -2.0 and e.relative == -0.5


@pytest.mark.parametrize("statistic", ["median", "mean", "min", "max", "std", "variance"])
def test_bootstrap_difference_resamples_by_expansion(statistic):
    # the vectorised resamples against the same index draws taken one by one
    rng = np.random.default_rng(4)
    x, y = rng.normal(5, 1, 9), rng.normal(6, 2, 7)
    d = bootstrap_difference(x, y, statistic=statistic, paired=False, better="lower", seed=9,
                             resamples=300)  # fmt: skip
    draws = np.random.default_rng(9)
    ix, iy = draws.integers(0, 9, (300, 9)), draws.integers(0, 7, (300, 7))
    f = {
        "median": np.median,
        "mean": np.mean,
        "min": np.min,
        "max": np.max,
        "std": lambda v: np.std(v, ddof=1),
        "variance": lambda v: np.var(v, ddof=1),
    }[statistic]
    boot = [f(y[j]) - f(x[i]) for i, j in zip(ix, iy, strict=True)]
    assert (d.low, d.high) == pytest.approx(tuple(np.percentile(boot, [2.5, 97.5])))
    assert d.estimate == pytest.approx(f(y) - f(x))


def test_bootstrap_paired_resamples_pairs_together():
    # every pair improves by exactly 1: each paired resample's mean improvement is 1
    rival = np.array([10.0, 50, 20, 80, 30, 70])
    d = bootstrap_difference(rival - 1, rival, statistic="mean", paired=True, better="lower")
    assert (d.estimate, d.low, d.high) == pytest.approx((1, 1, 1))
    u = bootstrap_difference(rival - 1, rival, statistic="mean", paired=False, better="lower")
    assert u.high - u.low > 10


def test_bootstrap_is_seeded():
    rng = np.random.default_rng(0)
    x, y = rng.normal(0, 1, 15), rng.normal(1, 1, 15)
    a, b, c = (bootstrap_difference(x, y, statistic="median", paired=True, better="lower",
                                    seed=s) for s in (3, 3, 4))  # fmt: skip
    assert a == b and (a.low, a.high) != (c.low, c.high)


def test_relative_none_when_rival_zero():
    d = bootstrap_difference([1, 2], [0, 0], statistic="mean", paired=False, better="lower")
    assert d.relative is None and d.relative_low is None


def test_bootstrap_refusals():
    with pytest.raises(ValueError, match="statistic"):
        bootstrap_difference([1], [2], statistic="mode", paired=False, better="lower")
    with pytest.raises(ValueError, match="two values"):
        bootstrap_difference([1], [2, 3], statistic="std", paired=False, better="lower")
    with pytest.raises(ValueError, match="size"):
        bootstrap_difference([1, 2], [2], statistic="mean", paired=True, better="lower")


@pytest.mark.parametrize("interval", ["percentile", "bca"])
@pytest.mark.parametrize("statistic", ["mean", "median", "std"])
def test_bootstrap_intervals_match_scipy(interval, statistic):
    # the same generator draws the same resamples as scipy.stats.bootstrap (method's first),
    # so the percentile and BCa intervals are scipy's; higher better: the raw difference
    rng = np.random.default_rng(1)
    x, y = rng.gamma(2, 1, 15), rng.gamma(2, 1.5, 12)
    f = {"mean": np.mean, "median": np.median, "std": lambda a, axis: np.std(a, ddof=1, axis=axis)}

    def gap(a, b, axis=-1):
        return f[statistic](a, axis=axis) - f[statistic](b, axis=axis)

    method = "BCa" if interval == "bca" else "percentile"
    for paired, xs in ((False, x), (True, x[:12])):
        want = bootstrap((xs, y), gap, n_resamples=2000, method=method, paired=paired,
                         rng=np.random.default_rng(5)).confidence_interval  # fmt: skip
        got = bootstrap_difference(xs, y, statistic=statistic, paired=paired, better="higher",
                                   seed=5, interval=interval)  # fmt: skip
        assert (got.low, got.high) == pytest.approx((want.low, want.high), rel=1e-9)
        assert got.interval == interval
        # lower better: the improvement is the negated difference, its interval turned round
        low = bootstrap_difference(xs, y, statistic=statistic, paired=paired, better="lower",
                                   seed=5, interval=interval)  # fmt: skip
        assert (low.low, low.high) == pytest.approx((-got.high, -got.low), rel=1e-9)


def test_bca_falls_back_to_percentile_when_undefined():
    # two values a side: the jackknife's standard deviation of one value is undefined; one
    # value: its mean of none
    d = bootstrap_difference([1.0, 2], [3.0, 5], statistic="std", paired=False, better="lower",
                             interval="bca")  # fmt: skip
    p = bootstrap_difference([1.0, 2], [3.0, 5], statistic="std", paired=False, better="lower")
    assert d.interval == "percentile" and (d.low, d.high) == (p.low, p.high)
    one = bootstrap_difference([1.0], [3.0, 5], statistic="mean", paired=False, better="lower",
                               interval="bca")  # fmt: skip
    assert one.interval == "percentile"
    with pytest.raises(ValueError, match="interval"):
        bootstrap_difference([1.0], [2.0], statistic="mean", paired=False, better="lower",
                             interval="basic")  # fmt: skip
