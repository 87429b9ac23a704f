"""The report's part for the methods that are not the papers': our variants (``udwa+``,
``iwso+g``, ``ssa-redraw`` ...), the exact planners and any plugin's method, every method of the
results that no paper table or claim names (:data:`PAPER_METHODS`).

Per method, a subsection: its outcomes in every group of cases it ran (a chart's routes, a
scene family's runs, the Imazu cases among them, the bundled scenarios together, a benchmark
function): the runs, the failures, the median and IQR of the main metrics (:data:`MAIN`) over
the runs that did not fail and, for runs, their encounters' COLREGs counts; then, in the
appendix, its effect against each paper method of the same kind that ran there, for each main
metric, by the judging module's comparison (:func:`usvtool.report.judging.comparison`: paired
by scene for runs, independent otherwise, a failed run the worst), with the uncorrected p: a
description, not a claim (a claim of the pipeline is judged in "Your claims"). Tables only,
no figure: the part adds a few hundredths of a second to the report.
"""

from __future__ import annotations

import re

from usvtool.report import inference
from usvtool.report.data import JobResults, Results
from usvtool.report.document import APPENDIX, Cell, Section, Table
from usvtool.report.judging import ALPHA, Test, comparison
from usvtool.report.papers import CLAIMS, TABLES, Claim
from usvtool.report.runs import TALLY_COLUMNS, RunTally, is_family
from usvtool.results import file_name

#: Every method a paper's table or claim names: the papers' methods.
PAPER_METHODS = frozenset(
    {r.method for t in TABLES.values() for r in t.rows}
    | {m for c in CLAIMS for m in (c.method, *c.rivals)}
)
#: The main metrics of each kind of job: (metric, better, heading, decimals).
MAIN = {
    "routes": (("length_m", "lower", "length (m)", 1), ("turns", "lower", "turns", 1)),
    "runs": (
        ("arrival_time_s", "lower", "arrival (s)", 1),
        ("closest_distance_m", "higher", "closest (m)", 1),
    ),
    "functions": (("final_cost", "lower", "final cost", 3),),
}
#: The group of the bundled scenarios' runs (cases without ``/``), shown together.
BUNDLED = "bundled scenarios"
#: A comparison needs this many runs on each side.
LEAST = 3
FAILED = {"routes": "through an obstacle", "runs": "failed", "functions": "failed"}


def others(results: Results) -> list[str]:
    """The methods of the results that are not the papers' (:data:`PAPER_METHODS`), in the
    report's order (the routes', the runs', the functions')."""
    seen: dict[str, None] = {}
    for kind in MAIN:
        for m in results.methods(kind):
            if m not in PAPER_METHODS:
                seen.setdefault(m)
    return list(seen)


def group(kind: str, case: str) -> str:
    """The group of cases a job is shown in: a scene family's entry (``emergency`` of
    ``emergency/head-on/s007``), :data:`BUNDLED` for a bundled scenario, else the case."""
    if kind == "runs":
        return case.split("/")[0] if is_family(case) else BUNDLED
    return case


def groups(results: Results, kind: str, method: str) -> dict[str, list[JobResults]]:
    """The method's jobs of ``kind`` by :func:`group`, the groups sorted (the bundled
    scenarios last)."""
    found: dict[str, list[JobResults]] = {}
    for j in results.select(kind, method=method):
        found.setdefault(group(kind, j.case), []).append(j)
    return dict(sorted(found.items(), key=lambda g: (g[0] == BUNDLED, _natural(g[0]))))


def _natural(name: str) -> tuple:
    """F2 before F10."""
    return tuple((0, int(t)) if t.isdigit() else (1, t) for t in re.split(r"(\d+)", name))


def _figure(values: list[float], digits: int) -> str:
    """``median (IQR)`` of the values, the value alone for one."""
    if not values:
        return "-"
    if len(values) == 1:
        return f"{values[0]:.{digits}f}" if abs(values[0]) < 1e6 else f"{values[0]:.2e}"
    median, iqr = inference.median(values), inference.iqr(values)
    return f"{median:.{digits}f} ({iqr:.{digits}f})" if abs(median) < 1e6 else (
        f"{median:.2e} ({iqr:.2e})")  # fmt: skip


def comparisons(results: Results, kind: str, method: str,
                name: str) -> list[tuple[str, str, Test]]:  # fmt: skip
    """The method against each paper method of the same kind that ran in the group ``name``
    (:data:`BUNDLED` has none: its scenarios are illustrations), per main metric: (rival,
    metric, the comparison) when both sides have :data:`LEAST` runs or more."""
    if name == BUNDLED:
        return []
    if len(results.group(kind, name, method)) < LEAST:
        return []
    rivals = [m for m in results.methods(kind) if m in PAPER_METHODS and m != method
              and len(results.group(kind, name, m)) >= LEAST]  # fmt: skip
    return [(rival, metric, test) for rival in rivals
            for metric, test in metric_tests(results, kind, method, rival, name)]  # fmt: skip


def metric_tests(results: Results, kind: str, method: str, rival: str,
                 name: str) -> list[tuple[str, Test]]:  # fmt: skip
    """The method against ``rival`` in the group of cases ``name``, per main metric
    (:data:`MAIN`): (metric, the judging module's comparison by the median: paired by scene for
    runs, independent otherwise, a failed run the worst; its p uncorrected) when both sides
    have :data:`LEAST` runs or more in it (after pairing). Shared with the baselines' section
    (:mod:`.baselines`)."""
    if kind == "runs" and len(results.pairs(kind, name, method, rival)) < LEAST:
        return []  # too few pairs whatever their values: spare the test's work
    out = []
    for metric, better, _, _ in MAIN[kind]:
        claim = Claim(f"{method} vs {rival}", "", (), kind, metric, "median", better, method,
                      (rival,), (name,))  # fmt: skip
        test = comparison(results, claim, name, rival)
        if test.comparison is not None and min(s.n for s in test.sides) >= LEAST:
            out.append((metric, test))
    return out


def _digest(found: list[tuple[str, str, Test]], kind: str) -> str:
    """How many paper methods the method beats and loses to per main metric (uncorrected p <
    :data:`ALPHA`)."""
    parts = []
    for metric, _, heading, _ in MAIN[kind]:
        mine = [t for _, m, t in found if m == metric]
        if not mine:
            continue
        won = sum(t.outcome == "better" for t in mine)
        lost = sum(t.outcome == "worse" for t in mine)
        parts.append(f"{heading.split(' (')[0]}: better than {won}, worse than {lost} of "
                     f"{len(mine)}")  # fmt: skip
    return "; ".join(parts) or "-"


def outcomes(results: Results, kind: str, method: str,
             tests: dict[str, list]) -> Table:  # fmt: skip
    """The method's runs per group: n, failures, median (IQR) of each main metric over the
    runs that did not fail (runs: their outcomes and COLREGs counts), and the digest of its
    comparisons with the papers' methods."""
    rows = []
    for name, jobs in groups(results, kind, method).items():
        failed = sum(j.failed for j in jobs)
        cells = [Cell(name), Cell(str(len(jobs)), "num")]
        if kind == "runs":
            cells += RunTally.of(jobs).cells()
        else:
            cells.append(Cell(str(failed), "num" + (" fails" if failed else "")))
        for metric, _, _, digits in MAIN[kind]:
            values = [v for j in jobs if j.succeeded and (v := j.number(metric)) is not None]
            cells.append(Cell(_figure(values, digits), "num"))
        cells.append(Cell(_digest(tests.get(name, []), kind)))
        rows.append(cells)
    counts = TALLY_COLUMNS if kind == "runs" else [FAILED[kind]]
    columns = ["cases", "runs", *counts, *(f"{h}: median (IQR)" for _, _, h, _ in MAIN[kind]),
               "against the papers' methods"]  # fmt: skip
    what = {"routes": "routes", "runs": "runs", "functions": "benchmark-function runs"}[kind]
    return Table(f"other-{file_name(method)}-{kind}", f"{method}: its {what}",
                 CAPTIONS[kind] + " Against the papers' methods: how many of those that ran "
                 "the same cases it is better or worse than (effect > 0 or < 0 with uncorrected "
                 f"p < {ALPHA}; each comparison in the appendix).", columns, rows)  # fmt: skip


#: What an outcomes table shows, per kind.
CAPTIONS = {
    "routes": "Per chart: the routes, those through an obstacle (failures), the medians (IQR) "
    "over the collision-free routes.",
    "runs": f"Per scene family ({BUNDLED} together): the runs, their outcomes (a run that "
    "collided or did not arrive is a failure) and their encounters' COLREGs counts, the "
    "medians (IQR) over the runs that arrived without collision.",
    "functions": "Per function: the runs and the median (IQR) of the final cost.",
}


def effects(method: str, kind: str, tests: dict[str, list]) -> Table | None:
    """Every comparison of the method with a paper method (:func:`comparisons`)."""
    rows = []
    for name, found in tests.items():
        for rival, metric, t in found:
            a, b = t.sides
            c = t.comparison
            rows.append([Cell(name), Cell(rival), Cell(metric),
                         Cell(f"{a.n}/{b.n} ({a.failed}/{b.failed})", "num"),
                         Cell(f"{value_text(a.median)} vs {value_text(b.median)}", "num"),
                         Cell(effect_text(c), "num"), Cell(p_text(c.p), "num"),
                         Cell(t.outcome)])  # fmt: skip
    if not rows:
        return None
    return Table(f"other-{file_name(method)}-{kind}-effects",
                 f"{method} against the papers' methods ({kind})",
                 "Each comparison with a paper method of the same kind in the same cases: the "
                 "runs n (failed) of each, the medians (a failed run counts as the worst: "
                 "'failed' when the median reaches one), the effect (r paired by scene, Cliff's "
                 "δ otherwise; > 0 the method better) with its 95 % bootstrap interval, the "
                 "test's p, uncorrected (a description: a pipeline's claims are judged with "
                 f"Holm's correction in Your claims), and the outcome at p < {ALPHA}. Groups "
                 f"with fewer than {LEAST} runs a side are left out.",
                 ["cases", "paper method", "metric", "n (failed)", "medians", "effect [95 %]",
                  "p", "outcome"], rows, placement=APPENDIX)  # fmt: skip


def value_text(value: float | None) -> str:
    """A side's median or IQR as the comparisons' tables print it: three significant digits,
    ``failed`` when it reaches a failed run (infinite), ``-`` when unknown."""
    if value is None:
        return "-"
    return "failed" if abs(value) == float("inf") else f"{value:.3g}"


def effect_text(c: inference.Comparison) -> str:
    """``r +0.43 [+0.10, +0.71]``: the effect (r paired by scene, δ Cliff's otherwise; > 0 the
    method better) with its 95 % bootstrap interval."""
    symbol = "r" if c.effect_name == inference.PAIRED_R else "δ"
    return f"{symbol} {c.effect:+.2f} [{c.low:+.2f}, {c.high:+.2f}]"


def p_text(p: float | None) -> str:
    """A p as the comparisons' tables print it (``-`` when undefined)."""
    return "-" if p is None else f"{p:.2g}"


def subsection(results: Results, method: str) -> Section:
    s = Section(f"other-{file_name(method)}", method)
    for kind in MAIN:
        if not results.select(kind, method=method):
            continue
        tests = {name: comparisons(results, kind, method, name)
                 for name in groups(results, kind, method)}  # fmt: skip
        s.blocks.append(outcomes(results, kind, method, tests))
        if (table := effects(method, kind, tests)) is not None:
            s.blocks.append(table)
    return s


def section(results: Results) -> Section | None:
    methods = others(results)
    if not methods:
        return None
    top = Section("other-methods", "Other methods beside the papers'")
    top.paragraphs.append(
        f"The {len(methods)} methods of these results that no paper's table or claim names "
        f"({', '.join(methods)}): our variants of the papers' methods, the exact planners and "
        "any plugin's. For each, its outcomes in every group of cases it ran (the Imazu cases "
        "are also in the Imazu section's grid) and how it compares with each paper method "
        "that ran the same cases, by the comparisons the claims use, uncorrected: to have "
        "such a comparison judged, declare it as a claim of the pipeline (docs/pipelines.md)."
    )
    top.subsections = [subsection(results, m) for m in methods]
    return top
