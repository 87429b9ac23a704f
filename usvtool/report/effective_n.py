"""The effective n of a comparison and the rule choosing the exact test over the normal
approximation (docs/statistics.md, "Effective n, exact or normal").

**Effective n.** Paired: the **informative pairs**, those whose difference is not zero (two
equal values, or two failures, say nothing about which side is better: the signed-rank test
drops them, Wilcoxon's ``zero_method="wilcox"``). Independent: the sizes of the two samples
(every run enters the rank-sum test; ties share their average rank).

**Exact or normal** (:func:`exact`). Exact (the permutation distribution of the observed
ranks, ties included, :mod:`usvtool.report.rank_null`) when at most :data:`EXACT_PAIRS`
informative pairs, or at most :data:`EXACT_RUNS` runs on both sides together; the normal
approximation with the tie and continuity corrections otherwise. Why these bounds: the exact
distribution costs one pass over the ranks with an array of at most 51 x 10 101 numbers, so it
is used wherever the report's cases can reach (30 scenes, 25 or 50 routes a side, 10 functions
a side); beyond them the statistic is a sum of 50 or more independent bounded terms and the
normal approximation is close (Lehmann 1975, Nonparametrics, chapters 1 and 3; at the
bounds, over 200 random samples of 50 pairs and 100 of 50 + 50 runs, the one-sided p of the
two differed by at most 0.0017 and 0.0008). The bound on pairs is scipy's own for the untied
exact signed-rank test (scipy.stats.wilcoxon, ``method="auto"``); scipy's rank-sum bound (a
side of 8 or fewer) is tighter only to save time, and it leaves tied samples to the normal
approximation at any size, where this rule does not.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

#: The largest number of informative pairs tested exactly.
EXACT_PAIRS = 50
#: The largest number of runs (both sides together) tested exactly.
EXACT_RUNS = 100


@dataclass(frozen=True)
class EffectiveN:
    """``sizes``: the values given on each side (pairs: both the number of pairs);
    ``informative``: the nonzero differences (paired) or the total of both sizes
    (independent); ``zeros``: the pairs dropped as zero differences (0 when independent);
    ``tied``: some informative |differences| (paired) or pooled values (independent) tie;
    ``exact``: the rule's choice (:func:`exact`)."""

    paired: bool
    sizes: tuple[int, int]
    informative: int
    zeros: int
    tied: bool
    exact: bool


def effective_n(method: Sequence[float], rival: Sequence[float], *, paired: bool) -> EffectiveN:
    """How many values a comparison of ``method`` with ``rival`` rests on (paired: element i
    of each is the same scene; equal infinities, two failures, are a zero difference)."""
    x, y = np.asarray(method, float), np.asarray(rival, float)
    if paired:
        if x.size != y.size:
            raise ValueError(f"paired samples differ in size ({x.size} and {y.size})")
        with np.errstate(invalid="ignore"):
            d = np.where(x == y, 0.0, x - y)
        size = np.abs(d[d != 0])
        informative = int(size.size)
        tied = bool(np.unique(size).size < size.size)
        return EffectiveN(True, (x.size, y.size), informative, x.size - informative, tied,
                          exact(True, informative))  # fmt: skip
    pooled = np.concatenate([x, y])
    tied = bool(np.unique(pooled).size < pooled.size)
    return EffectiveN(False, (x.size, y.size), int(pooled.size), 0, tied,
                      exact(False, int(pooled.size)))  # fmt: skip


def exact(paired: bool, informative: int) -> bool:
    """The rule: exact when ``informative`` (nonzero pairs; runs of both sides together) is at
    most :data:`EXACT_PAIRS` (paired) or :data:`EXACT_RUNS` (independent)."""
    return informative <= (EXACT_PAIRS if paired else EXACT_RUNS)
