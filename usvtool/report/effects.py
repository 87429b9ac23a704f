"""Effects in the metric's own units, with their intervals (docs/statistics.md, "Effects in the
metric's units").

**Sign.** As :func:`usvtool.report.inference.compare`: every estimate and bound here is an
**improvement**, > 0 when the method is better in the claim's direction. With ``better=
"lower"`` it is rival - method (a route 122 m shorter than the rival's is +122), with
``"higher"`` method - rival. The raw difference method - rival is the improvement with its
sign flipped when lower is better. The values must be finite (measured values: a failure has
no magnitude; compare the failures apart, :mod:`usvtool.report.rates`).

- :func:`hodges_lehmann`: the Hodges-Lehmann shift (Hodges and Lehmann 1963, Ann. Math. Stat.
  34) with its distribution-free interval (Bauer 1972, J. Am. Stat. Assoc. 67, 687-690;
  Hollander and Wolfe 1999, Nonparametric Statistical Methods, 2nd ed., sections 3.2-3.3
  paired, 4.2-4.3 independent). Paired: the median of the n(n + 1)/2 Walsh averages
  (d_i + d_j)/2, i <= j, of the n improvements d (all pairs, zeros too), the interval
  [W_(k), W_(M + 1 - k)] of the sorted Walsh averages with k the signed-rank depth
  (C_alpha = n(n + 1)/2 + 1 - t_(alpha/2)). Independent: the median of the m n cross
  differences a_i - b_j, the interval [D_(k), D_(mn + 1 - k)] with k the rank-sum depth
  (C_alpha = m(2n + m + 1)/2 + 1 - w_(alpha/2)). k is exact or normal by
  :func:`usvtool.report.effective_n.exact`; the exact k gives a coverage of at least the one
  asked for (the coverage reached is given); k = 0 (even the most extreme arrangement is
  more likely than (1 - confidence)/2: at 95 %, 5 pairs or fewer, 3 + 3 runs) gives the
  whole line, -inf to +inf. With ties the coverage is
  approximate (the depths are the untied distribution's).
- :func:`bootstrap_difference`: the difference of a named statistic (median, mean, min, max,
  std, variance: ddof 1) with its bootstrap interval, pairs resampled together when paired,
  the resamples drawn from ``numpy.random.default_rng(seed)`` as one (resamples, n) index
  array per side (the method's first): the draws, and so the intervals, of
  ``scipy.stats.bootstrap`` given the same generator. The interval is the **percentile**
  interval (Efron and Tibshirani 1993, An Introduction to the Bootstrap, chapter 13), or with
  ``interval="bca"`` the **bias-corrected and accelerated** one (Efron 1987, J. Am. Stat.
  Assoc. 82, 171-185; Efron and Tibshirani 1993, chapter 14: the percentiles
  Phi(z0 + (z0 + z_q) / (1 - a (z0 + z_q))), z0 = Phi^-1 of the share of resamples below the
  estimate, ties counting half, a from the jackknife, :func:`_acceleration`); where BCa is
  undefined (a side of fewer than 2 values, 3 for a spread; every resample on one side of the
  estimate) the percentile interval is given, and ``Difference.interval`` says which. And
  the **relative change**, the improvement over |the rival's statistic|, with its interval of
  the same kind over the same resamples (None when the rival's statistic is 0 in the sample
  or in some resample).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import partial

import numpy as np
from scipy.special import ndtr, ndtri

from usvtool.report import effective_n, rank_null

BETTER = ("lower", "higher")
PERCENTILE, BCA = "percentile", "bca"
#: The bootstrap intervals: percentile, or bias-corrected and accelerated.
INTERVALS = (PERCENTILE, BCA)
#: The statistics a difference may be of, each over the last axis.
STATISTICS = {
    "median": np.median,
    "mean": np.mean,
    "min": np.min,
    "max": np.max,
    "std": partial(np.std, ddof=1),
    "variance": partial(np.var, ddof=1),
}


@dataclass(frozen=True)
class Shift:
    """The Hodges-Lehmann shift (> 0: the method better) and its interval; ``coverage`` the
    interval's coverage (exact: reached, at least the one asked for; normal: the one asked
    for); ``exact``: the depth from the exact distribution; ``n``: the pairs (paired) or the
    sizes."""

    estimate: float
    low: float
    high: float
    confidence: float
    coverage: float
    paired: bool
    exact: bool
    n: tuple[int, int]


@dataclass(frozen=True)
class Difference:
    """The bootstrap of a statistic's difference: the improvement ``estimate`` (> 0: the
    method better) with its interval (``interval``: ``"percentile"`` or ``"bca"``, the one
    used), the two sides' statistics, and the relative change (the improvement over |the
    rival's statistic|) with its interval (None: the rival's statistic is 0)."""

    statistic: str
    estimate: float
    low: float
    high: float
    method_value: float
    rival_value: float
    relative: float | None
    relative_low: float | None
    relative_high: float | None
    paired: bool
    confidence: float
    resamples: int
    seed: int
    interval: str = PERCENTILE


def hodges_lehmann(method: Sequence[float], rival: Sequence[float], *, paired: bool,
                   better: str, confidence: float = 0.95) -> Shift:  # fmt: skip
    """The Hodges-Lehmann shift of ``method`` against ``rival`` with its distribution-free
    ``confidence`` interval (module docstring)."""
    a, b = oriented(method, rival, better, paired)
    tail = (1 - confidence) / 2
    if paired:
        d = a - b
        i, j = np.triu_indices(d.size)
        values = np.sort((d[i] + d[j]) / 2)
        rule = effective_n.exact(True, d.size)
        k = rank_null.signed_rank_depth(d.size, tail, exact=rule)
        coverage = rank_null.depth_coverage_signed_rank(d.size, k) if rule else confidence
        sizes = (d.size, d.size)
    else:
        values = np.sort((a[:, None] - b[None, :]).ravel())
        rule = effective_n.exact(False, a.size + b.size)
        k = rank_null.rank_sum_depth(a.size, b.size, tail, exact=rule)
        coverage = rank_null.depth_coverage_rank_sum(a.size, b.size, k) if rule else confidence
        sizes = (a.size, b.size)
    if k == 0:
        low, high, coverage = -math.inf, math.inf, 1.0
    else:
        low, high = float(values[k - 1]), float(values[values.size - k])
    return Shift(float(np.median(values)), low, high, confidence, coverage, paired, rule, sizes)


def bootstrap_difference(method: Sequence[float], rival: Sequence[float], *, statistic: str,
                         paired: bool, better: str, seed: int = 0, resamples: int = 2000,
                         confidence: float = 0.95,
                         interval: str = PERCENTILE) -> Difference:  # fmt: skip
    """The bootstrap of the improvement in ``statistic``, ``interval`` ``"percentile"`` or
    ``"bca"`` (module docstring)."""
    if statistic not in STATISTICS:
        raise ValueError(f"statistic must be one of {tuple(STATISTICS)}, not {statistic!r}")
    if interval not in INTERVALS:
        raise ValueError(f"interval must be one of {INTERVALS}, not {interval!r}")
    x, y = _finite(method, rival, paired)
    if statistic in ("std", "variance") and min(x.size, y.size) < 2:
        raise ValueError(f"the {statistic} needs at least two values on each side")
    sign = _sign(better)
    f = STATISTICS[statistic]
    fx, fy = float(f(x)), float(f(y))
    bx, by = resampled(x, y, statistic, paired=paired, seed=seed, resamples=resamples)
    boot = sign * (bx - by)
    estimate = float(sign * (fx - fy))
    # the jackknife leaves one value out: the statistic must be defined on n - 1 values
    smallest = 3 if statistic in ("std", "variance") else 2
    bca = interval == BCA and min(x.size, y.size) >= smallest
    jx, jy = _jackknife(x, y, f, paired) if bca else (None, None)
    groups = None if jx is None else [sign * (jx_ - jy_) for jx_, jy_ in zip(jx, jy, strict=True)]
    low, high, used = _bounds(boot, estimate, groups, confidence)
    relative = (None, None, None)
    if fy != 0 and np.all(by != 0):
        rel_groups = None
        if groups is not None and all(np.all(g != 0) for g in jy):
            rel_groups = [g / np.abs(r) for g, r in zip(groups, jy, strict=True)]
        rel_low, rel_high, _ = _bounds(boot / np.abs(by), estimate / abs(fy), rel_groups,
                                       confidence)  # fmt: skip
        relative = (estimate / abs(fy), rel_low, rel_high)
    return Difference(statistic, estimate, low, high, fx, fy, *relative, paired, confidence,
                      resamples, seed, used)  # fmt: skip


def _bounds(boot: np.ndarray, estimate: float, jackknife: list[np.ndarray] | None,
            confidence: float) -> tuple[float, float, str]:  # fmt: skip
    """The percentile bounds of ``boot``, or the BCa bounds when ``jackknife`` (the
    leave-one-out estimates, one array per sample) is given and BCa is defined (some resample
    on each side of the estimate, a finite acceleration); which was used."""
    tail = (1 - confidence) / 2
    levels, used = np.array([tail, 1 - tail]), PERCENTILE
    if jackknife is not None:
        share = (np.sum(boot < estimate) + np.sum(boot <= estimate)) / (2 * boot.size)
        a = _acceleration(jackknife)
        if 0 < share < 1 and math.isfinite(a):
            z0, z = ndtri(share), ndtri(levels)
            levels, used = ndtr(z0 + (z0 + z) / (1 - a * (z0 + z))), BCA
    low, high = np.percentile(boot, 100 * levels)
    return float(low), float(high), used


def _jackknife(x: np.ndarray, y: np.ndarray, f, paired: bool):
    """The leave-one-out statistics, per sample: paired, one group (a pair left out of both);
    independent, x's values left out one at a time (y whole) and y's (x whole). Returns the
    method's and the rival's statistic for each group."""

    def loo(v: np.ndarray) -> np.ndarray:
        keep = ~np.eye(v.size, dtype=bool)
        return f(np.broadcast_to(v, (v.size, v.size))[keep].reshape(v.size, v.size - 1), axis=-1)

    if paired:
        return [loo(x)], [loo(y)]
    return [loo(x), np.full(y.size, f(x))], [np.full(x.size, f(y)), loo(y)]


def _acceleration(groups: list[np.ndarray]) -> float:
    """BCa's acceleration from the jackknife estimates of each sample (Efron and Tibshirani
    1993, eq. 14.15; for several samples, Davison and Hinkley 1997, Bootstrap Methods and their
    Application, section 5.3.2): with U = (n - 1)(mean - each) per sample,
    a = sum_j sum U^3 / n_j^3 / (6 (sum_j sum U^2 / n_j^2)^(3/2)); 0 when every U is 0."""
    with np.errstate(invalid="ignore"):
        us = [(g.size - 1) * (g.mean() - g) for g in groups]
        num = sum(float(np.sum(u**3)) / u.size**3 for u in us)
        den = sum(float(np.sum(u**2)) / u.size**2 for u in us) ** 1.5
    if not math.isfinite(num) or not math.isfinite(den):
        return math.nan
    return 0.0 if den == 0 else num / (6 * den)


def resampled(x: np.ndarray, y: np.ndarray, statistic: str, *, paired: bool, seed: int,
              resamples: int) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """``statistic`` of each of ``resamples`` bootstrap resamples of x and of y (paired: the
    same indices for both), the indices drawn as one (resamples, n) array per side from
    ``numpy.random.default_rng(seed)``, x's first."""
    f = STATISTICS[statistic]
    rng = np.random.default_rng(seed)
    ix = rng.integers(0, x.size, size=(resamples, x.size))
    iy = ix if paired else rng.integers(0, y.size, size=(resamples, y.size))
    return f(x[ix], axis=-1), f(y[iy], axis=-1)


def _sign(better: str) -> float:
    if better not in BETTER:
        raise ValueError(f"better must be one of {BETTER}, not {better!r}")
    return 1.0 if better == "higher" else -1.0


def _finite(method: Sequence[float], rival: Sequence[float], paired: bool):
    x, y = np.asarray(method, float), np.asarray(rival, float)
    if x.size == 0 or y.size == 0:
        raise ValueError("an effect needs at least one value on each side")
    if not (np.isfinite(x).all() and np.isfinite(y).all()):
        raise ValueError("an effect in the metric's units takes finite values only (no "
                         "failure, no NaN): compare the failures apart (rates)")  # fmt: skip
    if paired and x.size != y.size:
        raise ValueError(f"paired samples differ in size ({x.size} and {y.size})")
    return x, y


def oriented(method, rival, better: str, paired: bool):
    """The values times +1 (higher better) or -1 (lower better): larger is better."""
    sign = _sign(better)
    x, y = _finite(method, rival, paired)
    return sign * x, sign * y
