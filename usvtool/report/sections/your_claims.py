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
from usvtool.report.sections.claims import CSS, LISTED, case_rows, judged

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
    """A user's claim's row: its id, the claim in words, ours, our change, the test and the
    verdict."""
    ours, change, test = judged(v)
    return [Cell(v.claim.id), Cell(statement(v.claim)), Cell(ours), Cell(change, "num"),
            Cell(test), Cell(v.verdict, CSS[v.verdict])]  # fmt: skip


def section(results: Results) -> Section | None:
    vs = user_verdicts(results)
    if not vs:
        return None
    tally = dict.fromkeys(VERDICTS, 0)
    for v in vs:
        tally[v.verdict] += 1
    tested = sum(t.comparison is not None and t.comparison.p is not None
                 for v in vs for t in v.tests)  # fmt: skip
    s = Section("your-claims", "Your claims")
    s.paragraphs.append(
        f"The {len(vs)} claims of the pipelines that ran these results (their claims:, "
        "docs/pipelines.md), judged as the papers' claims are (the next section, "
        "docs/statistics.md): " + ", ".join(f"{n} {k}" for k, n in tally.items() if n) + ". "
        "Runs of the scene families are paired by scene (Wilcoxon signed-rank, W; effect r), "
        "routes and functions compared as independent samples (Mann-Whitney U, U; effect "
        "Cliff's δ), a variance or standard deviation on the runs' absolute deviations from "
        "their median; effects lie in [-1, 1], > 0 the method better, with their 95 % "
        "bootstrap interval; a failed run counts as the worst. "
        f"The {tested} p of these claims are Holm-corrected together, as a family of their own: "
        "they change no verdict on the papers' claims, nor the papers' on theirs. A claim "
        f"holds when the method is better with corrected p < {ALPHA} against every rival in "
        "every case, does not hold when it is significantly worse in one, and is inconclusive "
        "otherwise; not tested when runs are missing. An absolute claim holds when every run "
        "meets its target (or, when it asks for a share of the runs, when each case's 95 % "
        "Clopper-Pearson interval lies at or above it)."
    )
    s.blocks.append(Table(
        TABLE, "Your claims and their verdicts",
        "One row per claim: the claim, ours (medians with IQR of the method and the rival, "
        "the runs n of each, the failed runs; or the runs meeting an absolute claim's "
        "target), our change (per cent of the claim's statistic, > 0 better), the test (W, U) "
        "with its Holm-corrected p and the effect (r, δ) with its 95 % interval, and the "
        f"verdict; a claim of more than {LISTED} comparisons shows the one that decides (all "
        "are in the appendix).",
        ["claim", "what it says", "ours", "change %", "test, effect", "verdict"],
        [row(v) for v in vs]))  # fmt: skip
    s.blocks.append(Table(
        "your-claims-cases", "Your claims: every comparison",
        "Each claim's comparison of the method with one rival in one case: the medians (IQR), "
        "the runs n (failed), our change %, the test with its p before and after Holm's "
        "correction, the effect [95 % interval] and the outcome. An absolute claim: its runs "
        "meeting the target, what the others did, and the 95 % Clopper-Pearson interval of "
        "the share.",
        ["claim, case", "medians (IQR)", "n (failed)", "our change %", "test: p, corrected",
         "effect [95 %]", "outcome"], case_rows(vs), placement=APPENDIX))  # fmt: skip
    return s
