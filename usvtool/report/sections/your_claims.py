"""The report's "Your claims" section: the claims of the pipelines behind the results tables
(``claims:``, docs/pipelines.md; the ``claims.json`` beside each table), judged as the papers'
are (:func:`usvtool.report.judging.user_verdicts`: the same comparisons, the same verdicts, and
Holm's correction within a family of their own, so that they change no verdict on the papers'
claims nor the papers' on theirs). Placed before the papers' claims; left out when the tables
have no claims."""

from __future__ import annotations

from usvtool.report.data import Results
from usvtool.report.document import APPENDIX, Cell, Section, Table
from usvtool.report.judging import ALPHA, VERDICTS, Verdict, user_verdicts
from usvtool.report.papers import Claim
from usvtool.report.sections.claims import CSS, LISTED, case_rows, judged, method_text, tested

#: The id of the section's claims table (:func:`usvtool.report.sections.claims.counts`).
TABLE = "your-claims-table"


def statement(c: Claim) -> str:
    """The claim in words.

    >>> from usvtool.report.data import as_claim
    >>> from usvtool.pipeline import ClaimSpec
    >>> statement(as_claim(ClaimSpec("a", "runs", "udwa+", ("udwa",), "closest_distance_m",
    ...                              "higher", "median", ("emergency",))))
    'udwa+ against udwa: closest_distance_m higher (median) in emergency'
    >>> statement(as_claim(ClaimSpec("b", "runs", "udwa+", (), "collision", "lower", "every",
    ...                              ("imazu", "wind/halves"), 0.0, 0.9)))
    'udwa+: collision at most 0 in 90 % of the runs of imazu, wind/halves'
    """
    cases = ", ".join(c.cases)
    if c.rivals:
        return (f"{c.method} against {', '.join(c.rivals)}: {c.metric} {c.better} "
                f"({c.statistic}) in {cases}")  # fmt: skip
    target = c.target if isinstance(c.target, str) else f"{c.target:g}"
    runs = "every run" if c.share >= 1 else f"{100 * c.share:g} % of the runs"
    bound = "at most" if c.better == "lower" else "at least"
    return f"{c.method}: {c.metric} {bound} {target} in {runs} of {cases}"


def row(v: Verdict) -> list[Cell]:
    """A user's claim's row: its id, the claim in words, ours, the effect in the metric's
    units, the tests and the verdict (:func:`usvtool.report.sections.claims.judged`)."""
    ours, effect, test = judged(v)
    return [Cell(v.claim.id), Cell(statement(v.claim)), Cell(ours), Cell(effect, "num"),
            Cell(test), Cell(v.verdict, CSS[v.verdict])]  # fmt: skip


def section(results: Results) -> Section | None:
    vs = user_verdicts(results)
    if not vs:
        return None
    tally = dict.fromkeys(VERDICTS, 0)
    for v in vs:
        tally[v.verdict] += 1
    failed = tested(vs, failures=True)
    s = Section("your-claims", "Your claims")
    s.paragraphs.append(
        f"The {len(vs)} claims of the pipelines that ran these results (their claims:, "
        "docs/pipelines.md), judged as the papers' claims are (the next section, "
        "docs/statistics.md): " + ", ".join(f"{n} {k}" for k, n in tally.items() if n) + ". "
        + method_text() + " "
        f"The {tested(vs)} p of these claims' metric comparisons are Holm-corrected together"
        + (f", the {failed} p of their failure comparisons apart" if failed else "")
        + ", in families of their own: they change no verdict on the papers' claims, nor the "
        "papers' on theirs. "
        f"A claim holds when the method is better with corrected p < {ALPHA} against every "
        "rival in every case, does not hold when it is significantly worse in one or fails "
        "significantly more often, is equivalent when every comparison lies within the "
        "metric's smallest effect of interest (TOST at 0.05 each), and is inconclusive "
        "otherwise, with the n a group that would give 80 % power; not tested when runs are "
        "missing. An absolute claim holds when every run meets its target (or, when it asks "
        "for a share of the runs, when each case's 95 % Clopper-Pearson interval lies at or "
        "above it)."
    )
    s.blocks.append(Table(
        TABLE, "Your claims and their verdicts",
        "One row per claim: the claim; ours (the claim's statistic of the method and the "
        "rival over the measured runs, which runs entered; or the runs meeting an absolute "
        "claim's target), the effect in the metric's units (method - rival) with its 95 % "
        "interval and the relative change (> 0 better), the tests with their Holm-corrected p "
        "and the rank effect (r, δ) with its 95 % interval, the failures' test, and the "
        f"verdict; a claim of more than {LISTED} comparisons shows the one that decides (all "
        "are in the appendix).",
        ["claim", "what it says", "ours", "effect [95 %]", "tests", "verdict"],
        [row(v) for v in vs]))  # fmt: skip
    s.blocks.append(Table(
        "your-claims-cases", "Your claims: every comparison",
        "Each claim's comparison of the method with one rival in one case: the claim's "
        "statistic of each side, which runs entered and the failed runs, the effect in units "
        "[95 %] with the relative change, the test with its p before and after Holm's "
        "correction, the rank effect [95 % interval], the failures' test and the outcome. An "
        "absolute claim: its runs meeting the target, what the others did, and the 95 % "
        "Clopper-Pearson interval of the share.",
        ["claim, case", "ours", "runs", "effect [95 %]", "test: p, corrected", "rank effect",
         "failures", "outcome"], case_rows(vs), placement=APPENDIX))  # fmt: skip
    return s
