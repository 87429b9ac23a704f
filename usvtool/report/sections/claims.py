"""The report's claims section: each claim of the papers (:data:`usvtool.report.papers.CLAIMS`)
judged on our runs with statistics over seeds and scenes (docs/statistics.md), one row per
claim with its verdict and, in the appendix, every comparison.

The judging itself (the tests, Holm's correction, the verdicts) is
:mod:`usvtool.report.judging`'s: this module builds the rows and tables from its
verdicts (:class:`~usvtool.report.judging.Verdict`), and the texts the summary shares
(:func:`headline`, :func:`paper_figure`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from scipy.stats import binomtest

from usvtool.report import inference
from usvtool.report.data import Results
from usvtool.report.document import APPENDIX, Cell, Section, Table
from usvtool.report.inference import Comparison
from usvtool.report.judging import (
    ALPHA,
    EQUIVALENT,
    FAILS,
    HOLDS,
    INCONCLUSIVE,
    UNTESTABLE,
    UNTESTED,
    VERDICTS,
    Test,
    Verdict,
    paper_verdicts,
)
from usvtool.report.papers import PAPERS, TABLES, Claim, Column

CSS = {HOLDS: "holds", FAILS: "fails", EQUIVALENT: "equivalent", INCONCLUSIVE: "inconclusive",
       UNTESTABLE: "untestable", UNTESTED: "untested"}  # fmt: skip
#: A relative claim with more comparisons than this shows a digest in the claims table (every
#: comparison is in the appendix's table).
LISTED = 3


def counts(sections: list[Section], table: str = "claims-table") -> dict[str, int]:
    """How many claims of the claims table ``table`` have each verdict (the papers' own
    methods': the rows of our variants, ``id (variant)``, are not counted)."""
    out = dict.fromkeys(VERDICTS, 0)
    for s in sections:
        for t in s.tables():
            if t.id == table:
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
    """The paper's figures of the claim: method against its first rival the paper ran, per
    paper case (``named``: after the two methods' names)."""
    column = _column(claim)
    if column is None or not claim.rivals:
        return "-"
    table = TABLES[claim.table]
    # the first rival the paper ran (a context rival when the claim is judged on an ablation)
    rival = next((r for r in (*claim.rivals, *claim.context)
                  if any(row.method == r for row in table.rows)), None)  # fmt: skip
    if rival is None:
        return "-"
    unit = f" {column.unit}" if column.unit and column.unit != "%" else ""
    index = table.columns.index(column)
    parts = []
    for case in claim.cases:
        rows = [[table.row(m, c) for c in claim.table_cases(case)]
                for m in (claim.method, rival)]
        if any(r is None or r.printed[index] is None for side in rows for r in side):
            continue
        mine, theirs = (", ".join(r.printed[index] for r in side) for side in rows)
        parts.append(f"{mine} vs {theirs}{unit}")
    if len(parts) > LISTED:
        return f"{len(parts)} cases ({table.label})"
    head = f"{claim.method} vs {rival}: " if parts and named else ""
    return head + "; ".join(parts) if parts else "-"


def units(metric: str) -> str:
    """The unit of a results column, from its name's suffix (docs/metrics.md): ``m``, ``s``.

    >>> units("length_m"), units("arrival_time_s"), units("turns")
    ('m', 's', '')
    """
    return {"m": "m", "s": "s"}.get(metric.rpartition("_")[2], "") if "_" in metric else ""


def _raw(better: str, *values: float) -> tuple[float, ...]:
    """Improvements (> 0 better) as method - rival differences, in the same order."""
    sign = 1.0 if better == "higher" else -1.0
    return tuple(sign * v + 0.0 for v in values)


def _span(low: float, high: float, digits: int = 3) -> str:
    """``[low, high]`` to ``digits`` significant digits (``-inf``, ``inf`` as themselves: a
    distribution-free interval too few values can reach).

    >>> _span(-137.2, -106.8), _span(float("inf"), float("-inf"))
    ('[-137, -107]', '[-inf, inf]')
    """
    low, high = min(low, high), max(low, high)
    bound = [("-inf" if x < 0 else "inf") if math.isinf(x) else _g(x, digits) for x in (low, high)]
    return f"[{bound[0]}, {bound[1]}]"


def effect_text(t: Test, claim: Claim) -> str:
    """The effect in the metric's units, method - rival, with its 95 % interval: the
    Hodges-Lehmann shift for a claim judged by the rank test, else the difference of the
    claim's statistic (bootstrap); then the relative change of the claim's statistic with its
    interval (> 0 better, as the papers state theirs). '-' without measured values."""
    if t.statistic is None:
        return "-"
    unit = f" {units(claim.metric)}" if units(claim.metric) else ""
    d = t.statistic.difference
    if t.statistic.statistic == "median" and t.shift is not None:
        estimate, low, high = _raw(claim.better, t.shift.estimate, t.shift.low, t.shift.high)
        text = f"shift {_g(estimate)}{unit} {_span(low, high)}"
    else:
        estimate, low, high = _raw(claim.better, d.estimate, d.low, d.high)
        text = f"Δ{d.statistic} {_g(estimate)}{unit} {_span(low, high)}"
    if d.relative is not None:
        text += (f"; {_percent(100 * d.relative)} % "
                 f"[{_percent(100 * d.relative_low)}, {_percent(100 * d.relative_high)}]")
    return text


def failures_text(t: Test) -> str:
    """The failure comparison: each side's failed runs, the test and its corrected p; '' when
    neither side failed."""
    f = t.failures
    if f is None or not (t.sides[0].failed or t.sides[1].failed):
        return ""
    short = "McNemar" if f.cells.both is not None else "Fisher"
    return (f"failed {t.sides[0].failed}/{t.sides[0].n} vs {t.sides[1].failed}/{t.sides[1].n}, "
            f"{short} p {_p(t.failures_p)}")


def entered_text(t: Test, paired: bool) -> str:
    """Which runs enter the metric's test: the measured values of each side (pairs: those
    where both are), of the runs compared, and the informative pairs."""
    a, b = t.sides
    if paired:
        text = f"{a.measured} of {a.n} pairs measured"
        if t.entered is not None and t.entered.informative < a.measured:
            text += f", {t.entered.informative} informative"
        return text
    return f"n {a.measured}/{b.measured}" + (
        f" of {a.n}/{b.n}" if (a.measured, b.measured) != (a.n, b.n) else "")


def _percent(value: float | None) -> str:
    """A change in per cent to one decimal (two significant digits beyond 10 000 %)."""
    if value is None or math.isnan(value):
        return "-"
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return f"{value:+.1e}" if abs(value) >= 1e4 else f"{round(value, 1) + 0.0:+.1f}"


def _ours(t: Test, claim: Claim) -> str:
    """The claim's statistic of each side over the measured values (the median's IQR)."""
    a, b = t.sides
    name = "median" if claim.statistic == "value" else claim.statistic
    if name == "median":
        return f"median {_g(a.median)} ({_g(a.iqr, 2)}) vs {_g(b.median)} ({_g(b.iqr, 2)})"
    return f"{name} {_g(a.figure)} vs {_g(b.figure)}"


def _effect(c: Comparison | None) -> str:
    if c is None:
        return "-"
    symbol = "r" if c.effect_name == inference.PAIRED_R else "δ"
    effect, low, high = (f"{round(x, 2) + 0.0:.2f}" for x in (c.effect, c.low, c.high))
    return f"{symbol} {effect} [{low}, {high}]"


def _label(t: Test, claim: Claim) -> str:
    """The comparison's case (a family's kind without the family: the claim names it) and
    its rival, when the claim has several."""
    several = len(claim.rivals) + len(claim.context) > 1
    rival = f" vs {t.rival}" + (" (context)" if t.context else "") if several else ""
    case = t.case.rpartition("/")[2]
    return f"{case}{rival}: " if len(claim.cases) > 1 or several else ""


def headline(v: Verdict) -> str:
    """Ours in one line: the claim's own statistic of each side and the effect in the metric's
    units with its interval (for several comparisons, how many are better and the one that
    decides: the most significant loss if there is one, else the weakest, the highest
    corrected p), the failures beside; an absolute claim's runs meeting the target with the
    interval."""
    if v.reason and not (v.tests or v.tallies):
        return v.reason
    if v.tallies:
        n, met = sum(t.n for t in v.tallies), sum(t.met for t in v.tallies)
        ci = binomtest(met, n).proportion_ci(0.95, method="exact")
        return f"{met}/{n} runs ({100 * ci.low:.0f}-{100 * ci.high:.0f} %)"
    judged_ = [t for t in v.tests if not t.context and t.outcome != "missing"]
    if not judged_:
        return v.reason or "-"
    worse = [t for t in judged_ if t.outcome == "worse"]
    if worse:  # the most significant loss decides
        shown = min(worse, key=lambda t: min(p for p in (t.p, t.failures_p, 1.0)
                                             if p is not None))  # fmt: skip
    else:
        shown = max(judged_, key=lambda t: (t.p is None, t.p or 0.0))
    extra = "; ".join(x for x in (failures_text(shown),) if x)
    body = f"{_ours(shown, v.claim)}, {effect_text(shown, v.claim)}"
    if len(judged_) > 1:
        better = sum(t.outcome == "better" for t in judged_)
        word = "worse" if worse else "weakest"
        body = (f"{better}/{len(judged_)} better; {word} {shown.case}/{shown.rival}: "
                + body)  # fmt: skip
    return body + (f" ({extra})" if extra else "")


def _test_text(t: Test, claim: Claim) -> str:
    """The test of the claim's statistic with its corrected p and the rank effect, then the
    failures' test."""
    if t.statistic is None:
        text = "-"
    else:
        text = f"{t.statistic.test} p {_p(t.p)}, {_effect(t.comparison)}"
        if t.equivalence is not None and t.outcome == "equivalent":
            text += (f"; equivalent within ±{_g(t.equivalence.margin, 2)} (TOST p "
                     f"{_p(t.equivalence.p)})")
        if t.outcome == "neither" and t.needed is not None:
            text += f"; n for 80 % power {t.needed.n or f'> {t.needed.cap}'}"
    if failures := failures_text(t):
        text += f"; {failures}"
    return text


def judged(v: Verdict) -> tuple[str, str, str]:
    """The claim's judgement in three texts of its row: ours (the claim's statistic of each
    side, which runs entered the test), the effect in the metric's units with its interval and
    the relative change, and the tests with their corrected p, the rank effect, the failures;
    a digest for more than :data:`LISTED` comparisons; an absolute claim's runs meeting the
    target."""
    c = v.claim
    tests = [t for t in v.tests if t.statistic is not None or t.failures is not None]
    paired = c.kind == "runs"
    if v.tallies:
        ours = "; ".join(f"{t.case}: {t.met}/{t.n} ({100 * t.low:.0f}-{100 * t.high:.0f} %)"
                         for t in v.tallies) if len(v.tallies) <= LISTED else headline(v)
        share = "" if c.share >= 1 else f" (asked: {100 * c.share:g} % of them)"
        ours, effect, test = ours + " runs meet it" + share, "-", "Clopper-Pearson 95 %"
    elif tests and len(v.tests) <= LISTED:
        ours = "; ".join(f"{_label(t, c)}{_ours(t, c)}, {entered_text(t, paired)}"
                         for t in tests)  # fmt: skip
        effect = "; ".join(_label(t, c) + effect_text(t, c) for t in tests)
        test = "; ".join(_label(t, c) + _test_text(t, c) for t in tests)
    elif tests:
        ps = [t.p for t in tests if t.p is not None] or [1.0]
        low, high = _p(min(ps)), _p(max(ps))
        ours, effect = headline(v), "-"
        named = next((t.statistic.test for t in tests if t.statistic is not None), "-")
        test = f"{named}: corrected p " + (low if low == high else f"{low}-{high}")
    else:
        ours, effect, test = v.reason or "-", "-", "-"
    if v.reason and (v.tests or v.tallies):
        ours += f" ({v.reason})"
    if v.edges:
        ours += f". {v.edges[0].upper()}{v.edges[1:]}."
    return ours, effect, test


def _row(v: Verdict, mine: Sequence[Verdict]) -> list[Cell]:
    """The claim's row; ``mine``: the verdicts of our variants of its method."""
    c = v.claim
    quote = c.quotes[0]
    paper = f"{PAPERS[c.paper].id} §{quote.section}: \u201c{quote.text}\u201d"
    if (figure := paper_figure(c)) != "-":
        paper += f" Figures: {figure}."
    stated = ", ".join(x for x in c.paper_change if x) if c.paper_change else ""
    if stated:
        paper += f" Change: {stated} %."
    ours, effect, test = judged(v)
    variant = "; ".join(f"{m.claim.method}: {m.verdict}" for m in mine) or "-"
    return [Cell(c.id), Cell(paper), Cell(ours), Cell(effect, "num"), Cell(test),
            Cell(variant), Cell(v.verdict, CSS[v.verdict])]  # fmt: skip


def case_rows(vs: Sequence[Verdict]) -> list[list[Cell]]:
    """Every comparison (claim x case x rival) and every absolute claim's case, a row each."""
    rows = []
    for v in vs:
        paired = v.claim.kind == "runs"
        for t in v.tests:
            a, b = t.sides
            p = "-" if t.statistic is None else (
                f"{t.statistic.test}: {_p(t.statistic.p)}, "
                + ("context" if t.context else _p(t.p)))  # fmt: skip
            rival = f"{t.rival} (context)" if t.context else t.rival
            rows.append([Cell(f"{v.claim.id}, {t.case} vs {rival}"),
                         Cell(_ours(t, v.claim), "num"),
                         Cell(f"{entered_text(t, paired)}; failed {a.failed}/{b.failed}", "num"),
                         Cell(effect_text(t, v.claim), "num"), Cell(p),
                         Cell(_effect(t.comparison)), Cell(failures_text(t) or "-"),
                         Cell(t.outcome)])  # fmt: skip
        for t in v.tallies:
            rows.append([Cell(f"{v.claim.id}, {t.case}"), Cell(f"{t.met} meet it", "num"),
                         Cell(f"{t.n}", "num"), Cell(t.note or "-"), Cell("Clopper-Pearson"),
                         Cell(f"{100 * t.low:.0f}-{100 * t.high:.0f} %"), Cell("-"),
                         Cell("met" if t.met == t.n else "not met")])  # fmt: skip
    return rows


def tested(vs: Sequence[Verdict], failures: bool = False) -> int:
    """How many p the Holm family of ``vs`` corrects: every defined p of their metrics'
    comparisons (``failures``: of their failure comparisons), context rivals left out."""
    return sum((t.failures is not None and t.failures.p is not None) if failures else
               (t.statistic is not None and t.statistic.p is not None)
               for v in vs for t in v.tests if not t.context)  # fmt: skip


def method_text() -> str:
    """How a relative claim is judged, in a paragraph (docs/statistics.md)."""
    return (
        "Each relative claim compares the method with each rival in each case it covers, runs "
        "of the scene families paired by scene, routes and functions as independent samples, "
        "in two comparisons. The failures (a run that collided, never arrived or whose "
        "controller failed; a route through an obstacle) are their own outcome: exact "
        "McNemar on scene pairs, Fisher's exact test otherwise. The metric is tested on the "
        "measured values only: a run that collided or whose controller failed, or a "
        "colliding route, measures nothing and is left out (a run that only never arrived "
        "keeps its closest distance); which runs entered is given. The test is the one of "
        "the statistic the claim names: the rank test for a median (Wilcoxon signed-rank "
        "paired, Mann-Whitney U otherwise, exact up to 50 informative pairs or 100 runs), "
        "the permutation test of the means for a mean, Brown-Forsythe for a variance or "
        "standard deviation, a bootstrap of the best run for a best run. The effect is given "
        "in the metric's units, method - rival, with its 95 % interval (the Hodges-Lehmann "
        "shift for a median, else the bootstrap of the statistic's difference), the relative "
        "change (> 0 better, as the papers state theirs), and the rank effect (r paired, δ "
        "Cliff's delta; > 0 better) with its bootstrap interval.")


def section(results: Results) -> Section:
    vs = paper_verdicts(results)
    mine = [v for v in vs if not v.variant]
    tally = dict.fromkeys(VERDICTS, 0)
    for v in mine:
        tally[v.verdict] += 1
    s = Section("claims", "The papers' claims on our maps")
    s.paragraphs.append(
        f"Of {len(mine)} claims for the papers' own methods, "
        + ", ".join(f"{n} {k}" for k, n in tally.items() if n) + ". " + method_text() + " "
        f"The {tested(mine)} p of the papers' methods' metric comparisons are Holm-corrected "
        f"together, the {tested(mine, failures=True)} p of their failure comparisons apart; "
        "our variants' (udwa+, iwso+g) are families of their own. A claim holds "
        f"when the method is better with corrected p < {ALPHA} against every rival in every "
        "case, does not hold when it is significantly worse in one or fails significantly "
        "more often, is equivalent when every comparison lies within the metric's smallest "
        "effect of interest (TOST at 0.05 each), and is inconclusive otherwise, with the n a "
        "group that would give 80 % power at the family's first Holm step; not testable when "
        "our set-up cannot move the metric (the reason is given), not tested when runs are "
        "missing. A rival marked context is shown, outside the verdict and the correction. An "
        "absolute claim holds when every run meets its target (the share with its 95 % "
        "Clopper-Pearson interval); docs/statistics.md.")
    s.blocks.append(Table(
        "claims-table", "Claims and verdicts",
        "One row per claim: the paper's words, figures and stated change; ours (the claim's "
        "statistic of the method and the rival over the measured runs, which runs entered), "
        "the effect in the metric's units (method - rival) with its 95 % interval and the "
        "relative change (> 0 better), the tests with their Holm-corrected p and the rank "
        "effect, the failures' test, the verdict for our variants of the method and the "
        f"verdict; a claim of more than {LISTED} comparisons shows the one that decides (all "
        "are in the appendix).",
        ["claim", "the paper", "ours", "effect [95 %]", "tests", "our variants", "verdict"],
        [_row(v, [m for m in vs if m.variant and m.claim.id.startswith(v.claim.id + " (")])
         for v in mine]))  # fmt: skip
    s.blocks.append(Table(
        "claims-cases", "Claims: every comparison",
        "Each claim's comparison of the method with one rival in one case (a claim in "
        "brackets: for our variant of the method): the claim's statistic of each side, which "
        "runs entered and the failed runs, the effect in units [95 %] with the relative "
        "change, the test with its p before and after Holm's correction, the rank effect "
        "[95 % interval], the failures' test and the outcome. An absolute claim: its runs "
        "meeting the target, what the others did, and the 95 % Clopper-Pearson interval of "
        "the share.",
        ["claim, case", "ours", "runs", "effect [95 %]", "test: p, corrected", "rank effect",
         "failures", "outcome"], case_rows(vs),
        placement=APPENDIX))  # fmt: skip
    return s
