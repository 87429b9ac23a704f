"""usvtool.report.named_statistic: each named statistic's own test (the permutation test of the
means against scipy's exhaustive permutation test and by hand, Brown-Forsythe against
scipy.stats.levene, the bootstrap of the best run, the rank test of the median), a mean claim
and a best claim getting different p on the same runs, seeding."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import levene, permutation_test

from usvtool.report import inference, named_statistic
from usvtool.report.named_statistic import compare_statistic, permutation_p


def test_paired_permutation_of_means_by_hand():
    # improvements 1, 2, 3 (one zero pair dropped): the 8 sign flips give |sums| 6, 4, 2, 0,
    # 0, 2, 4, 6; two reach 6 -> p = 2/8
    p, exact, draws = permutation_p(np.array([1.0, 2, 3, 5]), np.array([0.0, 0, 0, 5]),
                                    paired=True, seed=0, permutations=10)  # fmt: skip
    assert (p, exact, draws) == (0.25, True, 8)


def test_independent_permutation_of_means_by_hand():
    # [1, 2] against [3, 4]: of the 6 splits, {1,2} and {3,4} give |difference| 2 -> 2/6
    p, exact, draws = permutation_p(np.array([1.0, 2]), np.array([3.0, 4]), paired=False,
                                    seed=0, permutations=10)  # fmt: skip
    assert p == pytest.approx(2 / 6) and exact and draws == 6


def test_permutation_of_means_matches_scipy_exhaustive():
    rng = np.random.default_rng(0)
    x, y = rng.normal(0, 1, 8), rng.normal(0.8, 1, 7)

    def gap(a, b, axis):
        return np.abs(np.mean(a, axis=axis) - np.mean(b, axis=axis))

    want = permutation_test((x, y), gap, permutation_type="independent", n_resamples=np.inf,
                            alternative="greater").pvalue  # fmt: skip
    assert permutation_p(x, y, paired=False, seed=0, permutations=10)[0] == pytest.approx(want)
    u, v = rng.normal(0, 1, 10), rng.normal(0.5, 1, 10)

    def paired_gap(a, b, axis):
        return np.abs(np.mean(a - b, axis=axis))

    want = permutation_test((u, v), paired_gap, permutation_type="samples", n_resamples=np.inf,
                            alternative="greater").pvalue  # fmt: skip
    assert permutation_p(u, v, paired=True, seed=0, permutations=10)[0] == pytest.approx(want)


def test_permutation_sampled_when_large_and_seeded():
    rng = np.random.default_rng(1)
    x, y = rng.normal(0, 1, 30), rng.normal(0.5, 1, 30)
    a = permutation_p(x, y, paired=False, seed=3, permutations=2000)
    b = permutation_p(x, y, paired=False, seed=3, permutations=2000)
    assert a == b and a[1] is False and a[2] == 2000
    assert 1 / 2001 <= a[0] <= 1
    # 2^30 sign patterns: sampled too
    assert permutation_p(x, y, paired=True, seed=3, permutations=500)[1:] == (False, 500)


def test_combinations_are_every_subset():
    rows = named_statistic._combinations(6, 3)
    assert rows.shape == (20, 3)
    assert len({tuple(r) for r in rows}) == 20 and (np.diff(rows, axis=1) > 0).all()


def test_mean_claim_uses_the_means():
    x, y = [1.0, 2, 3, 4, 30], [5.0, 6, 7, 8, 9]
    t = compare_statistic(x, y, statistic="mean", paired=False, better="lower")
    assert t.test == "permutation test of the means" and t.exact
    assert t.difference.estimate == pytest.approx(7 - 8)  # means 8 and 7: the method worse
    # the medians' rank test sees the method's 4 lowest runs: a different p
    m = compare_statistic(x, y, statistic="median", paired=False, better="lower")
    assert m.test == "Mann-Whitney U" and m.p != t.p
    c = inference.compare(x, y, paired=False, better="lower")
    assert m.p == c.p


def test_spread_claim_is_brown_forsythe():
    rng = np.random.default_rng(2)
    x, y = rng.normal(0, 1, 20), rng.normal(0, 3, 20)
    t = compare_statistic(x, y, statistic="std", paired=False, better="lower")
    assert t.test == "Brown-Forsythe"
    assert t.p == pytest.approx(levene(x, y, center="median").pvalue)
    assert t.difference.estimate == pytest.approx(np.std(y, ddof=1) - np.std(x, ddof=1))
    v = compare_statistic(x, y, statistic="variance", paired=True, better="lower")
    assert v.p == t.p and v.difference.statistic == "variance"
    flat = compare_statistic([1.0, 1, 1], [2.0, 2, 2], statistic="std", paired=False,
                             better="lower")  # fmt: skip
    assert flat.p is None


def test_best_run_claim_is_a_bootstrap_of_the_best():
    # the method's minimum 1 below every rival value: every resample's minimum difference is
    # <= 0, most < 0
    x, y = [1.0, 5, 6, 7, 8, 9, 10, 11], [4.0, 5, 6, 7, 8, 9, 10, 11]
    t = compare_statistic(x, y, statistic="min", paired=False, better="lower", seed=1)
    assert t.test == "bootstrap of the best run" and t.draws == 2000
    assert t.difference.estimate == 3.0
    bx = np.random.default_rng(1)
    ix, iy = bx.integers(0, 8, (2000, 8)), bx.integers(0, 8, (2000, 8))
    boot = np.asarray(x)[ix].min(axis=1) - np.asarray(y)[iy].min(axis=1)
    assert t.p == pytest.approx(min(1, 2 * min(np.mean(boot <= 0), np.mean(boot >= 0))))
    # the mean claim on the same runs is another test with another p
    m = compare_statistic(x, y, statistic="mean", paired=False, better="lower", seed=1)
    assert m.test != t.test and m.p != t.p


def test_same_seed_same_bytes():
    rng = np.random.default_rng(3)
    x, y = rng.normal(0, 1, 12), rng.normal(1, 1, 12)
    for statistic in ("mean", "max", "std"):
        a, b = (compare_statistic(x, y, statistic=statistic, paired=True, better="higher",
                                  seed=5) for _ in range(2))  # fmt: skip
        assert a == b


def test_refusals():
    with pytest.raises(ValueError, match="statistic"):
        compare_statistic([1], [2], statistic="mode", paired=False, better="lower")
    with pytest.raises(ValueError, match="finite"):
        compare_statistic([1, np.inf], [2, 3], statistic="mean", paired=False, better="lower")
