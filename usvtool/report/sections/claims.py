"""The report's claims section: each claim of the papers (:data:`usvtool.report.papers.CLAIMS`)
judged on our runs with statistics over seeds and scenes (docs/statistics.md).

A **relative** claim compares the method with each rival in each case: runs paired by scene and
seed (a scene family's runs: :meth:`usvtool.report.data.Results.pairs`) with the Wilcoxon
signed-rank test, independent runs (optimizers and functions, which share no randomness by
seed) with the Mann-Whitney U test (:func:`usvtool.report.inference.compare`); a claim of a
spread (``variance``, ``std``) compares the runs' absolute deviations from their median. A run
that failed (a colliding route; a run that collided or did not arrive) is the worst outcome in
the claim's direction. Every p of the papers' methods in the table is Holm-corrected together
(our variants' rows, a family of their own). The claim **holds** when the method is better with
corrected p < :data:`ALPHA` against every rival in every case, **does not hold** when it is
significantly worse in some, is **inconclusive** otherwise, **not testable** when a declared
precondition fails (:data:`CHECKS`) and **not tested** when runs are missing.

An **absolute** claim (no rivals) holds when every run of the method in every case meets its
target, with the proportion that does and its 95 % Clopper-Pearson interval; a failed run never
meets a COLREGs target, nor does a run that judged no encounter; ``collision`` has a row only
when the ship hit something (absent: 0).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

from scipy.stats import binomtest

from usvtool.report import inference
from usvtool.report.data import JobResults, Results, in_group, summarise
from usvtool.report.document import APPENDIX, Cell, Section, Table
from usvtool.report.inference import Comparison
from usvtool.report.papers import CLAIMS, PAPERS, TABLES, Claim, Column

HOLDS, FAILS, INCONCLUSIVE = "holds", "does not hold", "inconclusive"
UNTESTABLE, UNTESTED = "not testable", "not tested"
#: The five verdicts, in the order the counts are given.
VERDICTS = (HOLDS, FAILS, INCONCLUSIVE, UNTESTABLE, UNTESTED)
CSS = {HOLDS: "holds", FAILS: "fails", INCONCLUSIVE: "inconclusive", UNTESTABLE: "untestable",
       UNTESTED: "untested"}  # fmt: skip
#: The corrected p below which a difference counts.
ALPHA = 0.05
#: The bootstrap's seed and resamples (inference.compare).
SEED, RESAMPLES = 0, 2000
#: Metrics with a row only when something happened (absent: 0).
EVENTS = ("collision",)
#: Statistics of a spread: judged on the absolute deviations from the median.
SPREADS = ("variance", "std")
#: A relative claim with more comparisons than this shows a digest in the claims table (every
#: comparison is in the appendix's table).
LISTED = 3


@dataclass(frozen=True)
class Side:
    """One method's runs in one case: how many, how many failed, their median and IQR (failures
    the worst), the claim's statistic over every run as measured (a failed route's length or
    penalised fitness; None when a failed run has no value, as a run that never arrived has no
    arrival time) and over the runs that did not fail."""

    method: str
    n: int
    failed: int
    median: float | None
    iqr: float | None
    figure: float | None
    clean: float | None


@dataclass(frozen=True)
class Test:
    """The method against one rival in one case: ``comparison`` None when a side has no runs;
    ``p`` the Holm-corrected p."""

    case: str
    rival: str
    sides: tuple[Side, Side]
    comparison: Comparison | None
    p: float | None = None

    @property
    def outcome(self) -> str:
        """``better``, ``worse`` (corrected p < ALPHA, by the effect's sign), ``neither`` or
        ``missing``."""
        if self.comparison is None:
            return "missing"
        if self.p is None or self.p >= ALPHA or self.comparison.effect == 0:
            return "neither"
        return "better" if self.comparison.effect > 0 else "worse"


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
    precondition's own reason; the runs missing), and its comparisons (relative) or tallies
    (absolute). ``variant``: our variant of the method."""

    claim: Claim
    verdict: str
    reason: str = ""
    tests: tuple[Test, ...] = ()
    tallies: tuple[Tally, ...] = ()
    variant: bool = False
    why: str = ""


# --- runs ------------------------------------------------------------------------------------


def _value(job: JobResults, metric: str) -> float | None:
    if metric in EVENTS:
        return 1.0 if job.text(metric) else 0.0
    return job.number(metric)


def _worst(claim: Claim) -> float:
    return math.inf if claim.better == "lower" else -math.inf


def outcome(job: JobResults, claim: Claim) -> float | None:
    """The run's value as the claim is judged: the worst for a failed run; None when it has no
    value, or the table does not say how it ended (:attr:`JobResults.settled`)."""
    if not job.settled:
        return None
    return _worst(claim) if job.failed else _value(job, claim.metric)


def _side(jobs: Sequence[JobResults], claim: Claim, judged: Sequence[float]) -> Side:
    measured = [_value(j, claim.metric) for j in jobs]
    fitness = [j.number("fitness") for j in jobs]
    ok = [i for i, j in enumerate(jobs) if not j.failed and measured[i] is not None]
    whole = None if any(v is None for v in measured) else summarise(measured, claim.statistic,
                                                                    fitness)  # fmt: skip
    clean = summarise([measured[i] for i in ok], claim.statistic, [fitness[i] for i in ok])
    return Side(jobs[0].method if jobs else "", len(judged), sum(j.failed for j in jobs),
                inference.median(judged) if judged else None,
                inference.iqr(judged) if judged else None, whole, clean)  # fmt: skip


def _test(results: Results, claim: Claim, case: str, rival: str) -> Test:
    if claim.kind == "runs":  # scenes: paired by (case, seed)
        pairs = [(a, b) for a, b in results.pairs(claim.kind, case, claim.method, rival)
                 if outcome(a, claim) is not None and outcome(b, claim) is not None]  # fmt: skip
        mine, theirs = [a for a, _ in pairs], [b for _, b in pairs]
    else:
        mine, theirs = ([j for j in results.group(claim.kind, case, m)
                         if outcome(j, claim) is not None] for m in (claim.method, rival))
    x, y = [outcome(j, claim) for j in mine], [outcome(j, claim) for j in theirs]
    sides = (replace(_side(mine, claim, x), method=claim.method),
             replace(_side(theirs, claim, y), method=rival))  # fmt: skip
    if not x or not y:
        return Test(case, rival, sides, None)
    if claim.statistic in SPREADS:
        x, y = inference.dispersion(x), inference.dispersion(y)
    comparison = inference.compare(x, y, paired=claim.kind == "runs", better=claim.better,
                                   seed=SEED, resamples=RESAMPLES, shift=False)  # fmt: skip
    return Test(case, rival, sides, comparison)


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
        return (f"our routes turn at most {cap} times ({min(points)} points), the paper's "
                f"up to {max(want):g}")
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


def _relative(claim: Claim, tests: Sequence[Test], variant: bool) -> Verdict:
    outcomes = {t.outcome for t in tests}
    missing = [f"{t.case} ({t.rival})" for t in tests if t.outcome == "missing"]
    if "worse" in outcomes:
        verdict = FAILS
    elif missing:
        verdict = UNTESTED
    else:
        verdict = HOLDS if outcomes == {"better"} else INCONCLUSIVE
    reason = f"no runs: {', '.join(missing)}" if missing else ""
    return Verdict(claim, verdict, reason, tuple(tests), variant=variant)


def _meets(job: JobResults, claim: Claim) -> bool:
    if not job.settled:  # no evidence of meeting it
        return False
    value = _value(job, claim.metric)
    if isinstance(claim.target, str):
        target = _value(job, claim.target)
        # a failed run, or one with nothing to judge, is no evidence of meeting it
        return (not job.failed and value is not None and target is not None and target >= 1
                and value == target)  # fmt: skip
    return value is not None and value == claim.target and (claim.metric in EVENTS
                                                            or not job.failed)  # fmt: skip


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
        if none := sum((_value(j, claim.target) or 0) < 1 for j in done):
            parts.append(f"{none} judged no encounter")
        if broke := sum((_value(j, "noncompliant") or 0) > 0 for j in done):
            parts.append(f"{broke} with a non-compliant encounter")
        excused = sum(not _meets(j, claim) and (_value(j, "compliant_excused") or 0) > 0
                      and _value(j, "noncompliant") == 0 and (_value(j, claim.target) or 0) >= 1
                      for j in done)  # fmt: skip
        if excused:
            parts.append(f"{excused} compliant only through an excused Rule 2 departure")
    return ", ".join(parts)


def _absolute(results: Results, claim: Claim, variant: bool) -> Verdict:
    tallies, missing = [], []
    for case in claim.cases:
        jobs = results.group(claim.kind, case, claim.method)
        if not jobs:
            missing.append(case)
            continue
        met = sum(_meets(j, claim) for j in jobs)
        ci = binomtest(met, len(jobs)).proportion_ci(0.95, method="exact")
        tallies.append(Tally(case, len(jobs), met, float(ci.low), float(ci.high),
                             _note(jobs, claim)))  # fmt: skip
    if any(t.met < t.n for t in tallies):
        verdict = FAILS
    else:
        verdict = UNTESTED if missing else HOLDS
    reason = f"no runs: {', '.join(missing)}" if missing else ""
    return Verdict(claim, verdict, reason, tallies=tuple(tallies), variant=variant)


def variants(results: Results, claim: Claim) -> list[str]:
    """Our clearly named variants of the claim's method run in the claim's cases (``udwa+`` of
    ``udwa``, ``iwso+g`` of ``iwso``): the claim is judged for each too, beside the paper's."""
    run = {j.method for case in claim.cases for j in results.jobs
           if j.kind == claim.kind and in_group(j.case, case)}  # fmt: skip
    return sorted(m for m in run if m.partition("+")[0] == claim.method and m != claim.method)


def _claims(results: Results) -> list[tuple[Claim, bool]]:
    """Every claim for the paper's method, each followed by the same claim for our variants."""
    return [(c2, c2 is not c) for c in CLAIMS
            for c2 in (c, *(replace(c, id=f"{c.id} ({m})", method=m)
                            for m in variants(results, c)))]  # fmt: skip


def judge_all(results: Results, claims: Sequence[tuple[Claim, bool]]) -> list[Verdict]:
    """The verdicts of ``claims`` ((claim, is a variant) pairs), the p of the relative ones
    Holm-corrected together, the papers' methods' and the variants' as two families."""
    pending: list[tuple[Claim, bool, tuple[str, str], list[Test]]] = []
    for claim, variant in claims:
        has_runs = any(outcome(j, claim) is not None for case in claim.cases
                       for j in results.group(claim.kind, case, claim.method))  # fmt: skip
        unmet = _unmet(results, claim) if has_runs else ("", "")
        tests = [] if unmet[0] or not claim.rivals else [
            _test(results, claim, case, rival) for case in claim.cases for rival in claim.rivals]
        pending.append((claim, variant, unmet, tests))
    for family in (False, True):
        tests = [t for _, v, _, ts in pending if v == family for t in ts]
        corrected = iter(inference.holm([None if t.comparison is None else t.comparison.p
                                         for t in tests]))  # fmt: skip
        for _, v, _, ts in pending:
            if v == family:
                ts[:] = [replace(t, p=next(corrected)) for t in ts]
    out = []
    for claim, variant, unmet, tests in pending:
        if unmet[0]:
            out.append(Verdict(claim, UNTESTABLE, unmet[0], variant=variant, why=unmet[1]))
        elif claim.rivals:
            out.append(_relative(claim, tests, variant))
        else:
            out.append(_absolute(results, claim, variant))
    return out


_CACHE: list[tuple[Results, list[Verdict]]] = []


def verdicts(results: Results) -> list[Verdict]:
    """Every claim's verdict (the papers' methods, each followed by our variants'), computed
    once per :class:`Results` (the claims section and the summary share them)."""
    if not _CACHE or _CACHE[0][0] is not results:
        _CACHE[:] = [(results, judge_all(results, _claims(results)))]
    return _CACHE[0][1]


def judge(results: Results, claim: Claim) -> Verdict:
    """One claim judged alone (its own Holm family)."""
    return judge_all(results, [(claim, False)])[0]


def counts(sections: list[Section]) -> dict[str, int]:
    """How many of the papers' claims have each verdict for the papers' own methods (from the
    claims table; the variants' rows are not counted)."""
    out = dict.fromkeys(VERDICTS, 0)
    for s in sections:
        for t in s.tables():
            if t.id == "claims-table":
                for row in t.rows:
                    if "(" not in row[0].text:
                        out[row[-1].text] += 1
    return out


# --- text ------------------------------------------------------------------------------------


def _g(value: float | None, digits: int = 3) -> str:
    """A figure to ``digits`` significant digits; ``failed`` for the worst (infinite)."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "-"
    if math.isinf(value):
        return "failed"
    return f"{value:.{digits}g}"


def _p(p: float | None) -> str:
    return "-" if p is None else f"{p:.2g}"


def change(mine: float | None, theirs: float | None, better: str) -> float | None:
    """The method's change against the rival in per cent, > 0 an improvement in the claim's
    direction, as the papers state theirs ((rival - method) / rival for lower is better)."""
    if mine is None or theirs is None or theirs == 0 or not math.isfinite(mine + theirs):
        return None
    sign = 1.0 if better == "higher" else -1.0
    return 100.0 * sign * (mine - theirs) / abs(theirs)


def _column(claim: Claim) -> Column | None:
    """The column of the claim's table holding the paper's figures of the claim, if any."""
    if claim.table is None:
        return None
    statistic = "value" if claim.statistic == "median" else claim.statistic
    return next((c for c in TABLES[claim.table].columns
                 if c.metric == claim.metric and c.statistic == statistic), None)  # fmt: skip


def paper_figure(claim: Claim, named: bool = True) -> str:
    """The paper's figures of the claim: method against its first rival, per paper case
    (``named``: after the two methods' names)."""
    column = _column(claim)
    if column is None or not claim.rivals:
        return "-"
    table = TABLES[claim.table]
    unit = f" {column.unit}" if column.unit and column.unit != "%" else ""
    index = table.columns.index(column)
    parts = []
    for case in claim.cases:
        rows = [[table.row(m, c) for c in claim.table_cases(case)]
                for m in (claim.method, claim.rivals[0])]
        if any(r is None or r.printed[index] is None for side in rows for r in side):
            continue
        mine, theirs = (", ".join(r.printed[index] for r in side) for side in rows)
        parts.append(f"{mine} vs {theirs}{unit}")
    if len(parts) > LISTED:
        return f"{len(parts)} cases ({table.label})"
    head = f"{claim.method} vs {claim.rivals[0]}: " if parts and named else ""
    return head + "; ".join(parts) if parts else "-"


def _figures(t: Test, claim: Claim) -> str:
    """Our change from the claim's statistic over every run (and over the runs that did not
    fail, when some did)."""
    a, b = t.sides
    text = _percent(change(a.figure, b.figure, claim.better))
    clean = _percent(change(a.clean, b.clean, claim.better))
    if (a.failed or b.failed) and (text, clean) != ("-", "-"):
        text += f" (without failures {clean})"
    return text


def _percent(value: float | None) -> str:
    """A change in per cent to one decimal (two significant digits beyond 10 000 %)."""
    if value is None:
        return "-"
    return f"{value:+.1e}" if abs(value) >= 1e4 else f"{round(value, 1) + 0.0:+.1f}"


def _ours(t: Test) -> str:
    a, b = t.sides
    failures = f", failed {a.failed}/{b.failed}" if a.failed or b.failed else ""
    return f"{_g(a.median)} ({_g(a.iqr, 2)}) vs {_g(b.median)} ({_g(b.iqr, 2)}){failures}"


def _effect(c: Comparison | None) -> str:
    if c is None:
        return "-"
    symbol = "r" if c.effect_name == inference.PAIRED_R else "δ"
    effect, low, high = (f"{round(x, 2) + 0.0:.2f}" for x in (c.effect, c.low, c.high))
    return f"{symbol} {effect} [{low}, {high}]"


def _label(t: Test, claim: Claim) -> str:
    """The comparison's case (a family's kind without the family: the claim names it) and
    its rival, when the claim has several."""
    rival = f" vs {t.rival}" if len(claim.rivals) > 1 else ""
    case = t.case.rpartition("/")[2]
    return f"{case}{rival}: " if len(claim.cases) > 1 or len(claim.rivals) > 1 else ""


def headline(v: Verdict) -> str:
    """Ours in one line: the comparison's medians, effect and interval (for several, how many
    are better and the effect of the most significant loss if there is one, else of the
    weakest: the highest corrected p); an absolute claim's runs meeting the target with the
    interval."""
    if v.reason and not (v.tests or v.tallies):
        return v.reason
    if v.tallies:
        n, met = sum(t.n for t in v.tallies), sum(t.met for t in v.tallies)
        ci = binomtest(met, n).proportion_ci(0.95, method="exact")
        return f"{met}/{n} runs ({100 * ci.low:.0f}-{100 * ci.high:.0f} %)"
    done = [t for t in v.tests if t.comparison is not None]
    if not done:
        return v.reason or "-"
    worse = [t for t in done if t.outcome == "worse"]
    if worse:  # the most significant loss decides
        shown, word = min(worse, key=lambda t: t.p), "worse"
    else:
        shown, word = max(done, key=lambda t: (t.p is None, t.p or 0.0)), "weakest"
    a, b = shown.sides
    if len(done) == 1:
        return f"{_g(a.median)} vs {_g(b.median)}, {_effect(shown.comparison)}"
    better = sum(t.outcome == "better" for t in done)
    return (f"{better}/{len(done)} better; {word} {shown.case}/{shown.rival} "
            f"{_effect(shown.comparison)}")


def _test_text(t: Test) -> str:
    short = "W" if t.comparison.test == inference.WILCOXON else "U"
    return f"{short} p {_p(t.p)}, {_effect(t.comparison)}"


def _row(v: Verdict, mine: Sequence[Verdict]) -> list[Cell]:
    """The claim's row; ``mine``: the verdicts of our variants of its method."""
    c = v.claim
    quote = c.quotes[0]
    paper = f"{PAPERS[c.paper].id} §{quote.section}: \u201c{quote.text}\u201d"
    if (figure := paper_figure(c)) != "-":
        paper += f" Figures: {figure}."
    stated = ", ".join(x for x in c.paper_change if x) if c.paper_change else ""
    tests = [t for t in v.tests if t.comparison is not None]
    if v.tallies:
        ours = "; ".join(f"{t.case}: {t.met}/{t.n} ({100 * t.low:.0f}-{100 * t.high:.0f} %)"
                         for t in v.tallies) if len(v.tallies) <= LISTED else headline(v)
        ours, change, test = ours + " runs meet it", "-", "Clopper-Pearson 95 %"
    elif tests and len(v.tests) <= LISTED:
        ours, change, test = ("; ".join(_label(t, c) + f(t) for t in tests) for f in (
            _ours, lambda t: _figures(t, c), _test_text))  # fmt: skip
        sizes = {(t.sides[0].n, t.sides[1].n) for t in tests}
        ours += (f"; n {'/'.join(map(str, sizes.pop()))}" if len(sizes) == 1 else
                 "; n " + ", ".join(f"{t.sides[0].n}/{t.sides[1].n}" for t in tests))
    elif tests:
        low, high = (_p(f(t.p or 1.0 for t in tests)) for f in (min, max))
        ours, change = headline(v), "-"
        test = f"{tests[0].comparison.test}: corrected p " + (low if low == high else
                                                              f"{low}-{high}")  # fmt: skip
    else:
        ours, change, test = v.reason or "-", "-", "-"
    if v.reason and (v.tests or v.tallies):
        ours += f" ({v.reason})"
    change = "; ".join([f"ours {change}"] * (change != "-") + [f"paper {stated}"] * bool(stated))
    variant = "; ".join(f"{m.claim.method}: {m.verdict}" for m in mine) or "-"
    return [Cell(c.id), Cell(paper), Cell(ours), Cell(change or "-", "num"), Cell(test),
            Cell(variant), Cell(v.verdict, CSS[v.verdict])]  # fmt: skip


def _case_rows(vs: Sequence[Verdict]) -> list[list[Cell]]:
    rows = []
    for v in vs:
        for t in v.tests:
            a, b = t.sides
            c = t.comparison
            p = "-" if c is None else f"{c.test}: {_p(c.p)}, {_p(t.p)}"
            rows.append([Cell(f"{v.claim.id}, {t.case} vs {t.rival}"),
                         Cell(_ours(t).partition(", failed")[0], "num"),
                         Cell(f"{a.n}/{b.n} ({a.failed}/{b.failed})", "num"),
                         Cell(_figures(t, v.claim), "num"), Cell(p), Cell(_effect(c)),
                         Cell(t.outcome)])  # fmt: skip
        for t in v.tallies:
            rows.append([Cell(f"{v.claim.id}, {t.case}"), Cell(f"{t.met} meet it", "num"),
                         Cell(f"{t.n}", "num"), Cell(t.note or "-"), Cell("Clopper-Pearson"),
                         Cell(f"{100 * t.low:.0f}-{100 * t.high:.0f} %"),
                         Cell("met" if t.met == t.n else "not met")])  # fmt: skip
    return rows


def section(results: Results) -> Section:
    vs = verdicts(results)
    mine = [v for v in vs if not v.variant]
    tally = dict.fromkeys(VERDICTS, 0)
    for v in mine:
        tally[v.verdict] += 1
    tested = sum(len([t for t in v.tests if t.comparison is not None]) for v in mine)
    s = Section("claims", "The papers' claims on our maps")
    s.paragraphs.append(
        f"Of {len(mine)} claims for the papers' own methods, "
        + ", ".join(f"{n} {k}" for k, n in tally.items() if n) + ". "
        f"Each relative claim compares the method with each rival in each case it covers: "
        "runs of the scene families paired by scene (Wilcoxon signed-rank, W; effect: the "
        "matched-pairs rank-biserial r), routes and functions as independent samples "
        "(Mann-Whitney U, U; effect: Cliff's delta, δ), a claim of variance or standard "
        "deviation on the runs' absolute deviations from their median. Effects lie in [-1, 1], "
        "> 0 the method better, with their 95 % bootstrap interval; a failed run (a colliding "
        "route, a run that collided or did not arrive) counts as the worst. "
        f"The {tested} p of the papers' methods are Holm-corrected together (our variants', "
        f"udwa+ and iwso+g, as a family of their own). A claim holds when the method is "
        f"better with corrected p < {ALPHA} against every rival in every case, does not hold "
        "when it is significantly worse in one, and is inconclusive otherwise; not testable "
        "when our set-up cannot move the metric (the reason is given), not tested when runs "
        "are missing. An absolute claim holds when every run meets its target (the share "
        "with its 95 % Clopper-Pearson interval). \"Our change\" is the papers' statistic of "
        "ours, as the paper states its change (> 0: better); docs/statistics.md.")
    s.blocks.append(Table(
        "claims-table", "Claims and verdicts",
        "One row per claim: the paper's words and figures (its method against its first "
        "rival), ours (medians with IQR of the method and the rival, the runs n of each, the "
        "failed runs), our change beside the paper's (per cent, > 0 better), the test (W, U) "
        "with its Holm-corrected p and the effect (r, δ) with its 95 % interval, the verdict "
        "for our variants of the method and the verdict; a claim of more than "
        f"{LISTED} comparisons shows the one that decides (all are in the appendix).",
        ["claim", "the paper", "ours", "change %", "test, effect", "our variants", "verdict"],
        [_row(v, [m for m in vs if m.variant and m.claim.id.startswith(v.claim.id + " (")])
         for v in mine]))  # fmt: skip
    s.blocks.append(Table(
        "claims-cases", "Claims: every comparison",
        "Each claim's comparison of the method with one rival in one case (a claim in "
        "brackets: for our variant of the method): the medians (IQR), the runs n (failed), "
        "our change %, the test with its p before and after Holm's correction, the effect "
        "[95 % interval] and the outcome. An absolute claim: its runs meeting the target, "
        "what the others did, and the 95 % Clopper-Pearson interval of the share.",
        ["claim, case", "medians (IQR)", "n (failed)", "our change %", "test: p, corrected",
         "effect [95 %]", "outcome"], _case_rows(vs),
        placement=APPENDIX))  # fmt: skip
    return s

