"""The test of the statistic a claim names (docs/statistics.md, "The statistic a claim names"):
a claim of a lower mean is tested on means, of a lower variance or standard deviation on
spreads, of a better best run on the best runs, so that two claims naming different statistics
never share one test.

Each :class:`StatisticTest` says which test it used, its two-sided p, and the difference of the
named statistic with its bootstrap interval and relative change
(:func:`usvtool.report.effects.bootstrap_difference`: > 0 when the method is better in the
claim's direction). The values must be finite (measured values; the failures are compared
apart, :mod:`usvtool.report.rates`).

- ``median``: the rank test, Wilcoxon signed-rank (paired) or Mann-Whitney U, two-sided,
  exact (ties included) or normal by the effective-n rule (:func:`rank_p`).
- ``mean``: the **permutation test of the means** (Fisher 1935, The Design of Experiments,
  chapter III, Darwin's paired plants; Good 2005, Permutation, Parametric and Bootstrap Tests
  of Hypotheses, 3rd ed., chapter 3). Paired: every sign of the nonzero improvements d
  flipped, the statistic |sum of the signed d|; independent: every split of the pooled values
  into groups of the two sizes, the statistic |mean(a) - mean(b)|. p = the share of
  rearrangements whose statistic is at least the observed one (within 1e-9 relative: ties of
  floating sums). **Exhaustive** (exact) when there are at most
  :data:`EXACT_REARRANGEMENTS` of them (17 informative pairs; 10 + 10 runs), each a row of
  one matrix product; otherwise
  ``permutations`` random rearrangements from ``numpy.random.default_rng(seed)``, p = (1 +
  hits) / (1 + permutations) (Phipson and Smyth 2010, Stat. Appl. Genet. Mol. Biol. 9, 39).
- ``variance``, ``std``: the **Brown-Forsythe** test (Brown and Forsythe 1974, J. Am. Stat.
  Assoc. 69, 364-367: Levene's test on the absolute deviations from each group's median,
  ``scipy.stats.levene(center="median")``); paired runs are tested as two independent groups
  (the test has no paired form, and its p assumes independence: say so beside a paired
  comparison). p None when every deviation is zero.
- ``min``, ``max`` (a best run): the **bootstrap of the best run's difference** (pairs
  resampled together when paired): p = twice the smaller share of resamples whose difference
  is <= 0 or >= 0, capped at 1 (the smallest level at which the equal-tailed percentile
  interval excludes 0; Efron and Tibshirani 1993, An Introduction to the Bootstrap, chapters
  13 and 16). The bootstrap of an extreme is coarse (a resample's minimum is one of the
  observed values): read its p with the interval.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.stats import levene

from usvtool.report import effective_n, inference, rank_null
from usvtool.report.effects import Difference, bootstrap_difference, oriented, resampled

PERMUTATION, BROWN_FORSYTHE = "permutation test of the means", "Brown-Forsythe"
BOOTSTRAP_BEST = "bootstrap of the best run"
#: The most rearrangements enumerated exhaustively (the permutation test of the means).
EXACT_REARRANGEMENTS = 200_000
#: The statistics, each with its test's name.
TESTS = {"median": None, "mean": PERMUTATION, "variance": BROWN_FORSYTHE,
         "std": BROWN_FORSYTHE, "min": BOOTSTRAP_BEST, "max": BOOTSTRAP_BEST}  # fmt: skip


@dataclass(frozen=True)
class StatisticTest:
    """The named ``statistic``'s test (its name in ``test``), its two-sided p (None: no
    evidence), whether it was exact (exhaustive permutations; None where the notion does not
    apply), the rearrangements or resamples it used, and the statistic's difference."""

    statistic: str
    test: str
    p: float | None
    exact: bool | None
    draws: int
    difference: Difference


def compare_statistic(method: Sequence[float], rival: Sequence[float], *, statistic: str,
                      paired: bool, better: str, seed: int = 0, resamples: int = 2000,
                      permutations: int = 20_000) -> StatisticTest:  # fmt: skip
    """Test ``method`` against ``rival`` on ``statistic`` (module docstring)."""
    if statistic not in TESTS:
        raise ValueError(f"statistic must be one of {tuple(TESTS)}, not {statistic!r}")
    a, b = oriented(method, rival, better, paired)
    difference = bootstrap_difference(method, rival, statistic=statistic, paired=paired,
                                      better=better, seed=seed, resamples=resamples)  # fmt: skip
    if statistic == "median":
        p, exact = rank_p(a, b, paired=paired)
        test = inference.WILCOXON if paired else inference.MANN_WHITNEY
        return StatisticTest(statistic, test, p, exact, 0, difference)
    if statistic == "mean":
        p, exact, draws = permutation_p(a, b, paired=paired, seed=seed,
                                        permutations=permutations)  # fmt: skip
        return StatisticTest(statistic, PERMUTATION, p, exact, draws, difference)
    if statistic in ("variance", "std"):
        flat = not (np.any(a != np.median(a)) or np.any(b != np.median(b)))
        p = None if flat else float(levene(a, b, center="median").pvalue)
        return StatisticTest(statistic, BROWN_FORSYTHE, p, None, 0, difference)
    x, y = np.asarray(method, float), np.asarray(rival, float)
    bx, by = resampled(x, y, statistic, paired=paired, seed=seed, resamples=resamples)
    boot = bx - by
    p = min(1.0, 2 * min(np.mean(boot <= 0), np.mean(boot >= 0)))
    return StatisticTest(statistic, BOOTSTRAP_BEST, float(p), None, resamples, difference)


def rank_p(a: np.ndarray, b: np.ndarray, *, paired: bool) -> tuple[float | None, bool]:
    """The two-sided p of the rank test of the oriented values ``a`` against ``b`` (Wilcoxon
    signed-rank on a - b when paired, zeros dropped; Mann-Whitney U otherwise): twice the
    smaller one-sided p of :mod:`usvtool.report.rank_null`, capped at 1, exact or normal by
    :func:`usvtool.report.effective_n.exact` (so a handful of informative pairs gets the exact
    distribution, ties included). None when nothing is informative (every pair a zero
    difference, every value tied). Also whether it was exact."""
    if paired:
        d = a - b
        informative = int(np.count_nonzero(d))
        exact = effective_n.exact(True, informative)
        if informative == 0:
            return None, exact
        tails = [rank_null.signed_rank_p(d, t, exact=exact) for t in rank_null.ALTERNATIVES]
    else:
        exact = effective_n.exact(False, a.size + b.size)
        if np.all(np.concatenate([a, b]) == a[0]):
            return None, exact
        tails = [rank_null.rank_sum_p(a, b, t, exact=exact) for t in rank_null.ALTERNATIVES]
    return min(1.0, 2 * min(tails)), exact


def permutation_p(a: np.ndarray, b: np.ndarray, *, paired: bool, seed: int,
                  permutations: int) -> tuple[float | None, bool, int]:  # fmt: skip
    """The two-sided permutation p of the means (module docstring), whether exhaustive, and
    the rearrangements used; p None when no rearrangement can differ (every paired improvement
    zero, or every value equal)."""
    if paired:
        d = (a - b)[a != b]
        if d.size == 0:
            return None, True, 0
        observed = abs(d.sum())
        if 2**d.size <= EXACT_REARRANGEMENTS:
            codes = np.arange(2**d.size)[:, None] >> np.arange(d.size)
            signs = 1.0 - 2.0 * (codes & 1)
            exact = True
        else:
            signs = np.random.default_rng(seed).choice([-1.0, 1.0], size=(permutations, d.size))
            exact = False
        sums = np.abs(signs @ d)
    else:
        pooled = np.concatenate([a, b])
        if np.all(pooled == pooled[0]):
            return None, True, 0
        m, total = a.size, pooled.sum()
        observed = abs(a.mean() - b.mean())
        small = min(a.size, b.size)
        if math.comb(pooled.size, small) <= EXACT_REARRANGEMENTS:
            chosen = pooled[_combinations(pooled.size, small)].sum(axis=1)
            first = chosen if small == m else total - chosen
            exact = True
        else:
            rng = np.random.default_rng(seed)
            shuffled = rng.permuted(np.broadcast_to(pooled, (permutations, pooled.size)), axis=1)
            first = shuffled[:, :m].sum(axis=1)
            exact = False
        sums = np.abs(first / m - (total - first) / b.size)
    hits = int(np.count_nonzero(sums >= observed * (1 - 1e-9) - 1e-12))
    if exact:
        return hits / sums.size, True, int(sums.size)
    return (1 + hits) / (1 + permutations), False, permutations


def _combinations(n: int, k: int) -> np.ndarray:
    """Every k-subset of range(n) as the rows of a (C(n, k), k) array, in lexicographic order;
    built one column at a time (each row extended by every larger index)."""
    rows = np.arange(n)[:, None][: n - k + 1] if k else np.zeros((1, 0), int)
    for column in range(1, k):
        last = rows[:, -1]
        extend = n - k + column - last  # the indices last + 1 .. n - k + column
        repeated = np.repeat(rows, extend, axis=0)
        starts = np.repeat(last + 1, extend)
        offsets = np.arange(extend.sum()) - np.repeat(np.cumsum(extend) - extend, extend)
        rows = np.hstack([repeated, (starts + offsets)[:, None]])
    return rows
