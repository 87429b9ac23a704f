"""Failure rates as their own outcome (docs/statistics.md, "Failure rates"): the method's runs
that failed (collided, never arrived) against the rival's, with the test, the difference of
the rates with its 95 % interval and the counts of every cell.

**Sign.** As :func:`usvtool.report.inference.compare`: ``difference`` = the rival's failure
rate - the method's, > 0 when the method fails less (better); its bounds likewise.

- **Paired** (runs of the same scenes): the 2 x 2 table of pairs, ``both`` failed, ``method``
  only, ``rival`` only, ``neither``. Test: the **exact McNemar** test (McNemar 1947,
  Psychometrika 12; its exact form: Agresti 2013, Categorical Data Analysis, 3rd ed., section
  11.1): the two-sided binomial test of the b method-only failures among the b + c
  discordant pairs against 1/2 (``scipy.stats.binomtest``); p None when no pair is discordant
  (no evidence either way). Interval: **Newcombe's method 10 for paired data** (Newcombe 1998,
  Stat. Med. 17, 2635-2650): with the Wilson score intervals (l1, u1), (l2, u2) of the two
  marginal rates p1 = (a + b)/n, p2 = (a + c)/n and the continuity-corrected correlation
  phi = C / sqrt((a + b)(c + d)(a + c)(b + d)), C = a d - b c - n/2 when a d - b c > n/2, 0
  when 0 <= a d - b c <= n/2, a d - b c when negative (phi = 0 when a margin is 0; Newcombe's
  method 10 as Altman et al. 2000, Statistics with Confidence, 2nd ed., ch. 6, and Fagerland,
  Lydersen and Laake 2017, Statistical Analysis of Contingency Tables, chapter 8, give it),
  p1 - p2 is bounded by
  p1 - p2 - sqrt((p1 - l1)^2 - 2 phi (p1 - l1)(u2 - p2) + (u2 - p2)^2) and
  p1 - p2 + sqrt((u1 - p1)^2 - 2 phi (u1 - p1)(p2 - l2) + (p2 - l2)^2).
- **Independent**: the two groups' failures. Test: **Fisher's exact test**, two-sided
  (``scipy.stats.fisher_exact``); p None when no run of either side failed, or every run did.
  Interval: **Newcombe's hybrid score interval** (Newcombe 1998, Stat. Med. 17, 873-890,
  method 10): p1 - p2 - sqrt((p1 - l1)^2 + (u2 - p2)^2) to p1 - p2 + sqrt((u1 - p1)^2 +
  (p2 - l2)^2).

The Wilson score interval (Wilson 1927, J. Am. Stat. Assoc. 22) of k of n at z:
(k + z^2/2 ± z sqrt(k (n - k) / n + z^2 / 4)) / (n + z^2). The intervals are computed for
p1 - p2 (method - rival) and turned round (negated, bounds swapped) for the sign above.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.special import ndtri
from scipy.stats import binomtest, fisher_exact

MCNEMAR, FISHER = "exact McNemar", "Fisher's exact"
NEWCOMBE_PAIRED, NEWCOMBE_HYBRID = "Newcombe (paired, method 10)", "Newcombe hybrid score"


@dataclass(frozen=True)
class Cells:
    """The counts. Paired: ``both`` failed, ``method`` only, ``rival`` only, ``neither`` (of
    the pairs). Independent: ``both`` and ``neither`` are None, ``method`` and ``rival`` the
    failures of each group, ``sizes`` each group's runs."""

    both: int | None
    method: int
    rival: int
    neither: int | None
    sizes: tuple[int, int]


@dataclass(frozen=True)
class RateComparison:
    """The failure rates compared: the test and its two-sided p (None: no evidence), the rates,
    their difference rival - method (> 0: the method fails less) with its interval, and the
    cells."""

    test: str
    p: float | None
    method_rate: float
    rival_rate: float
    difference: float
    low: float
    high: float
    interval: str
    confidence: float
    cells: Cells


def compare_failures(method_failed: Sequence[bool], rival_failed: Sequence[bool], *,
                     paired: bool, confidence: float = 0.95) -> RateComparison:  # fmt: skip
    """Compare the method's failures with the rival's (paired: element i of each is the same
    scene); True is a failed run."""
    x, y = np.asarray(method_failed, bool), np.asarray(rival_failed, bool)
    if x.size == 0 or y.size == 0:
        raise ValueError("a rate needs at least one run on each side")
    z = float(ndtri(0.5 + confidence / 2))
    if paired:
        if x.size != y.size:
            raise ValueError(f"paired samples differ in size ({x.size} and {y.size})")
        a, b = int(np.sum(x & y)), int(np.sum(x & ~y))
        c, d = int(np.sum(~x & y)), int(np.sum(~x & ~y))
        p = binomtest(b, b + c, 0.5).pvalue if b + c else None
        low, high = newcombe_paired(a, b, c, d, z)
        cells, test, interval = Cells(a, b, c, d, (x.size, y.size)), MCNEMAR, NEWCOMBE_PAIRED
        rates = ((a + b) / x.size, (a + c) / x.size)
    else:
        k1, k2, n1, n2 = int(x.sum()), int(y.sum()), x.size, y.size
        informative = 0 < k1 + k2 < n1 + n2
        p = fisher_exact([[k1, n1 - k1], [k2, n2 - k2]]).pvalue if informative else None
        low, high = newcombe_hybrid(k1, n1, k2, n2, z)
        cells, test, interval = Cells(None, k1, k2, None, (n1, n2)), FISHER, NEWCOMBE_HYBRID
        rates = (k1 / n1, k2 / n2)
    p = None if p is None else float(p)
    return RateComparison(test, p, rates[0], rates[1], rates[1] - rates[0], -high, -low,
                          interval, confidence, cells)  # fmt: skip


def wilson(k: int, n: int, z: float) -> tuple[float, float]:
    """The Wilson score interval of k successes of n (module docstring)."""
    centre, half = k + z * z / 2, z * math.sqrt(k * (n - k) / n + z * z / 4)
    return max(0.0, (centre - half) / (n + z * z)), min(1.0, (centre + half) / (n + z * z))


def newcombe_hybrid(k1: int, n1: int, k2: int, n2: int, z: float) -> tuple[float, float]:
    """Newcombe's hybrid score interval of k1/n1 - k2/n2 (independent; module docstring)."""
    p1, p2 = k1 / n1, k2 / n2
    l1, u1 = wilson(k1, n1, z)
    l2, u2 = wilson(k2, n2, z)
    d = p1 - p2
    return d - math.hypot(p1 - l1, u2 - p2), d + math.hypot(u1 - p1, p2 - l2)


def newcombe_paired(a: int, b: int, c: int, d: int, z: float) -> tuple[float, float]:
    """Newcombe's method 10 interval of (a + b)/n - (a + c)/n for the paired table a (both),
    b (first only), c (second only), d (neither) (module docstring)."""
    n = a + b + c + d
    p1, p2 = (a + b) / n, (a + c) / n
    l1, u1 = wilson(a + b, n, z)
    l2, u2 = wilson(a + c, n, z)
    margins = (a + b) * (c + d) * (a + c) * (b + d)
    cross = a * d - b * c
    corrected = cross - n / 2 if cross > n / 2 else (0.0 if cross >= 0 else cross)
    phi = corrected / math.sqrt(margins) if margins else 0.0
    dl1, du1, dl2, du2 = p1 - l1, u1 - p1, p2 - l2, u2 - p2
    delta = p1 - p2
    low = delta - math.sqrt(max(0.0, dl1 * dl1 - 2 * phi * dl1 * du2 + du2 * du2))
    high = delta + math.sqrt(max(0.0, du1 * du1 - 2 * phi * du1 * dl2 + dl2 * dl2))
    return low, high
