"""The report's part for the methods that are not the papers': our variants (``udwa+``,
``iwso+g``, ``ssa-redraw`` ...), the exact planners and any plugin's method, every method of the
results that no paper table or claim names (:data:`PAPER_METHODS`).

Per method, a subsection: its outcomes in every group of cases it ran (a chart's routes, a
scene family's runs, the Imazu cases among them, the bundled scenarios together, a benchmark
function): the runs, the failures, the median and IQR of the main metrics (:data:`MAIN`) over
the measured runs (:func:`measured_values`) and, for runs, their encounters' COLREGs counts;
then, in the appendix, its comparison with each paper method of the same kind that ran there,
for each main metric, by the judging module's comparison
(:func:`usvtool.report.judging.comparison`, the claims' own: paired by scene for runs,
independent otherwise; the failures as their own outcome, exact McNemar or Fisher; the metric
on the measured values, :func:`usvtool.report.judging.measured`), shown as the claims section
shows its comparisons (:func:`row_cells`, on :mod:`.claims`' texts) with the uncorrected p: a
description, not a claim (a claim of the pipeline is judged in "Your claims"). Tables only, no
figure: the part adds a fraction of a second to the report (the comparisons' bootstraps).
"""

from __future__ import annotations

import re
from dataclasses import replace

from usvtool.report import inference
from usvtool.report.data import JobResults, Results
from usvtool.report.document import APPENDIX, Cell, Section, Table
from usvtool.report.judging import ALPHA, Side, Test, comparison, measured
from usvtool.report.papers import CLAIMS, TABLES, Claim
from usvtool.report.runs import TALLY_COLUMNS, RunTally, is_family
from usvtool.report.sections.claims import _test_text, effect_text, entered_text, failures_text
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


def claim_of(kind: str, method: str, rival: str, metric: str, name: str) -> Claim:
    """The claim a comparison of the part stands for: ``method`` against ``rival`` on a main
    metric (:data:`MAIN`, its direction) by the median in the group of cases ``name``, judged
    by no one (no paper, no Holm family)."""
    better = next(b for m, b, _, _ in MAIN[kind] if m == metric)
    return Claim(f"{method} vs {rival}", "", (), kind, metric, "median", better, method,
                 (rival,), (name,))  # fmt: skip


def measured_values(jobs: list[JobResults], kind: str, metric: str) -> list[float]:
    """The values of a main metric that enter the comparisons (:func:`usvtool.report.judging.
    measured`): a run that collided or whose controller failed, a colliding route, measures
    nothing; a run that only never arrived keeps its closest distance (it has no arrival
    time)."""
    claim = claim_of(kind, "", "", metric, "")
    return [v for j in jobs if (v := measured(j, claim)) is not None]


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
    (:data:`MAIN`): (metric, the judging module's comparison of :func:`claim_of`: the failures
    over every run compared, exact McNemar on scene pairs, Fisher otherwise; the median's
    rank test on the measured values, paired by scene for runs; its p uncorrected) when both
    sides have :data:`LEAST` runs or more in it (after pairing) and there is something to
    show: measured values on both sides, or failures where the metric was written (a side
    that failed in every run measures nothing, yet loses; a metric no run has is left out).
    Shared with the baselines' section (:mod:`.baselines`)."""
    if kind == "runs" and len(results.pairs(kind, name, method, rival)) < LEAST:
        return []  # too few pairs whatever their values: spare the test's work
    out = []
    for metric, *_ in MAIN[kind]:
        test = comparison(results, claim_of(kind, method, rival, metric, name), name, rival)
        if min(s.n for s in test.sides) < LEAST:
            continue
        written = any(j.number(metric) is not None for m in (method, rival)
                      for j in results.group(kind, name, m))  # fmt: skip
        if test.statistic is not None or (written and failures_text(test)):
            out.append((metric, test))
    return out


#: A comparison's outcome (:attr:`usvtool.report.judging.Test.outcome`) as the part's tables
#: and the baselines' word it, and its cell's class.
WORDS = {"better": "better", "worse": "worse", "equivalent": "equivalent", "neither": "n.s.",
         "missing": "not measured"}  # fmt: skip
CSS = {"better": "holds", "worse": "fails", "equivalent": "equivalent"}


def outcome_cell(t: Test) -> Cell:
    """The comparison's outcome in its word (:data:`WORDS`), coloured."""
    return Cell(WORDS.get(t.outcome, t.outcome), CSS.get(t.outcome, ""))


def row_cells(t: Test, claim: Claim) -> list[Cell]:
    """A comparison as the claims section gives one (:mod:`.claims`' texts), in five cells:
    the medians (IQR) of each side over the measured values with which runs entered
    (:func:`~.claims.entered_text`), the effect in the metric's units with its 95 % interval
    and the relative change (:func:`~.claims.effect_text`), the rank test with its p
    (uncorrected here) and the rank effect, and TOST when equivalent (:func:`~.claims.
    _test_text`, the failures left to the next cell), the failures' test (:func:`~.claims.
    failures_text`, '-' when no run failed), the outcome (:func:`outcome_cell`)."""
    medians = (" vs ".join(_median(side) for side in t.sides)
               + f"; {entered_text(t, claim.kind == 'runs')}")  # fmt: skip
    return [Cell(medians, "num"), Cell(effect_text(t, claim), "num"),
            Cell(_test_text(replace(t, failures=None), claim)), Cell(failures_text(t) or "-"),
            outcome_cell(t)]  # fmt: skip


#: The columns of :func:`row_cells`.
ROW_COLUMNS = ["medians (IQR); runs entered", "effect [95 %]; change %",
               "test: p (uncorrected), rank effect [95 %]", "failures", "outcome"]  # fmt: skip
#: What :func:`row_cells` shows, for the tables' captions.
ROW_CAPTION = (
    "the median (IQR) of each side over the measured runs (a run that collided or whose "
    "controller failed, a route through an obstacle, is left out; a run that only never "
    "arrived keeps its closest distance; paired, the pairs where both are measured) and which "
    "entered (pairs measured of those compared, informative when fewer: the non-zero "
    "differences); the effect in the metric's units, method - rival (the Hodges-Lehmann shift) "
    "with its 95 % interval, and the relative change of the medians with its interval (> 0 "
    "better, as the papers state theirs); the rank test (Wilcoxon signed-rank paired by scene, "
    "Mann-Whitney U otherwise) with its two-sided p, uncorrected (a description: a pipeline's "
    "claims are judged with Holm's correction in Your claims), and the rank effect (r paired, "
    "Cliff's δ otherwise; > 0 the method better) with its 95 % bootstrap interval, and TOST "
    "against the metric's smallest effect of interest when it is equivalent (docs/statistics.md); "
    "the failures, each side's failed of its runs compared, with exact McNemar's p on scene "
    "pairs, Fisher's otherwise (uncorrected; '-' when no run failed); the outcome at p < "
    f"{ALPHA}: better or worse (worse also when it fails significantly more often), "
    "equivalent, n.s. otherwise, not measured when a side has no measured run"
)


def _digest(found: list[tuple[str, str, Test]], kind: str) -> str:
    """How many paper methods the method beats, loses to (its metric, or failing more often)
    and is equivalent to, per main metric (uncorrected p < :data:`ALPHA`)."""
    parts = []
    for metric, _, heading, _ in MAIN[kind]:
        mine = [t for _, m, t in found if m == metric]
        if not mine:
            continue
        won = sum(t.outcome == "better" for t in mine)
        lost = sum(t.outcome == "worse" for t in mine)
        same = sum(t.outcome == "equivalent" for t in mine)
        also = f", equivalent to {same}" if same else ""
        parts.append(f"{heading.split(' (')[0]}: better than {won}, worse than {lost}{also} "
                     f"of {len(mine)}")  # fmt: skip
    return "; ".join(parts) or "-"


def outcomes(results: Results, kind: str, method: str,
             tests: dict[str, list]) -> Table:  # fmt: skip
    """The method's runs per group: n, failures, median (IQR) of each main metric over the
    measured runs (:func:`measured_values`; runs: their outcomes and COLREGs counts), and the
    digest of its comparisons with the papers' methods."""
    rows = []
    for name, jobs in groups(results, kind, method).items():
        failed = sum(j.failed for j in jobs)
        cells = [Cell(name), Cell(str(len(jobs)), "num")]
        if kind == "runs":
            cells += RunTally.of(jobs).cells()
        else:
            cells.append(Cell(str(failed), "num" + (" fails" if failed else "")))
        for metric, _, _, digits in MAIN[kind]:
            cells.append(Cell(_figure(measured_values(jobs, kind, metric), digits), "num"))
        cells.append(Cell(_digest(tests.get(name, []), kind)))
        rows.append(cells)
    counts = TALLY_COLUMNS if kind == "runs" else [FAILED[kind]]
    columns = ["cases", "runs", *counts, *(f"{h}: median (IQR)" for _, _, h, _ in MAIN[kind]),
               "against the papers' methods"]  # fmt: skip
    what = {"routes": "routes", "runs": "runs", "functions": "benchmark-function runs"}[kind]
    return Table(f"other-{file_name(method)}-{kind}", f"{method}: its {what}",
                 CAPTIONS[kind] + " Against the papers' methods: how many of those that ran "
                 "the same cases it is better or worse than (its metric at uncorrected p < "
                 f"{ALPHA}; worse also when it fails significantly more often) or equivalent to "
                 "(TOST; each comparison in the appendix).", columns, rows)  # fmt: skip


#: What an outcomes table shows, per kind.
CAPTIONS = {
    "routes": "Per chart: the routes, those through an obstacle (failures), the medians (IQR) "
    "over the collision-free routes (those measured).",
    "runs": f"Per scene family ({BUNDLED} together): the runs, their outcomes (a run that "
    "collided or did not arrive is a failure) and their encounters' COLREGs counts, the "
    "medians (IQR) over the measured runs: the arrival time over those that arrived, the "
    "closest distance also over those that only never arrived (a run that collided or whose "
    "controller failed measures nothing).",
    "functions": "Per function: the runs and the median (IQR) of the final cost.",
}


def effects(method: str, kind: str, tests: dict[str, list]) -> Table | None:
    """Every comparison of the method with a paper method (:func:`comparisons`), a row each
    (:func:`row_cells`)."""
    rows = []
    for name, found in tests.items():
        for rival, metric, t in found:
            rows.append([Cell(name), Cell(rival), Cell(metric),
                         *row_cells(t, claim_of(kind, method, rival, metric, name))])  # fmt: skip
    if not rows:
        return None
    return Table(f"other-{file_name(method)}-{kind}-effects",
                 f"{method} against the papers' methods ({kind})",
                 "Each comparison with a paper method of the same kind in the same cases, as "
                 f"the claims section gives them: {ROW_CAPTION}. Groups with fewer than "
                 f"{LEAST} runs a side are left out.",
                 ["cases", "paper method", "metric", *ROW_COLUMNS], rows,
                 placement=APPENDIX)  # fmt: skip


def _median(side: Side) -> str:
    """``median (IQR)`` of a side's measured values, ``-`` without any."""
    if side.median is None:
        return "-"
    return f"{value_text(side.median)} ({value_text(side.iqr)})"


def value_text(value: float | None) -> str:
    """A side's median or IQR as the comparisons' tables print it: three significant digits,
    ``-`` when unknown."""
    return "-" if value is None else f"{value:.3g}"


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
        "that ran the same cases, by the comparisons the claims use (the failures as their own "
        "outcome, the main metrics on the measured runs, the effect in the metric's units), "
        "uncorrected: to have such a comparison judged, declare it as a claim of the pipeline "
        "(docs/pipelines.md)."
    )
    top.subsections = [subsection(results, m) for m in methods]
    return top
