"""The null distributions of the two rank statistics, exact or normal, and their one-sided p
(docs/statistics.md, "Effective n, exact or normal").

- The **signed-rank** statistic T+ of paired differences (Wilcoxon 1945): the sum of the
  ranks of |d| (average ranks for ties, zeros dropped first) carried by positive d. Under the
  null each rank's sign is + or - with probability 1/2 independently, so T+ is the sum of a
  random subset of the ranks.
- The **rank-sum** statistic R of independent samples (Wilcoxon 1945; Mann and Whitney 1947
  use U = R - m(m + 1) / 2): the sum of the pooled ranks (average ranks for ties) of the m
  values of the first sample. Under the null every m-subset of the N = m + n pooled ranks is
  equally likely.

**Exact**: the permutation distribution of the observed ranks, ties included (the conditional
distribution given the tie pattern, Lehmann 1975, Nonparametrics, chapters 1 and 3),
computed by the generating function prod_i (1 + x^(2 r_i)) / 2 (signed rank) and the
coefficient of y^m in prod_i (1 + y x^(2 r_i)) / C(N, m) (rank sum): the ranks are doubled
so that average ranks are integers (then divided by their common factor: 2 without ties).
One loop over the N ranks, each step a shift-and-add of an array (at most (m + 1) x (N (N +
1) + 1) numbers); no enumeration of the 2^n or C(N, m) arrangements. Without ties these are
the distributions scipy.stats.wilcoxon and mannwhitneyu call exact.

**Normal**: the same statistic standardised by its permutation mean and variance (Lehmann
1975, chapters 1 and 3, written out here): E T+ = sum r / 2, Var T+ = sum r^2 / 4;
E R = m (N + 1) / 2, Var R = m n / (N (N - 1)) sum (r - (N + 1) / 2)^2 (both equal the
textbook tie-corrected variances), with the continuity correction of half a rank.

Which of the two a comparison uses is :func:`usvtool.report.effective_n.exact`'s rule.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy.special import ndtr, ndtri
from scipy.stats import rankdata

ALTERNATIVES = ("greater", "less")


def signed_rank_p(d, alternative: str, *, exact: bool) -> float:
    """One-sided p of the signed-rank test of the differences ``d`` (zeros dropped):
    ``greater`` is P(T+ >= t) (the differences tend above 0), ``less`` P(T+ <= t); 1 when
    every difference is zero (no evidence)."""
    _check(alternative)
    d = np.asarray(d, float)
    d = d[d != 0]
    if d.size == 0:
        return 1.0
    doubled = _doubled_ranks(np.abs(d))
    t = int(doubled[d > 0].sum())
    if exact:
        g = int(np.gcd.reduce(doubled))  # 2 without ties: the sums on half the grid
        return _tail(_subset_sums(doubled // g), t // g, alternative)
    mean, var = doubled.sum() / 2, (doubled**2).sum() / 4
    return _normal_tail(t, mean, var, alternative)


def rank_sum_p(x, y, alternative: str, *, exact: bool) -> float:
    """One-sided p of the rank-sum (Mann-Whitney) test of ``x`` against ``y``: ``greater`` is
    P(R >= r) (x tends above y), ``less`` P(R <= r); 1 when every value is tied."""
    _check(alternative)
    x, y = np.asarray(x, float), np.asarray(y, float)
    doubled = _doubled_ranks(np.concatenate([x, y]))
    if np.all(doubled == doubled[0]):
        return 1.0
    r, m, n = int(doubled[: x.size].sum()), x.size, y.size
    if exact:
        g = int(np.gcd.reduce(doubled))
        return _tail(_subset_sums_of_size(doubled // g, m), r // g, alternative)
    total = m + n
    mean = m * doubled.sum() / total
    var = m * n / (total * (total - 1)) * ((doubled - doubled.mean()) ** 2).sum()
    return _normal_tail(r, mean, var, alternative)


@lru_cache(maxsize=256)
def signed_rank_depth(n: int, tail: float, *, exact: bool) -> int:
    """The depth k of the distribution-free interval from the signed-rank test of n untied
    differences: the largest k with P(T+ <= k - 1) <= ``tail`` (0 when no k qualifies), so that
    the k-th smallest and k-th largest Walsh averages bound the interval (Hollander and Wolfe
    1999, section 3.3: k = C_alpha = n(n + 1)/2 + 1 - t_(alpha/2)). Normal: k = floor(n(n + 1)
    / 4 - z sqrt(n(n + 1)(2n + 1) / 24) + 1/2), z the upper ``tail`` quantile."""
    if n <= 0:
        return 0
    if exact:
        return _depth(_subset_sums(np.arange(1, n + 1)), tail)
    mean, sd = n * (n + 1) / 4, math.sqrt(n * (n + 1) * (2 * n + 1) / 24)
    return max(0, math.floor(mean + ndtri(tail) * sd + 0.5))


@lru_cache(maxsize=256)
def rank_sum_depth(m: int, n: int, tail: float, *, exact: bool) -> int:
    """The depth k of the distribution-free interval from the rank-sum test of m and n
    untied values: the largest k with P(U <= k - 1) <= ``tail`` (U = R - m(m + 1)/2), so that
    the k-th smallest and k-th largest of the m n cross differences bound the interval
    (Hollander and Wolfe 1999, section 4.3: C_alpha = m(2n + m + 1)/2 + 1 - w_(alpha/2)).
    Normal: k = floor(m n / 2 - z sqrt(m n (m + n + 1) / 12) + 1/2)."""
    if m <= 0 or n <= 0:
        return 0
    if exact:
        ranks = np.arange(1, m + n + 1)
        pmf = _subset_sums_of_size(ranks, m)[m * (m + 1) // 2 :]  # U = R - m(m + 1)/2
        return _depth(pmf, tail)
    mean, sd = m * n / 2, math.sqrt(m * n * (m + n + 1) / 12)
    return max(0, math.floor(mean + ndtri(tail) * sd + 0.5))


@lru_cache(maxsize=256)
def depth_coverage_signed_rank(n: int, k: int) -> float:
    """The exact coverage 1 - 2 P(T+ <= k - 1) of the depth-k interval of n untied
    differences (1 for k = 0: the whole line)."""
    if k <= 0:
        return 1.0
    return 1.0 - 2.0 * float(_subset_sums(np.arange(1, n + 1))[:k].sum())


@lru_cache(maxsize=256)
def depth_coverage_rank_sum(m: int, n: int, k: int) -> float:
    """The exact coverage 1 - 2 P(U <= k - 1) of the depth-k interval of m and n untied
    values."""
    if k <= 0:
        return 1.0
    pmf = _subset_sums_of_size(np.arange(1, m + n + 1), m)[m * (m + 1) // 2 :]
    return 1.0 - 2.0 * float(pmf[:k].sum())


def _check(alternative: str) -> None:
    if alternative not in ALTERNATIVES:
        raise ValueError(f"alternative must be one of {ALTERNATIVES}, not {alternative!r}")


def _doubled_ranks(v: np.ndarray) -> np.ndarray:
    """Twice the average ranks: integers."""
    return np.rint(2 * rankdata(v)).astype(np.int64)


def _subset_sums(scores: np.ndarray) -> np.ndarray:
    """pmf[s] = P(the sum of a uniformly random subset of the integer ``scores`` is s)."""
    return _subset_sums_cached(tuple(int(s) for s in scores))


@lru_cache(maxsize=64)
def _subset_sums_cached(scores: tuple[int, ...]) -> np.ndarray:
    """:func:`_subset_sums` of the scores as a tuple, kept: a report asks for the same ranks
    (untied, or shifted by a margin) many times."""
    scores = np.asarray(scores, np.int64)
    pmf = np.zeros(int(scores.sum()) + 1)
    pmf[0] = 1.0
    for s in scores:  # one step per rank: pmf <- (pmf + pmf shifted by s) / 2
        shifted = np.zeros_like(pmf)
        shifted[s:] = pmf[: pmf.size - s]
        pmf = (pmf + shifted) / 2
    pmf.flags.writeable = False  # kept: no caller may change it
    return pmf


def _subset_sums_of_size(scores: np.ndarray, m: int) -> np.ndarray:
    """pmf[s] = P(the sum of a uniformly random m-subset of the integer ``scores`` is s)."""
    return _subset_sums_of_size_cached(tuple(int(s) for s in scores), int(m))


@lru_cache(maxsize=64)
def _subset_sums_of_size_cached(scores: tuple[int, ...], m: int) -> np.ndarray:
    """:func:`_subset_sums_of_size` of the scores as a tuple, kept (as
    :func:`_subset_sums_cached`)."""
    scores = np.asarray(scores, np.int64)
    chosen, m = m, min(m, scores.size - m)  # the complement's sums mirror: total - s
    counts = np.zeros((m + 1, int(scores.sum()) + 1))
    counts[0, 0] = 1.0
    reach = 0  # the largest sum reachable so far
    for i, s in enumerate(scores):  # one step per rank: take it (one more chosen, sum + s)
        rows, reach = min(i + 1, m), reach + int(s)
        # numpy reads the overlapping right-hand side as it was before the addition
        counts[1 : rows + 1, s : reach + 1] += counts[:rows, : reach + 1 - s]
    row = counts[m]
    if m != chosen:
        row = row[::-1]
    pmf = row / row.sum()
    pmf.flags.writeable = False  # kept: no caller may change it
    return pmf


def _tail(pmf: np.ndarray, t: int, alternative: str) -> float:
    p = pmf[t:].sum() if alternative == "greater" else pmf[: t + 1].sum()
    return float(min(1.0, p))


def _normal_tail(t: float, mean: float, var: float, alternative: str) -> float:
    """The continuity-corrected normal tail; t, mean and var in doubled-rank units, so the
    correction of half a rank is 1."""
    if var <= 0:
        return 1.0
    z = (t - mean - 1) / math.sqrt(var) if alternative == "greater" else \
        (t - mean + 1) / math.sqrt(var)  # fmt: skip
    return float(ndtr(-z) if alternative == "greater" else ndtr(z))


def _depth(pmf: np.ndarray, tail: float) -> int:
    """The largest k with cdf(k - 1) <= tail (pmf over 0, 1, 2, ...)."""
    cdf = np.cumsum(pmf)
    return int(np.count_nonzero(cdf <= tail * (1 + 1e-12)))
