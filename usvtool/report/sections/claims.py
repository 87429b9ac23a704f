"""The report's claims section: each claim of the papers (:data:`usvtool.report.papers.CLAIMS`)
tested on our results, with the figures it rests on and a plain verdict.

A relative claim **holds** when, in every case it covers, the method's statistic over our seeds
is strictly better than every rival's; it **does not hold** when it is worse or equal in some
case; it is **not tested** when some case lacks our runs of the method or a rival. An absolute
claim holds when every run of the method in every case reaches its target: a number, or another
metric of the same run (``compliant`` equal to ``judged``). ``collision`` has a row only when the
ship hit something, so an absent row counts as 0.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from usvtool.report.data import JobResults, Results, statistic
from usvtool.report.document import Cell, Section, Table
from usvtool.report.papers import CLAIMS, PAPERS, Claim

HOLDS, FAILS, UNTESTED = "holds", "does not hold", "not tested"
#: Metrics with a row only when something happened (absent: 0).
EVENTS = ("collision",)


@dataclass(frozen=True)
class Verdict:
    claim: Claim
    verdict: str
    evidence: list[str]  # one line per case: our figures


def _run_value(job: JobResults, metric: str) -> float | None:
    if metric in EVENTS:
        return 1.0 if job.text(metric) else 0.0
    return job.number(metric)


def _absolute(results: Results, c: Claim) -> Verdict:
    evidence, verdict = [], HOLDS
    for case in c.cases:
        jobs = results.select(c.kind, case, c.method)
        if not jobs:
            evidence.append(f"{case}: no run")
            verdict = UNTESTED if verdict == HOLDS else verdict
            continue
        good = 0
        for j in jobs:
            value = _run_value(j, c.metric)
            target = _run_value(j, c.target) if isinstance(c.target, str) else c.target
            good += value is not None and target is not None and value == target
        evidence.append(f"{case}: {good}/{len(jobs)} runs")
        if good < len(jobs):
            verdict = FAILS
    return Verdict(c, verdict, evidence)


def _better(a: float, b: float, direction: str) -> bool:
    return a < b if direction == "lower" else a > b


def _relative(results: Results, c: Claim) -> Verdict:
    evidence, verdict = [], HOLDS
    for case in c.cases:
        mine = statistic(results, c.kind, case, c.method, c.metric, c.statistic)
        rivals = {r: statistic(results, c.kind, case, r, c.metric, c.statistic)
                  for r in c.rivals}  # fmt: skip
        shown = ", ".join(f"{r} {_fmt(v)}" for r, v in rivals.items())
        evidence.append(f"{case}: {c.method} {_fmt(mine)} against {shown}")
        if mine is None or any(v is None for v in rivals.values()):
            verdict = UNTESTED if verdict == HOLDS else verdict
        elif not all(_better(mine, v, c.better) for v in rivals.values()):
            verdict = FAILS
    return Verdict(c, verdict, evidence)


def judge(results: Results, claim: Claim) -> Verdict:
    return _relative(results, claim) if claim.rivals else _absolute(results, claim)


def _fmt(value: float | None) -> str:
    return "-" if value is None else f"{value:.4g}"


def variants(results: Results, claim: Claim) -> list[str]:
    """Our clearly named variants of the claim's method run in the claim's cases (``udwa+`` of
    ``udwa``, ``iwso+s`` of ``iwso``): the claim is judged for each too, beside the paper's."""
    run = {m for case in claim.cases for m in results.methods(claim.kind, case)}
    return sorted(m for m in run if m.partition("+")[0] == claim.method and m != claim.method)


def verdicts(results: Results) -> list[Verdict]:
    """Every claim for the paper's method, each followed by the same claim for our variants."""
    return [judge(results, c2) for c in CLAIMS
            for c2 in (c, *(replace(c, id=f"{c.id} ({m})", method=m)
                            for m in variants(results, c)))]  # fmt: skip


def counts(sections: list[Section]) -> dict[str, int]:
    """How many of the papers' claims hold, do not hold and are not tested for the papers' own
    methods (from the claims table; the variants' rows are not counted)."""
    out = {HOLDS: 0, FAILS: 0, UNTESTED: 0}
    for s in sections:
        for t in s.tables():
            if t.id == "claims-table":
                for row in t.rows:
                    if "(" not in row[0].text:
                        out[row[-1].text] += 1
    return out


def section(results: Results) -> Section:
    rows = []
    for v in verdicts(results):
        c = v.claim
        stated = ", ".join(x for x in c.paper_change if x) if c.paper_change else ""
        css = {HOLDS: "holds", FAILS: "fails", UNTESTED: "untested"}[v.verdict]
        quote = c.quotes[0]
        rows.append([
            Cell(c.id), Cell(f"{PAPERS[c.paper].id} §{quote.section}: \u201c{quote.text}\u201d"),
            Cell(f"{c.statistic} {c.metric}, {c.better} is better"),
            Cell("; ".join(v.evidence)), Cell(f"{stated} %" if stated else "-", "num paper"),
            Cell(v.verdict, css),
        ])  # fmt: skip
    s = Section("claims", "The papers' claims on our maps")
    mine = [r for r in rows if "(" not in r[0].text]
    held = sum(r[-1].text == HOLDS for r in mine)
    s.paragraphs.append(
        f"{held} of {len(mine)} claims hold on our results for the papers' own methods. Rows "
        "whose claim is followed by a variant in brackets judge the same claim for our clearly "
        "named variant of the method (docs/controllers.md, docs/planning.md), which does not "
        "change the verdict on the paper's. A claim holds when the method is "
        "strictly better than every rival in every case it covers (statistics over our seeds); "
        "a tie does not hold; a claim whose runs are missing is not tested. The papers' stated "
        "changes are shown for reference (docs/papers.md lists where they disagree with the "
        "papers' own tables).")
    s.blocks.append(Table("claims-table", "Claims and verdicts",
                          "Each claim with the paper's words, the figures it rests on and the "
                          "verdict.", ["claim", "paper", "figure", "ours", "paper's change",
                                       "verdict"], rows))  # fmt: skip
    return s
