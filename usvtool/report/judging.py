"""How the report judges a claim on our runs (docs/statistics.md): the tests, Holm's correction
within a family of claims and the six verdicts, for the papers' claims
(:data:`usvtool.report.papers.CLAIMS`, each followed by our variants of its method:
:func:`paper_verdicts`) and the user's (a pipeline's ``claims:``,
:attr:`usvtool.report.data.Results.claims`: :func:`user_verdicts`) alike, each source a Holm
family of its own. Nothing here writes a page: the sections (:mod:`.sections.claims`,
:mod:`.sections.your_claims`, :mod:`.sections.summary`, :mod:`.sections.other_methods`,
:mod:`.sections.baselines`) build their tables from the :class:`Verdict` and :class:`Test`
given here.

A **relative** claim compares the method with each rival in each case (:func:`comparison`),
runs paired by scene and seed (a scene family's runs: :meth:`usvtool.report.data.Results.pairs`)
or independent (routes and functions, which share no randomness by seed), in two comparisons:

- **the failures** as their own outcome, every run counted (a run that collided, never
  arrived, or whose controller failed; a route through an obstacle): exact McNemar on scene
  pairs, Fisher's exact test otherwise, the rates' difference with its interval
  (:mod:`usvtool.report.rates`);
- **the metric on the measured values** (:func:`measured`: a run that broke, collided or
  whose controller failed, or a colliding route, measures nothing and is left out; a run that
  only never arrived keeps its closest distance; paired, the pairs where both are measured),
  by the test of the statistic the claim names (:data:`TESTED`,
  :mod:`usvtool.report.named_statistic`), with the effective n, the rank effect (r or δ) with
  its bootstrap interval, the Hodges-Lehmann shift in the metric's units with its
  distribution-free interval, the named statistic's difference and relative change with
  their bootstrap intervals, and, for a location statistic, TOST against the metric's
  smallest effect of interest (:mod:`usvtool.report.margins`).

The p of one family's metric comparisons are Holm-corrected together, and those of its failure
comparisons apart, as a second family (:func:`judge_family`). The claim **holds** when the method is
better with corrected p < :data:`ALPHA` against every rival in every case (and fails no more often,
significantly, anywhere), **does not hold** when it is significantly worse in some, or fails
significantly more often, is **equivalent** when every comparison lies within the margin (TOST, each
at ALPHA: the intersection-union test needs no correction), is **inconclusive** otherwise, with the
n a group it would need for 80 % power (:func:`needed`), **not testable** when a declared
precondition fails (:data:`CHECKS`) and **not tested** when runs are missing. A claim's ``context``
rivals are compared and shown, outside the verdict and the Holm family.

An **absolute** claim (no rivals) is counted per case by its statistic's function in
:data:`ABSOLUTE` (``every``: the runs meeting the target, with the 95 % Clopper-Pearson
interval of their share); it holds when every run of the method in every case meets its
target (a user's claim may ask for a ``share`` of them: then by the interval), does not hold
when one does not, and is not tested when a case has no runs. A failed run never meets a
COLREGs target, nor does a run that judged no encounter; ``collision`` has a
row only when the ship hit something (absent: 0).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

from scipy.stats import binomtest

from usvtool.report import edges, inference
from usvtool.report.data import JobResults, Results, in_group, summarise
from usvtool.report.effective_n import EffectiveN, effective_n
from usvtool.report.effects import Shift, hodges_lehmann, oriented
from usvtool.report.equivalence import Equivalence, SampleSize, noether, sample_size, tost
from usvtool.report.inference import Comparison
from usvtool.report.margins import MARGINS, margin
from usvtool.report.named_statistic import StatisticTest, compare_statistic
from usvtool.report.papers import CLAIMS, TABLES, Claim
from usvtool.report.rates import RateComparison, compare_failures

HOLDS, FAILS, EQUIVALENT = "holds", "does not hold", "equivalent"
INCONCLUSIVE = "inconclusive"
UNTESTABLE, UNTESTED = "not testable", "not tested"
#: The five verdicts, in the order the counts are given.
VERDICTS = (HOLDS, FAILS, EQUIVALENT, INCONCLUSIVE, UNTESTABLE, UNTESTED)
#: The corrected p below which a difference counts.
ALPHA = 0.05
#: The bootstrap's seed and resamples (inference.compare).
SEED, RESAMPLES = 0, 2000
#: Metrics with a row only when something happened (absent: 0).
EVENTS = ("collision", "controller_failed")


@dataclass(frozen=True)
class Side:
    """One method's runs in one comparison: how many (``n``, those whose table says how they
    ended), how many failed (:attr:`JobResults.failed`: collided, never arrived, a colliding
    route), how many entered the metric's test (``measured``: :func:`measured`), and over
    those the median, the IQR and the claim's own statistic (``figure``)."""

    method: str
    n: int
    failed: int
    measured: int
    median: float | None
    iqr: float | None
    figure: float | None


@dataclass(frozen=True)
class Test:
    """The method against one rival in one case, in two comparisons: the failures
    (``failures``, every run) and the metric on the measured values (``statistic``: the
    claim's statistic's test, :func:`usvtool.report.named_statistic.compare_statistic`;
    ``comparison``: the rank effect, r or δ, with its interval; ``shift``: the Hodges-Lehmann
    shift in the metric's units; ``entered``: the effective n; ``equivalence``: TOST against
    the metric's smallest effect of interest, for a location statistic). ``p`` and
    ``failures_p`` are Holm-corrected (:func:`judge_family`); ``needed``: the n a group an
    inconclusive comparison would need for 80 % power. ``context``: a rival compared for
    context only, outside the verdict and the Holm family (its p uncorrected)."""

    case: str
    rival: str
    sides: tuple[Side, Side]
    comparison: Comparison | None
    p: float | None = None
    statistic: StatisticTest | None = None
    shift: Shift | None = None
    entered: EffectiveN | None = None
    equivalence: Equivalence | None = None
    failures: RateComparison | None = None
    failures_p: float | None = None
    needed: SampleSize | None = None
    context: bool = False

    @property
    def metric_outcome(self) -> str:
        """``better`` or ``worse`` (corrected p < ALPHA, by the direction of the claim's
        statistic), ``equivalent`` (TOST), ``neither``, or ``missing`` (no measured values)."""
        if self.statistic is None:
            return "missing"
        if self.p is not None and self.p < ALPHA and (sign := self.direction):
            return "better" if sign > 0 else "worse"
        if self.equivalence is not None and self.equivalence.equivalent:
            return "equivalent"
        return "neither"

    @property
    def direction(self) -> float:
        """The sign of the method's advantage: the rank effect's for a location statistic,
        the named statistic's difference's otherwise (> 0: the method better)."""
        if self.statistic is None:
            return 0.0
        if self.statistic.statistic == "median" and self.comparison is not None:
            return float(math.copysign(1.0, self.comparison.effect)) if self.comparison.effect \
                else 0.0  # fmt: skip
        estimate = self.statistic.difference.estimate
        return float(math.copysign(1.0, estimate)) if estimate else 0.0

    @property
    def failure_outcome(self) -> str:
        """``better`` or ``worse`` (the failure rates differ with corrected p < ALPHA), or
        ``neither``."""
        f = self.failures
        if f is None or self.failures_p is None or self.failures_p >= ALPHA or f.difference == 0:
            return "neither"
        return "better" if f.difference > 0 else "worse"

    @property
    def outcome(self) -> str:
        """``worse`` when the method fails significantly more often or its metric is
        significantly worse; else its metric's outcome (``better``, ``equivalent``,
        ``neither``; ``missing`` without measured values)."""
        if "worse" in (self.metric_outcome, self.failure_outcome):
            return "worse"
        return self.metric_outcome


@dataclass(frozen=True)
class Tally:
    """An absolute claim in one case: runs, those meeting the target with the 95 %
    Clopper-Pearson interval of the proportion, and what the others did."""

    case: str
    n: int
    met: int
    low: float
    high: float
    note: str = ""


@dataclass(frozen=True)
class Verdict:
    """A claim's verdict, why (``reason``: what fails of a precondition, with ``why`` the
    precondition's own reason; the runs missing; the n an inconclusive claim would need), and
    its comparisons (relative) or tallies (absolute). ``variant``: our variant of the
    method. ``edges``: the routes that hug the grid's edges and whether they decide the verdict
    (:func:`flag_edges`)."""

    claim: Claim
    verdict: str
    reason: str = ""
    tests: tuple[Test, ...] = ()
    tallies: tuple[Tally, ...] = ()
    variant: bool = False
    why: str = ""
    edges: str = ""


# --- runs ------------------------------------------------------------------------------------


def value(job: JobResults, metric: str) -> float | None:
    """The run's metric as a number (:data:`EVENTS`: 1 when it has a row, else 0)."""
    if metric in EVENTS:
        return 1.0 if job.text(metric) else 0.0
    return job.number(metric)


def broke(job: JobResults) -> bool:
    """Whether the job's metrics measure no work of the method: a run that collided or whose
    controller failed, a route through an obstacle. A run that only never arrived did its work:
    its closest distance, its COLREGs counts are measured (it has no arrival time)."""
    if job.kind == "routes":
        return job.text("collision_free") == "False"
    return bool(job.text("collision")) or bool(job.text("controller_failed"))


def measured(job: JobResults, claim: Claim) -> float | None:
    """The run's value entering the claim's metric test: None when its table does not say how
    it ended, when it broke (:func:`broke`; but for a claim on :data:`EVENTS`, which counts
    them) or has no value."""
    if not job.settled or (claim.metric not in EVENTS and broke(job)):
        return None
    return value(job, claim.metric)


def _side(method: str, jobs: Sequence[JobResults], values: Sequence[float],
          claim: Claim) -> Side:  # fmt: skip
    """The side's figures over its measured ``values`` (of ``jobs``, the runs compared)."""
    figure = summarise(values, claim.statistic, [j.number("fitness") for j in jobs
                                                 if measured(j, claim) is not None])  # fmt: skip
    return Side(method, len(jobs), sum(j.failed for j in jobs), len(values),
                inference.median(values) if values else None,
                inference.iqr(values) if values else None, figure)  # fmt: skip


# --- the claims' statistics --------------------------------------------------------------------

#: Each relative statistic of a claim (:data:`usvtool.report.papers.STATISTICS`) -> the
#: statistic its test compares (:mod:`usvtool.report.named_statistic`): a median, a paper's
#: single figure (``value``) and the best-fitness run's metric (``of-best``: one draw, judged by
#: where the runs lie) by the rank test; a mean by the means; a spread by Brown-Forsythe; a
#: best run by the bootstrap of the best.
TESTED = {"value": "median", "median": "median", "of-best": "median", "mean": "mean",
          "min": "min", "max": "max", "variance": "variance", "std": "std"}  # fmt: skip
#: The statistics whose equivalence is tested (a shift of location; TOST on spreads and best
#: runs is not defined here: those stay inconclusive when not significant).
LOCATION = ("median", "mean")
#: The power an inconclusive comparison's n is computed for.
POWER = 0.8


# --- absolute claims ------------------------------------------------------------------------


def meets(job: JobResults, claim: Claim) -> bool:
    """Whether the run meets an absolute claim's target: its metric at least as good as the
    target in the claim's direction (the target a number, or the name of another metric of the
    run, as ``compliant`` against ``judged``: for the papers' claims, equal to it). A run that
    failed meets none (but a target on :data:`EVENTS`), nor does one whose table does not say
    how it ended, nor one whose target metric is below 1 (nothing to judge)."""
    if not job.settled:  # no evidence of meeting it
        return False
    mine = value(job, claim.metric)
    if isinstance(claim.target, str):
        target = value(job, claim.target)
        # a failed run, or one with nothing to judge, is no evidence of meeting it
        return (not job.failed and mine is not None and target is not None and target >= 1
                and _reaches(mine, target, claim.better))  # fmt: skip
    return (mine is not None and claim.target is not None
            and _reaches(mine, float(claim.target), claim.better)
            and (claim.metric in EVENTS or not job.failed))  # fmt: skip


def _reaches(mine: float, target: float, better: str) -> bool:
    """``mine`` at least as good as ``target`` when ``better`` (lower or higher) is better."""
    return mine <= target if better == "lower" else mine >= target


def _note(jobs: Sequence[JobResults], claim: Claim) -> str:
    """What the runs that did not meet an absolute claim's target did instead."""
    parts = []
    crashed = sum(bool(j.text("collision")) for j in jobs)
    stopped = sum(j.text("arrived") == "False" and not j.text("collision") for j in jobs)
    if crashed:
        parts.append(f"{crashed} collided")
    if stopped:
        parts.append(f"{stopped} did not arrive")
    if isinstance(claim.target, str):
        done = [j for j in jobs if not j.failed]
        if none := sum((value(j, claim.target) or 0) < 1 for j in done):
            parts.append(f"{none} judged no encounter")
        if broke := sum((value(j, "noncompliant") or 0) > 0 for j in done):
            parts.append(f"{broke} with a non-compliant encounter")
        excused = sum(not meets(j, claim) and (value(j, "compliant_excused") or 0) > 0
                      and value(j, "noncompliant") == 0 and (value(j, claim.target) or 0) >= 1
                      for j in done)  # fmt: skip
        if excused:
            parts.append(f"{excused} compliant only through an excused Rule 2 departure")
    return ", ".join(parts)


def every(case: str, jobs: Sequence[JobResults], claim: Claim) -> Tally:
    """The runs of one case meeting the target (:func:`meets`), with the 95 % Clopper-Pearson
    interval of their share and what the others did."""
    met = sum(meets(j, claim) for j in jobs)
    ci = binomtest(met, len(jobs)).proportion_ci(0.95, method="exact")
    return Tally(case, len(jobs), met, float(ci.low), float(ci.high), _note(jobs, claim))


#: An absolute statistic's count of one case's runs.
Count = Callable[[str, Sequence[JobResults], Claim], Tally]
#: Each absolute statistic's count.
ABSOLUTE: dict[str, Count] = {"every": every}


# --- comparisons -----------------------------------------------------------------------------


def _jobs(results: Results, claim: Claim, case: str,
          rival: str) -> tuple[list[JobResults], list[JobResults]]:  # fmt: skip
    """The runs compared: scene and seed pairs of the family's runs, each side's routes or
    function runs otherwise; only those whose table says how they ended."""
    if claim.kind == "runs":
        pairs = [(a, b) for a, b in results.pairs(claim.kind, case, claim.method, rival)
                 if a.settled and b.settled]  # fmt: skip
        return [a for a, _ in pairs], [b for _, b in pairs]
    mine, theirs = ([j for j in results.group(claim.kind, case, m) if j.settled]
                    for m in (claim.method, rival))  # fmt: skip
    return mine, theirs


def _values(mine: Sequence[JobResults], theirs: Sequence[JobResults], claim: Claim,
            paired: bool) -> tuple[list[float], list[float]]:  # fmt: skip
    """The measured values of each side (:func:`measured`); paired, of the pairs where both
    are measured."""
    x = [measured(j, claim) for j in mine]
    y = [measured(j, claim) for j in theirs]
    if paired:
        kept = [(a, b) for a, b in zip(x, y, strict=True) if a is not None and b is not None]
        return [a for a, _ in kept], [b for _, b in kept]
    return [a for a in x if a is not None], [b for b in y if b is not None]


def comparison(results: Results, claim: Claim, case: str, rival: str,
               context: bool = False) -> Test:  # fmt: skip
    """The claim's method against ``rival`` in ``case`` (a results case or a group of them,
    :func:`usvtool.report.data.in_group`): the failure rates over every run (paired by scene
    and seed for a family's runs: exact McNemar; else Fisher), and the claim's statistic over
    the measured values (:func:`measured`; paired: the pairs where both are measured). The p
    are left uncorrected: :func:`judge_family` corrects a family's."""
    paired = claim.kind == "runs"
    mine, theirs = _jobs(results, claim, case, rival)
    failures = None
    if mine and theirs and claim.kind != "functions":
        failures = compare_failures([j.failed for j in mine], [j.failed for j in theirs],
                                    paired=paired)  # fmt: skip
    x, y = _values(mine, theirs, claim, paired)
    sides = (_side(claim.method, mine, x, claim), _side(rival, theirs, y, claim))
    if not x or not y:
        return Test(case, rival, sides, None, failures=failures,
                    failures_p=None if failures is None else failures.p, context=context)
    named = TESTED[claim.statistic]
    found = compare_statistic(x, y, statistic=named, paired=paired, better=claim.better,
                              seed=SEED, resamples=RESAMPLES)  # fmt: skip
    spread = named in ("variance", "std")  # the rank effect on the absolute deviations
    ranks = inference.compare(*((inference.dispersion(x), inference.dispersion(y)) if spread
                                else (x, y)), paired=paired, better=claim.better, seed=SEED,
                              resamples=RESAMPLES, shift=False)  # fmt: skip
    shift = hodges_lehmann(x, y, paired=paired, better=claim.better)
    equivalent = None
    if named in LOCATION and claim.metric in MARGINS.get(claim.kind, {}):
        bound = margin(claim.kind, claim.metric, inference.median(y))
        if bound > 0:
            equivalent = tost(x, y, paired=paired, better=claim.better, margin=bound)
    return Test(case, rival, sides, ranks, found.p, found, shift,
                effective_n(x, y, paired=paired), equivalent, failures,
                None if failures is None else failures.p, context=context)  # fmt: skip


def _needed_values(results: Results, claim: Claim, test: Test) -> tuple[list, list]:
    """The values whose rank test's power :func:`needed` simulates: the measured values, their
    absolute deviations from each side's median for a spread."""
    x, y = _values(*_jobs(results, claim, test.case, test.rival), claim, claim.kind == "runs")
    if TESTED[claim.statistic] in ("variance", "std"):
        return list(inference.dispersion(x)), list(inference.dispersion(y))
    return x, y


def needed(results: Results, claim: Claim, test: Test, alpha: float) -> SampleSize | None:
    """The n a group the inconclusive ``test`` would need for :data:`POWER` at ``alpha``, by
    simulation from its measured values (:func:`usvtool.report.equivalence.sample_size`): the
    rank test's power, on the values for a median or a mean (the rank test standing in for
    the permutation of the means), on the absolute deviations from each side's median for a
    spread; None for a best run (no power of the bootstrap of an extreme is computed)."""
    if TESTED[claim.statistic] in ("min", "max"):
        return None
    x, y = _needed_values(results, claim, test)
    return sample_size(x, y, paired=claim.kind == "runs", better=claim.better, power=POWER,
                       alpha=alpha, seed=SEED)  # fmt: skip


# --- preconditions ---------------------------------------------------------------------------


def _points(job: JobResults) -> int | None:
    path = job.dir / "summary.json"
    try:
        return int(json.loads(path.read_text(encoding="utf-8"))["points"])
    except (OSError, ValueError, KeyError, TypeError):
        return None


def _turns_reachable(results: Results, claim: Claim) -> str:
    """'' when every route of the claim's methods can turn as often as the paper's table has
    any of them turn in the claim's cases (a route of P points turns at most P - 2 times);
    else what fails."""
    table = TABLES[claim.table]
    column = next(c for c in table.columns if c.metric == "turns")
    methods = (claim.method, *claim.rivals)
    want = [v for case in claim.cases for pc in claim.table_cases(case) for m in methods
            if (v := table.value(m, pc, column.name)) is not None]  # fmt: skip
    jobs = [j for case in claim.cases for m in methods for j in results.group(claim.kind, case, m)]
    points = [_points(j) for j in jobs]
    if not jobs or None in points:
        return "the routes' summary.json (their points) are missing"
    cap = min(points) - 2
    if want and cap < max(want):
        return (
            f"our routes turn at most {cap} times ({min(points)} points), the paper's "
            f"up to {max(want):g}"
        )
    return ""


#: Each precondition check (:data:`usvtool.report.papers.CHECKS`): what fails ('' when met).
CHECKS: dict[str, Callable[[Results, Claim], str]] = {"turns-reachable": _turns_reachable}


def _unmet(results: Results, claim: Claim) -> tuple[str, str]:
    """What fails of the first precondition that does, and that precondition's reason (two
    empty strings when every precondition holds)."""
    for p in claim.preconditions:
        fails = CHECKS[p.check](results, claim)
        if fails:
            return fails, p.reason
    return "", ""


# --- verdicts --------------------------------------------------------------------------------


def _relative(claim: Claim, tests: Sequence[Test]) -> Verdict:
    """Holds when the method is better against every rival in every case, does not hold when
    it is worse in one (its metric, or fails more often), is equivalent when every comparison
    is (TOST), inconclusive otherwise (with the largest n a group the inconclusive comparisons
    would need); not tested when runs are missing. Context rivals do not count."""
    judged = [t for t in tests if not t.context]
    outcomes = {t.outcome for t in judged}
    missing = [f"{t.case} ({t.rival})" for t in judged if t.outcome == "missing"]
    reason = f"no runs: {', '.join(missing)}" if missing else ""
    if "worse" in outcomes:
        verdict = FAILS
    elif missing:
        verdict = UNTESTED
    elif outcomes == {"better"}:
        verdict = HOLDS
    elif outcomes == {"equivalent"}:
        verdict = EQUIVALENT
    else:
        verdict, reason = INCONCLUSIVE, _power(judged)
    return Verdict(claim, verdict, reason, tuple(tests))


def _power(tests: Sequence[Test]) -> str:
    """What the weakest inconclusive comparison would need (:func:`_weakest`): the n a group
    for 80 % power, and which comparison."""
    t = next((t for t in tests if t.needed is not None), None)
    if t is None:
        return ""
    which = f"{t.case} vs {t.rival}"
    if t.needed.n is None:
        return (f"more than {t.needed.cap} runs a group for {100 * POWER:.0f} % power "
                f"({which})")  # fmt: skip
    return f"about {t.needed.n} runs a group for {100 * POWER:.0f} % power ({which})"


def _weakest(results: Results, claim: Claim, tests: Sequence[Test]) -> Test | None:
    """The claim's inconclusive comparison that would need the most runs, by Noether's
    approximation (:func:`usvtool.report.equivalence.noether`); None when the claim has
    none, or names a best run."""
    if TESTED.get(claim.statistic, "min") in ("min", "max"):  # absolute claims: none
        return None
    paired = claim.kind == "runs"
    found, most = None, -1.0
    for t in tests:
        if t.context or t.outcome != "neither":
            continue
        x, y = _needed_values(results, claim, t)
        a, b = oriented(x, y, claim.better, paired)
        guess = noether(a, b, paired=paired, power=POWER, alpha=ALPHA)
        if guess > most:
            found, most = t, guess
    return found


def _absolute(results: Results, claim: Claim) -> Verdict:
    """Every run in every case meets the target (``share`` 1, the papers'); for a smaller
    ``share``, the 95 % Clopper-Pearson interval of each case's share: it holds when every
    case's interval lies at or above ``share``, does not hold when one lies wholly below it,
    and is inconclusive otherwise."""
    tallies, missing = [], []
    for case in claim.cases:
        jobs = results.group(claim.kind, case, claim.method)
        if not jobs:
            missing.append(case)
            continue
        tallies.append(ABSOLUTE[claim.statistic](case, jobs, claim))
    if claim.share >= 1:
        short, sure = [t for t in tallies if t.met < t.n], True
    else:
        short = [t for t in tallies if t.high < claim.share]
        sure = all(t.low >= claim.share for t in tallies)
    if short:
        verdict = FAILS
    elif missing:
        verdict = UNTESTED
    else:
        verdict = HOLDS if sure else INCONCLUSIVE
    reason = f"no runs: {', '.join(missing)}" if missing else ""
    return Verdict(claim, verdict, reason, tallies=tuple(tallies))


def judge_family(results: Results, claims: Sequence[Claim]) -> list[Verdict]:
    """The verdicts of ``claims``: the p of their metrics' comparisons one Holm family, the p
    of their failure rates' another (two questions; a p that is undefined is not counted;
    context rivals are outside both). An inconclusive comparison gets the n a group it would
    need at the metrics' family's first Holm step, ALPHA over the p counted
    (:func:`needed`)."""
    pending: list[tuple[Claim, tuple[str, str], list[Test]]] = []
    for claim in claims:
        has_runs = any(j.settled for case in claim.cases
                       for j in results.group(claim.kind, case, claim.method))
        unmet = _unmet(results, claim) if has_runs else ("", "")
        tests = [] if unmet[0] or not claim.rivals else [
            comparison(results, claim, case, rival, context=rival in claim.context)
            for case in claim.cases for rival in (*claim.rivals, *claim.context)]  # fmt: skip
        pending.append((claim, unmet, tests))
    counted = [t for _, _, ts in pending for t in ts if not t.context]
    metrics = inference.holm([t.statistic and t.statistic.p for t in counted])
    failures = inference.holm([t.failures_p for t in counted])
    fixed = {id(t): pair for t, pair in zip(counted, zip(metrics, failures, strict=True),
                                            strict=True)}  # fmt: skip
    family = sum(t.statistic is not None and t.statistic.p is not None for t in counted)
    out = []
    for claim, unmet, ts in pending:
        ts = [replace(t, p=fixed[id(t)][0], failures_p=fixed[id(t)][1]) if id(t) in fixed
              else t for t in ts]  # fmt: skip
        weakest = _weakest(results, claim, ts)
        ts = [replace(t, needed=needed(results, claim, t, ALPHA / max(family, 1)))
              if t is weakest else t for t in ts]  # fmt: skip
        if unmet[0]:
            out.append(Verdict(claim, UNTESTABLE, unmet[0], why=unmet[1]))
        elif claim.rivals:
            out.append(_relative(claim, ts))
        else:
            out.append(_absolute(results, claim))
    return out


def judge(results: Results, claim: Claim) -> Verdict:
    """One claim judged alone (its own Holm family)."""
    return judge_family(results, [claim])[0]


# --- the claims of the report ----------------------------------------------------------------


def variants(results: Results, claim: Claim) -> list[str]:
    """Our clearly named variants of the claim's method run in the claim's cases (``udwa+`` of
    ``udwa``, ``iwso+g`` of ``iwso``): the claim is judged for each too, beside the paper's."""
    run = {j.method for case in claim.cases for j in results.jobs
           if j.kind == claim.kind and in_group(j.case, case)}  # fmt: skip
    return sorted(m for m in run if m.partition("+")[0] == claim.method and m != claim.method)


def flag_edges(results: Results, verdicts: Sequence[Verdict]) -> list[Verdict]:
    """The verdicts, each relative claim on routes with :attr:`Verdict.edges` saying how many
    of its routes hug the grid's edges (:func:`usvtool.report.edges.edge_share`) and whether
    they decide its verdict: the flagged claims judged again without those routes, as a Holm
    family of their own (docs/statistics.md)."""
    found = {v.claim.id: [c for c in edges.edge_share(results, v.claim) if c.hugging]
             for v in verdicts if v.claim.rivals and v.verdict not in (UNTESTABLE, UNTESTED)}
    flagged = [v for v in verdicts if found.get(v.claim.id)]
    if not flagged:
        return list(verdicts)
    left = {k for counts in found.values() for c in counts for k in c.keys}
    without = replace(results, jobs=[j for j in results.jobs if j.key not in left])
    again = {v.claim.id: v for v in judge_family(without, [v.claim for v in flagged])}
    out = []
    for v in verdicts:
        if v.claim.id in again:
            other = again[v.claim.id].verdict
            said = "; ".join(c.text() for c in found[v.claim.id])
            said += (f': without them the verdict would be "{other}"' if other != v.verdict
                     else ": without them the verdict is the same")  # fmt: skip
            v = replace(v, edges=said)
        out.append(v)
    return out


_PAPERS: list[tuple[Results, list[Verdict]]] = []


def paper_verdicts(results: Results) -> list[Verdict]:
    """Every claim of the papers judged, each followed by the same claim for our variants of
    its method (``id (variant)``, :attr:`Verdict.variant`): the papers' methods' comparisons
    one Holm family, the variants' another, so that adding a variant never changes a verdict on
    a paper's method. Computed once per :class:`Results` (the claims section and the summary
    share them)."""
    if not _PAPERS or _PAPERS[0][0] is not results:
        extra = {c.id: [replace(c, id=f"{c.id} ({m})", method=m) for m in variants(results, c)]
                 for c in CLAIMS}  # fmt: skip
        own = iter(flag_edges(results, judge_family(results, CLAIMS)))
        theirs = iter(judge_family(results, [v for c in CLAIMS for v in extra[c.id]]))
        _PAPERS[:] = [
            (
                results,
                [
                    v
                    for c in CLAIMS
                    for v in (
                        next(own),
                        *(replace(next(theirs), variant=True) for _ in extra[c.id]),
                    )
                ],
            )
        ]
    return _PAPERS[0][1]


_USERS: list[tuple[Results, list[Verdict]]] = []


def user_verdicts(results: Results) -> list[Verdict]:
    """The user's claims (:attr:`Results.claims`: a pipeline's ``claims:``) judged as one Holm
    family of their own, so that a user's claim never changes a verdict on the papers' (nor
    theirs on the user's). Computed once per :class:`Results`."""
    if not _USERS or _USERS[0][0] is not results:
        _USERS[:] = [(results, flag_edges(results, judge_family(results, results.claims)))]
    return _USERS[0][1]
