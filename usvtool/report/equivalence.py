"""Equivalence against a margin, and the n a test would need (docs/statistics.md,
"Equivalence" and "The n needed").

- :func:`tost`: the **two one-sided tests** (Schuirmann 1987, J. Pharmacokin. Biopharm. 15,
  657-680; their rank forms: Wellek 2010, Testing Statistical Hypotheses of Equivalence and
  Noninferiority, 2nd ed., chapters 5 and 6, here as shifted rank tests) of the shift
  theta of the method's values against the rival's (> 0: the method better, as
  :func:`usvtool.report.inference.compare`) against a margin m > 0 in the metric's units.
  H0: theta <= -m or theta >= m; H1: -m < theta < m. The lower test is the signed-rank test of
  d + m (paired; d the improvements) or the rank-sum test of a + m against b (independent; a
  and b the oriented values), alternative "greater"; the upper one the same with - m,
  alternative "less". p = the larger of the two one-sided p; **equivalent** when p < alpha.
  Exact or normal by :func:`usvtool.report.effective_n.exact` on the shifted data's informative
  n (:mod:`usvtool.report.rank_null`; zero differences after the shift dropped). Beside it, the
  (1 - 2 alpha) Hodges-Lehmann interval (:func:`usvtool.report.effects.hodges_lehmann`): the
  usual reading of TOST, equivalent when it lies inside (-m, m), which the two tests agree with
  up to ties.
- :func:`sample_size`: the n **per group** (pairs, when paired) at which the two-sided rank
  test at ``alpha`` would reject **in the observed direction** (the sign of the observed rank
  statistic) with probability ``power`` (0.8), by simulation from the observed data:
  ``simulations`` samples of size n drawn with replacement from the observed improvements
  (paired) or from each side (independent, n each), drawn from
  ``numpy.random.default_rng(seed)`` in batches of at most 2 million values (the same seed at
  every n: common random numbers), each tested by the normal approximation with the tie and
  continuity corrections (vectorised over the samples: ranks by counting the observed values'
  levels in each sample, :class:`_Coded`; the same floats as ``scipy.stats.rankdata(axis=1)``
  of the drawn values gives). The search starts at Noether's approximation
  (:func:`noether`), halves or doubles n until the power is bracketed, then bisects between
  the last n that fell short and the first that did not, to within 5 % (or 1): a handful of
  simulations at about the n sought. Above ``cap`` it gives up: ``n`` None, and ``reason``
  says so (without simulating when Noether's n is beyond twice the cap: its figure is
  given, the power NaN).
  An observed effect of zero (as many ahead as behind) never reaches the power.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.special import ndtr, ndtri
from scipy.stats import rankdata

from usvtool.report import effective_n, rank_null
from usvtool.report.effects import Shift, hodges_lehmann, oriented

SIGNED_RANK, RANK_SUM = "Wilcoxon signed-rank", "Mann-Whitney U"
#: The values ranked at once when simulating (samples x n x sides), to bound the memory.
_CHUNK = 2_000_000


@dataclass(frozen=True)
class Equivalence:
    """TOST against ``margin``: the one-sided p of the lower (theta > -margin) and upper
    (theta < margin) tests, ``p`` the larger, ``equivalent`` p < ``alpha``; ``exact`` whether
    both used the exact distribution; ``interval`` the (1 - 2 alpha) Hodges-Lehmann interval."""

    test: str
    margin: float
    p_lower: float
    p_upper: float
    p: float
    alpha: float
    equivalent: bool
    exact: bool
    interval: Shift


@dataclass(frozen=True)
class SampleSize:
    """The n per group (pairs) reaching ``target`` power, None above ``cap``; ``power`` the
    simulated power at n (at ``cap`` when None); ``reason`` says why there is no n."""

    n: int | None
    power: float
    target: float
    alpha: float
    cap: int
    simulations: int
    seed: int
    test: str
    reason: str = ""


def tost(method: Sequence[float], rival: Sequence[float], *, paired: bool, better: str,
         margin: float, alpha: float = 0.05) -> Equivalence:  # fmt: skip
    """Two one-sided rank tests of the shift against (-margin, margin) (module docstring)."""
    if not margin > 0:
        raise ValueError(f"the margin must be positive, not {margin!r}")
    a, b = oriented(method, rival, better, paired)
    if paired:
        d = a - b
        lower, upper = d + margin, d - margin
        exact_low = effective_n.exact(True, int(np.count_nonzero(lower)))
        exact_up = effective_n.exact(True, int(np.count_nonzero(upper)))
        p_lower = rank_null.signed_rank_p(lower, "greater", exact=exact_low)
        p_upper = rank_null.signed_rank_p(upper, "less", exact=exact_up)
        test = SIGNED_RANK
    else:
        exact_low = exact_up = effective_n.exact(False, a.size + b.size)
        p_lower = rank_null.rank_sum_p(a + margin, b, "greater", exact=exact_low)
        p_upper = rank_null.rank_sum_p(a - margin, b, "less", exact=exact_up)
        test = RANK_SUM
    p = max(p_lower, p_upper)
    interval = hodges_lehmann(method, rival, paired=paired, better=better,
                              confidence=1 - 2 * alpha)  # fmt: skip
    return Equivalence(test, float(margin), p_lower, p_upper, p, alpha, p < alpha,
                       exact_low and exact_up, interval)  # fmt: skip


def sample_size(method: Sequence[float], rival: Sequence[float], *, paired: bool, better: str,
                power: float = 0.8, alpha: float = 0.05, seed: int = 0,
                simulations: int = 400, cap: int = 10_000) -> SampleSize:  # fmt: skip
    """The n per group a rank test of the observed effect would need for ``power`` (module
    docstring)."""
    a, b = oriented(method, rival, better, paired)
    d = a - b if paired else None
    test = SIGNED_RANK if paired else RANK_SUM
    observed = _signed_rank_z(d[None, :]) if paired else _rank_sum_z(a[None, :], b[None, :])
    direction = float(np.sign(observed[0]))

    coded = _Coded(d) if paired else _Coded(a, b)

    def power_at(n: int) -> float:
        rng = np.random.default_rng(seed)
        rows = max(1, _CHUNK // (n if paired else 2 * n))
        rejected = 0
        for done in range(0, simulations, rows):  # batches of samples, each vectorised
            k = min(rows, simulations - done)
            if paired:
                z = coded.signed_rank_z(rng.integers(0, d.size, size=(k, n)))
            else:
                z = coded.rank_sum_z(rng.integers(0, a.size, size=(k, n)),
                                     rng.integers(0, b.size, size=(k, n)))  # fmt: skip
            rejected += int(np.count_nonzero(ndtr(-direction * z) < alpha / 2))
        return rejected / simulations

    def result(n, reached, reason=""):
        return SampleSize(n, reached, power, alpha, cap, simulations, seed, test, reason)

    if direction == 0:
        return result(None, 0.0, "no observed effect: as many ahead as behind")
    guess = noether(a, b, paired=paired, power=power, alpha=alpha)
    if guess > 2 * cap:  # far beyond the cap: Noether's figure says so without simulating
        return result(None, float("nan"), f"Noether's approximation gives about {guess:.0f} "
                                          f"a group, beyond {cap}")  # fmt: skip
    n = int(min(max(2, round(guess)), cap))
    at_n = power_at(n)
    if at_n >= power:  # halve until it falls short
        high, at_high = n, at_n
        low = max(1, n // 2)
        while low > 1 and (at_low := power_at(low)) >= power:
            high, at_high, low = low, at_low, max(1, low // 2)
    else:  # double until it is reached
        low = n
        while True:
            high = min(2 * low, cap)
            at_high = power_at(high)
            if at_high >= power:
                break
            if high >= cap:
                return result(None, at_high, f"the power at {cap} a group is {at_high:.2f}, "
                                             f"below {power:g}")  # fmt: skip
            low = high
    while high - low > max(1, low // 20):
        mid = (low + high) // 2
        at_mid = power_at(mid)
        if at_mid >= power:
            high, at_high = mid, at_mid
        else:
            low = mid
    return result(high, at_high)


def noether(a: np.ndarray, b: np.ndarray, *, paired: bool, power: float,
            alpha: float) -> float:  # fmt: skip
    """Noether's (1987, J. Am. Stat. Assoc. 82, 645-647) approximate n per group of the
    two-sided rank test at ``alpha`` with ``power``: N = (z_(1 - alpha/2) + z_power)^2 / (3 (q
    - 1/2)^2), the pairs with q = P(d_i + d_j > 0) over the Walsh averages (paired), or both
    groups together, N / 2 each, with q = P(a > b) (independent, two equal groups; half the
    ties counted); the search's start. inf when q = 1/2."""
    z = float(ndtri(1 - alpha / 2) + ndtri(power))
    if paired:
        d = a - b
        i, j = np.triu_indices(d.size, k=1)
        w = d[i] + d[j] if d.size > 1 else d
        q = float(np.mean(w > 0) + 0.5 * np.mean(w == 0))
    else:
        q = float(np.mean(a[:, None] > b[None, :]) + 0.5 * np.mean(a[:, None] == b[None, :]))
    if q == 0.5:
        return float("inf")
    total = z * z / (3 * (q - 0.5) ** 2)  # pairs; or both groups together, half each
    return total if paired else total / 2


def _signed_rank_z(d: np.ndarray) -> np.ndarray:
    """Each row's continuity-corrected signed-rank z (> 0: positive differences ahead), zeros
    dropped: the ranks of |d| among the row's nonzero values are its ranks among all of them
    less the row's zeros (which rank below every nonzero value); 0 for a row of zeros."""
    size = np.abs(d)
    zeros = np.sum(size == 0, axis=1, keepdims=True)
    ranks = np.where(size > 0, rankdata(size, axis=1) - zeros, 0.0)
    t = np.sum(np.where(d > 0, ranks, 0.0), axis=1)
    mean, var = ranks.sum(axis=1) / 2, (ranks**2).sum(axis=1) / 4
    return _z(t, mean, var)


def _rank_sum_z(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Each row's continuity-corrected rank-sum z of x against y (> 0: x ahead), the
    permutation variance of the row's average ranks."""
    m, n = x.shape[1], y.shape[1]
    ranks = rankdata(np.concatenate([x, y], axis=1), axis=1)
    r = ranks[:, :m].sum(axis=1)
    total = m + n
    var = m * n / (total * (total - 1)) * ((ranks - (total + 1) / 2) ** 2).sum(axis=1)
    return _z(r, m * (total + 1) / 2, var)


class _Coded:
    """The rank statistics of samples drawn from observed values, ranked by counting: each
    observed value is coded by its place among the distinct ones (``levels``), a sample's ranks
    are its rows' counts of each level, cumulated (a level's average rank is the count below it
    plus (its count + 1) / 2), with no sort of the samples. The same floats as
    :func:`_signed_rank_z` and :func:`_rank_sum_z` on the drawn values: ranks are multiples of
    1/2, so every sum of them (and of their squared offsets, multiples of 1/4) is exact in
    any order. Given ``d`` (paired) or ``a, b``; the samples as indices into them."""

    def __init__(self, first: np.ndarray, second: np.ndarray | None = None):
        if second is None:
            size = np.abs(first)
            self.levels = np.unique(size)
            self.code = np.searchsorted(self.levels, size)
            self.positive = first > 0
        else:
            self.levels = np.unique(np.concatenate([first, second]))
            self.code = np.searchsorted(self.levels, first)
            self.code_second = np.searchsorted(self.levels, second)

    def _counts(self, codes: np.ndarray) -> np.ndarray:
        """(k, levels): how many of each row's entries hold each level (``codes`` (k, n), or
        a masked selection given as (rows, codes) of equal length)."""
        u = self.levels.size
        k = codes.shape[0]
        flat = codes + u * np.arange(k)[:, None]
        return np.bincount(flat.ravel(), minlength=k * u).reshape(k, u)

    @staticmethod
    def _ranks(counts: np.ndarray) -> np.ndarray:
        """Each level's average rank (1-based) in its row."""
        return (np.cumsum(counts, axis=1) - counts) + (counts + 1) / 2

    def signed_rank_z(self, drawn: np.ndarray) -> np.ndarray:
        """:func:`_signed_rank_z` of ``d[drawn]``."""
        codes = self.code[drawn]
        counts = self._counts(codes)
        u, k = self.levels.size, drawn.shape[0]
        zero = self.levels[0] == 0
        zeros = counts[:, :1] if zero else np.zeros((k, 1), counts.dtype)
        ranks = self._ranks(counts) - zeros
        if zero:
            counts = counts.copy()
            counts[:, 0] = 0  # zero differences are dropped
        flat = (codes + u * np.arange(k)[:, None])[self.positive[drawn]]
        ahead = np.bincount(flat, minlength=k * u).reshape(k, u)
        t = (ahead * ranks).sum(axis=1)
        mean, var = (counts * ranks).sum(axis=1) / 2, (counts * ranks**2).sum(axis=1) / 4
        return _z(t, mean, var)

    def rank_sum_z(self, drawn_first: np.ndarray, drawn_second: np.ndarray) -> np.ndarray:
        """:func:`_rank_sum_z` of ``a[drawn_first]`` against ``b[drawn_second]``."""
        m, n = drawn_first.shape[1], drawn_second.shape[1]
        first = self._counts(self.code[drawn_first])
        counts = first + self._counts(self.code_second[drawn_second])
        ranks = self._ranks(counts)
        r = (first * ranks).sum(axis=1)
        total = m + n
        var = m * n / (total * (total - 1)) * (counts * (ranks - (total + 1) / 2) ** 2).sum(axis=1)
        return _z(r, m * (total + 1) / 2, var)


def _z(t: np.ndarray, mean, var: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore", divide="ignore"):
        z = np.sign(t - mean) * np.maximum(np.abs(t - mean) - 0.5, 0) / np.sqrt(var)
    return np.where(var > 0, z, 0.0)
