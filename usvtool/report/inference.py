"""Comparisons of two methods over seeds or scenes: rank tests, an ordinal effect size with a
bootstrap interval, and Holm's correction (docs/statistics.md).

A run that failed (collided, never arrived) is passed as the worst possible value in the
claim's direction (``+inf`` when lower is better, ``-inf`` when higher is): every statistic
here is rank-based or an order statistic, so a failure ranks below every success and ties with
the other failures. Paired samples (the same scene under two controllers) are tested with the
Wilcoxon signed-rank test on the differences (zeros dropped, Wilcoxon's own rule), independent
ones (optimizers, which share no randomness by seed) with the Mann-Whitney U test; both
two-sided, as scipy.stats computes them (exact when small and untied, an exhaustive sign-flip
permutation for tied pairs up to 13, else the normal approximation with tie and continuity
corrections). Both tests see ranks only, so they are handed ranks: infinities never reach
arithmetic.

The effect is the rank-biserial correlation matching the test (Kerby 2014, Compr. Psychol. 3):
Cliff's delta for independent samples, P(method better) - P(method worse) over all cross pairs
(Cliff 1993, Psychol. Bull. 114(3)), and for paired samples the matched-pairs rank-biserial
r = (W+ - W-) / (W+ + W-) of the signed-rank sums. Both lie in [-1, 1] and are signed so that
> 0 means the method is better in the claim's direction; the effect's sign is the direction of
the test's statistic. The interval is the 2.5 and 97.5 percentiles of the effect over
``resamples`` bootstrap resamples (pairs resampled together when paired), drawn from
``numpy.random.default_rng(seed)``: the same inputs give the same bytes.

The Hodges-Lehmann shift (the median of the cross differences; of the Walsh averages when
paired: the estimators of the two tests, Hodges and Lehmann 1963, Ann. Math. Stat. 34) is given
beside it in the metric's units, same sign convention, only when no value is infinite: over
failures it is undefined, and over the successes alone it would flatter.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.stats import mannwhitneyu, rankdata, wilcoxon

WILCOXON, MANN_WHITNEY = "Wilcoxon signed-rank", "Mann-Whitney U"
CLIFF, PAIRED_R = "Cliff's delta", "matched-pairs rank-biserial r"
HL = "Hodges-Lehmann shift"
BETTER = ("lower", "higher")


@dataclass(frozen=True)
class Comparison:
    """The method against one rival: sizes, medians and IQRs (q75 - q25) of each side (over
    failures too: an infinite median says half or more failed, an infinite IQR that a quartile
    reaches a failure), the
    test and its two-sided uncorrected p (None when untestable: a side empty, or every value
    tied, every paired difference zero), the effect (> 0: the method better) with its 95 %
    bootstrap interval, and the Hodges-Lehmann shift with its interval (None when a value is
    infinite, or not asked for)."""

    n: tuple[int, int]
    median: tuple[float, float]
    iqr: tuple[float, float]
    test: str
    p: float | None
    effect_name: str
    effect: float
    low: float
    high: float
    shift: float | None = None
    shift_low: float | None = None
    shift_high: float | None = None


def compare(method: Sequence[float], rival: Sequence[float], *, paired: bool, better: str,
            seed: int = 0, resamples: int = 2000, shift: bool = True) -> Comparison:  # fmt: skip
    """Compare ``method``'s values with ``rival``'s (paired: element i of each is the same
    scene); ``better``: ``"lower"`` or ``"higher"``; ``shift``: also the Hodges-Lehmann shift
    (most of the bootstrap's work)."""
    if better not in BETTER:
        raise ValueError(f"better must be one of {BETTER}, not {better!r}")
    x, y = np.asarray(method, float), np.asarray(rival, float)
    if x.size == 0 or y.size == 0:
        raise ValueError("compare needs at least one value on each side")
    if np.isnan(x).any() or np.isnan(y).any():
        raise ValueError("compare takes no NaN: pass a failure as the worst infinity")
    if paired and x.size != y.size:
        raise ValueError(f"paired samples differ in size ({x.size} and {y.size})")
    sign = 1.0 if better == "higher" else -1.0
    # Oriented so that larger is better: the statistics below need no direction.
    a, b = sign * x, sign * y
    rng = np.random.default_rng(seed)
    finite = shift and bool(np.isfinite(a).all() and np.isfinite(b).all())
    if paired:
        d = _improvement(a, b)
        test, name, p = WILCOXON, PAIRED_R, _wilcoxon_p(d)
        effect = float(_signed_rank_r(d, np.ones((1, d.size)))[0])
        counts = _counts(rng, d.size, resamples)
        boot = _signed_rank_r(d, counts)
        if finite:  # the one-sample estimator over the Walsh averages
            i, j = np.triu_indices(d.size)
            shifts = (d[i] + d[j]) / 2.0, _walsh_weights(np.ones((1, d.size))), \
                _walsh_weights(counts)
    else:
        test, name, p = MANN_WHITNEY, CLIFF, _mann_whitney_p(a, b)
        dominance = _dominance(a, b)
        effect = float(dominance.mean())
        ca, cb = _counts(rng, a.size, resamples), _counts(rng, b.size, resamples)
        boot = np.einsum("bi,ij,bj->b", ca, dominance, cb) / (a.size * b.size)
        if finite:  # the two-sample estimator over the cross differences
            shifts = (a[:, None] - b[None, :]).ravel(), np.ones((1, a.size * b.size)), \
                (ca[:, :, None] * cb[:, None, :]).reshape(resamples, -1)
    low, high = np.percentile(boot, [2.5, 97.5])
    hl = (None, None, None)
    if finite:
        values, weights, resampled = shifts
        estimate = _weighted_median(values, weights)[0]
        low_s, high_s = np.percentile(_weighted_median(values, resampled), [2.5, 97.5])
        hl = (float(estimate), float(low_s), float(high_s))
    return Comparison((x.size, y.size), (median(x), median(y)), (iqr(x), iqr(y)), test, p,
                      name, effect, float(low), float(high), *hl)  # fmt: skip


def holm(p_values: Sequence[float | None]) -> list[float | None]:
    """Holm-Bonferroni adjusted p (Holm 1979, Scand. J. Stat. 6): the k-th smallest of m times
    (m - k + 1), made monotone and capped at 1; None (untestable) stays None and does not count
    in m."""
    tested = [(p, i) for i, p in enumerate(p_values) if p is not None]
    out: list[float | None] = [None] * len(p_values)
    running = 0.0
    for k, (p, i) in enumerate(sorted(tested)):
        running = max(running, min(1.0, (len(tested) - k) * p))
        out[i] = running
    return out


def median(v: Sequence[float]) -> float:
    """The median as an order statistic (the lower and upper middle's mean, an infinite one
    winning)."""
    s = np.sort(np.asarray(v, float))
    lo, hi = s[(s.size - 1) // 2], s[s.size // 2]
    return float(lo if lo == hi else (lo + hi) / 2)


def iqr(v: Sequence[float]) -> float:
    """q75 - q25; infinite when a quartile is (a failure within the middle half's reach), but 0
    when every value is the same."""
    s = np.sort(np.asarray(v, float))
    if s[0] == s[-1]:
        return 0.0
    q25, q75 = _quantile(s, 0.25), _quantile(s, 0.75)
    return math.inf if math.isinf(q25) or math.isinf(q75) else q75 - q25


def dispersion(v: Sequence[float]) -> np.ndarray:
    """Each value's absolute deviation from the sample's median (a spread claim compares these,
    as Brown and Forsythe 1974, J. Am. Stat. Assoc. 69, and Fligner and Killeen 1976 do):
    infinite for a failure and for every value when the median is a failure."""
    a = np.asarray(v, float)
    m = median(a)
    with np.errstate(invalid="ignore"):
        return np.where(np.isinf(a) | np.isinf(m), math.inf, np.abs(a - m))


def _quantile(s: np.ndarray, q: float) -> float:
    """numpy's linear quantile of sorted ``s``; between a number and an infinity, the infinity
    (the limit of the interpolation)."""
    h = (s.size - 1) * q
    lo, hi, frac = s[int(np.floor(h))], s[int(np.ceil(h))], h - np.floor(h)
    if lo == hi or frac == 0:
        return float(lo)
    if not np.isfinite(lo) or not np.isfinite(hi):
        return float(lo if np.isinf(lo) else hi)
    return float(lo + frac * (hi - lo))


def _improvement(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a - b, 0 where both are the same infinity (two failures tie)."""
    with np.errstate(invalid="ignore"):
        return np.where(a == b, 0.0, a - b)


def _dominance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """sign(a_i - b_j) by comparison (infinities tie with themselves)."""
    return (a[:, None] > b[None, :]).astype(float) - (a[:, None] < b[None, :])


def _mann_whitney_p(a: np.ndarray, b: np.ndarray) -> float | None:
    ranks = rankdata(np.concatenate([a, b]))
    if np.all(ranks == ranks[0]):
        return None
    return float(mannwhitneyu(ranks[: a.size], ranks[a.size :], alternative="two-sided").pvalue)


def _wilcoxon_p(d: np.ndarray) -> float | None:
    if not d.any():
        return None
    signed = np.sign(d) * rankdata(np.abs(d))
    return float(wilcoxon(signed, alternative="two-sided").pvalue)


def _counts(rng: np.random.Generator, n: int, resamples: int) -> np.ndarray:
    """How often each of n values is drawn in each resample: (resamples, n)."""
    draws = rng.integers(0, n, size=(resamples, n)) + n * np.arange(resamples)[:, None]
    return np.bincount(draws.ravel(), minlength=resamples * n).reshape(resamples, n).astype(float)


def _signed_rank_r(d: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """(W+ - W-) / (W+ + W-) of each resample given by ``counts`` (resamples, n) of the paired
    improvements ``d``: zeros dropped, average ranks of |d| among the resample's nonzero values
    (value k's rank = the count below it + (the count equal to it + 1) / 2); 0 when every
    difference is zero."""
    size = np.abs(d)
    nonzero = d != 0
    below = ((size[None, :] < size[:, None]) & nonzero[None, :]).astype(float)
    equal = ((size[None, :] == size[:, None]) & nonzero[None, :]).astype(float)
    ranks = counts @ below.T + (counts @ equal.T + 1.0) / 2.0
    signed = counts * ranks * np.sign(d)
    total = np.abs(signed).sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(total > 0, signed.sum(axis=1) / total, 0.0)


def _walsh_weights(counts: np.ndarray) -> np.ndarray:
    """How often each Walsh average occurs in each resample: c_i c_j for i < j, c_i (c_i + 1)
    / 2 for i = j."""
    i, j = np.triu_indices(counts.shape[1])
    pair = counts[:, i] * counts[:, j]
    return np.where(i == j, (pair + counts[:, i]) / 2.0, pair)


def _weighted_median(values: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """The median of each row's multiset (``values`` repeated ``weights`` times, integer
    weights): the mean of its order statistics ceil(T/2) and floor(T/2) + 1, found by one
    search in the rows' cumulative weights laid end to end (row i shifted past row i - 1)."""
    order = np.argsort(values, kind="stable")
    v, cum = values[order], np.cumsum(weights[:, order], axis=1)
    total = cum[:, -1]
    base = np.concatenate([[0.0], np.cumsum(total + 1)[:-1]])
    flat = (cum + base[:, None]).ravel()
    start = np.arange(cum.shape[0]) * cum.shape[1]
    at = [np.searchsorted(flat, k + base) - start
          for k in (np.floor((total + 1) / 2), np.floor(total / 2) + 1)]
    return (v[at[0]] + v[at[1]]) / 2.0
