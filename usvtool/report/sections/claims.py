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

CSS = {HOLDS: "holds", FAILS: "fails", INCONCLUSIVE: "inconclusive", UNTESTABLE: "untestable",
       UNTESTED: "untested"}  # fmt: skip
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


def judged(v: Verdict) -> tuple[str, str, str]:
    """The claim's judgement in three texts of its row: ours (the medians with the IQR of each
    side and the runs n per comparison, or the runs meeting an absolute claim's target, or a
    digest of many comparisons), our change in per cent (- for none) and the test with its
    corrected p and effect."""
    c = v.claim
    tests = [t for t in v.tests if t.comparison is not None]
    if v.tallies:
        ours = "; ".join(f"{t.case}: {t.met}/{t.n} ({100 * t.low:.0f}-{100 * t.high:.0f} %)"
                         for t in v.tallies) if len(v.tallies) <= LISTED else headline(v)
        share = "" if c.share >= 1 else f" (asked: {100 * c.share:g} % of them)"
        ours, change, test = ours + " runs meet it" + share, "-", "Clopper-Pearson 95 %"
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
    return ours, change, test


def _row(v: Verdict, mine: Sequence[Verdict]) -> list[Cell]:
    """The claim's row; ``mine``: the verdicts of our variants of its method."""
    c = v.claim
    quote = c.quotes[0]
    paper = f"{PAPERS[c.paper].id} §{quote.section}: \u201c{quote.text}\u201d"
    if (figure := paper_figure(c)) != "-":
        paper += f" Figures: {figure}."
    stated = ", ".join(x for x in c.paper_change if x) if c.paper_change else ""
    ours, change, test = judged(v)
    change = "; ".join([f"ours {change}"] * (change != "-") + [f"paper {stated}"] * bool(stated))
    variant = "; ".join(f"{m.claim.method}: {m.verdict}" for m in mine) or "-"
    return [Cell(c.id), Cell(paper), Cell(ours), Cell(change or "-", "num"), Cell(test),
            Cell(variant), Cell(v.verdict, CSS[v.verdict])]  # fmt: skip


def case_rows(vs: Sequence[Verdict]) -> list[list[Cell]]:
    """Every comparison (claim x case x rival) and every absolute claim's case, a row each."""
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
    vs = paper_verdicts(results)
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
         "effect [95 %]", "outcome"], case_rows(vs),
        placement=APPENDIX))  # fmt: skip
    return s

