"""The report's part "Against the field's baselines": every controller of a scene family set
against the field's baseline controllers ``vo`` (velocity obstacles, Kuwata et al. 2014) and
``sbmpc`` (simulation-based MPC, Johansen et al. 2016; docs/controllers.md) that ran the same
scenes.

A **group** is a scene family entry's runs (``emergency``, ``imazu``, ``imazu-compressed``,
``trafficgen``: the cases' prefix, :func:`usvtool.report.sections.other_methods.group`); the
part covers every group in which a baseline ran, and in it every controller that ran there (the
papers', ours, a pipeline's variants and plugins'). Per controller: its runs, their outcomes and
COLREGs counts (:class:`usvtool.report.runs.RunTally`: a run that collided or did not arrive, a
controller that failed among them, is a failure, never a success), the median (IQR) of the main
metrics over the measured runs (:func:`usvtool.report.sections.other_methods.measured_values`)
and, against each baseline but itself, per main metric (arrival time, closest distance), the
paired-by-scene comparison of the judging module, the claims' own
(:func:`usvtool.report.sections.other_methods.metric_tests`, on
:func:`usvtool.report.judging.comparison`: the failures as their own outcome, exact McNemar;
the metric on the measured pairs, Wilcoxon signed-rank, the Hodges-Lehmann shift in the
metric's units, TOST) with the uncorrected p: a description, not a claim.

Three layers, kept apart: :func:`groups` and :func:`standings` judge (no page, no file read
beyond the results table; computed once per :class:`Results` and process: the summary's line
is derived from them by :func:`record`); the tables (:func:`outcomes_table`,
:func:`against_table`, :func:`comparisons_table`) and :func:`section` write the page. No
figure: the tables say it. The part's cost is its comparisons' (most of it the bootstraps: 64
on ``pipelines/full.yaml``, paid again by the summary, which the report builds in another
process).
"""

from __future__ import annotations

from dataclasses import dataclass

from usvtool.report import inference
from usvtool.report.data import JobResults, Results
from usvtool.report.document import APPENDIX, Cell, Section, Table
from usvtool.report.judging import ALPHA, Test
from usvtool.report.runs import (
    COUNTS,
    TALLY_COLUMNS,
    RunTally,
    controller_failed,
    is_family,
)
from usvtool.report.sections.claims import _percent, _raw, failures_text, units
from usvtool.report.sections.other_methods import (
    BUNDLED,
    CSS,
    LEAST,
    MAIN,
    ROW_CAPTION,
    ROW_COLUMNS,
    WORDS,
    claim_of,
    group,
    measured_values,
    metric_tests,
    row_cells,
)

#: The field's baseline controllers (docs/controllers.md) and what each is.
BASELINES = {
    "vo": "velocity obstacles (Kuwata et al. 2014)",
    "sbmpc": "simulation-based MPC (Johansen et al. 2016)",
}
#: Short names of the main metrics of runs (:data:`MAIN`).
SHORT = {"arrival_time_s": "arrival", "closest_distance_m": "closest"}


# --- judging: no page ----------------------------------------------------------------------


@dataclass(frozen=True)
class Standing:
    """One controller in one group: its runs' outcomes and COLREGs counts, how many of them
    ended because the controller failed, each main metric's measured values
    (:func:`~.other_methods.measured_values`), and its comparisons against each baseline but
    itself: (baseline, metric, test), when both sides have :data:`LEAST` paired runs or
    more."""

    method: str
    runs: int
    tally: RunTally
    controller_failed: int
    values: dict[str, list[float]]
    tests: tuple[tuple[str, str, Test], ...]


@dataclass(frozen=True)
class Group:
    """A scene family group in which a baseline ran: the baselines that ran it and every
    controller's :class:`Standing` there, in the report's order of methods."""

    name: str
    baselines: tuple[str, ...]
    standings: tuple[Standing, ...]


def groups(results: Results) -> dict[str, dict[str, list[JobResults]]]:
    """The scene family groups in which a baseline (:data:`BASELINES`) ran: group -> controller
    -> its runs there, the groups in :func:`other_methods.groups`'s order, the controllers in
    the report's (:meth:`Results.methods`)."""
    found: dict[str, dict[str, list[JobResults]]] = {}
    order = results.methods("runs")
    for job in results.select("runs"):
        if is_family(job.case):
            found.setdefault(group("runs", job.case), {}).setdefault(job.method, []).append(job)
    chosen = {name: {m: by[m] for m in order if m in by} for name, by in found.items()
              if name != BUNDLED and any(b in by for b in BASELINES)}  # fmt: skip
    return dict(sorted(chosen.items()))


def standing(results: Results, name: str, method: str, jobs: list[JobResults],
             baselines: tuple[str, ...]) -> Standing:  # fmt: skip
    """The controller ``method``'s :class:`Standing` in the group ``name``."""
    failed_controller = sum(controller_failed(j) for j in jobs)
    values = {metric: measured_values(jobs, "runs", metric) for metric, *_ in MAIN["runs"]}
    tests = tuple((b, metric, t) for b in baselines if b != method
                  for metric, t in metric_tests(results, "runs", method, b, name))  # fmt: skip
    return Standing(method, len(jobs), RunTally.of(jobs), failed_controller, values, tests)


_DONE: list[tuple[Results, list[Group]]] = []


def standings(results: Results) -> list[Group]:
    """Every group with a baseline (:func:`groups`) and every controller's standing there.
    Computed once per :class:`Results` (the section and the summary share it)."""
    if not _DONE or _DONE[0][0] is not results:
        out = []
        for name, by in groups(results).items():
            baselines = tuple(b for b in BASELINES if b in by)
            out.append(Group(name, baselines, tuple(standing(results, name, m, jobs, baselines)
                                                    for m, jobs in by.items())))  # fmt: skip
        _DONE[:] = [(results, out)]
    return _DONE[0][1]


def record(s: Standing, baseline: str | None = None) -> tuple[int, int, int, int]:
    """The controller's comparisons (against ``baseline``, or every baseline), by their
    outcome (:attr:`usvtool.report.judging.Test.outcome`): how many it is better in, worse in
    (its metric at uncorrected p < :data:`ALPHA`, or failing significantly more often),
    equivalent in (TOST), and of how many."""
    mine = [t for b, _, t in s.tests if baseline in (None, b)]
    return (*(sum(t.outcome == o for t in mine) for o in ("better", "worse", "equivalent")),
            len(mine))  # fmt: skip


# --- the page --------------------------------------------------------------------------------


def _figure(values: list[float]) -> Cell:
    """``median (IQR)`` of the values, ``-`` for none."""
    if not values:
        return Cell("-", "num")
    return Cell(f"{inference.median(values):.1f} ({inference.iqr(values):.1f})", "num")


def _first(g: Group, i: int) -> Cell:
    """The group's name on its first row only."""
    return Cell(g.name if i == 0 else "")


def _name(method: str) -> str:
    return f"{method} (baseline)" if method in BASELINES else method


def outcomes_table(found: list[Group]) -> Table:
    """Per group and controller: runs, outcomes, COLREGs counts and controller failures."""
    rows = []
    for g in found:
        for i, s in enumerate(g.standings):
            failed = Cell(str(s.controller_failed),
                          "num" + (" fails" if s.controller_failed else ""))  # fmt: skip
            rows.append([_first(g, i), Cell(_name(s.method)), Cell(str(s.runs), "num"),
                         *s.tally.cells(), failed])  # fmt: skip
    return Table(
        "baselines-outcomes", "Where the baselines ran: every controller's outcomes",
        "Per scene family group where a baseline ran and controller: the runs, their outcomes "
        "each in its own column (controller failed: those of the runs that did not arrive that "
        "ended because the controller failed, a failure as the others), their encounters' "
        f"COLREGs counts. {COUNTS}",
        ["group", "controller", "runs", *TALLY_COLUMNS, "controller failed"], rows)


def _test(s: Standing, baseline: str, metric: str) -> Test | None:
    return next((t for b, m, t in s.tests if b == baseline and m == metric), None)


def _against(t: Test | None, metric: str) -> Cell:
    """A comparison on one metric in short: the outcome, the Hodges-Lehmann shift in the
    metric's units (controller - baseline), the relative change (> 0 better) and the rank
    effect r; ``-`` with too few paired runs, the outcome alone without measured pairs."""
    if t is None:
        return Cell("-")
    word = WORDS.get(t.outcome, t.outcome)
    if t.statistic is None or t.shift is None or t.comparison is None:
        return Cell(word, CSS.get(t.outcome, ""))
    better = next(b for m, b, _, _ in MAIN["runs"] if m == metric)
    (shift,) = _raw(better, t.shift.estimate)
    unit = f" {units(metric)}" if units(metric) else ""
    relative = t.statistic.difference.relative
    change = "" if relative is None else f" ({_percent(100 * relative)} %)"
    return Cell(f"{word}, {shift:+.3g}{unit}{change}, r {t.comparison.effect:+.2f}",
                CSS.get(t.outcome, ""))  # fmt: skip


def _failures(t: Test | None) -> Cell:
    """The failures against the baseline (:func:`~.claims.failures_text`), coloured when they
    differ significantly (uncorrected)."""
    if t is None:
        return Cell("-")
    css = {"better": "holds", "worse": "fails"}.get(t.failure_outcome, "")
    return Cell(failures_text(t) or "none failed", css)


def against_table(found: list[Group]) -> Table:
    """Per group and controller: the main metrics' median (IQR) over the measured runs, then a
    row against each other baseline that ran there: per metric the paired comparison in short
    (:func:`_against`), and the failures' comparison."""
    metrics = MAIN["runs"]
    rows = []
    for g in found:
        for i, s in enumerate(g.standings):
            head = [_first(g, i), Cell(_name(s.method)),
                    *(_figure(s.values[m]) for m, *_ in metrics)]  # fmt: skip
            others = [b for b in g.baselines if b != s.method]
            if not others:
                rows.append([*head, *(Cell("-") for _ in range(len(metrics) + 2))])
            for k, b in enumerate(others):
                tests = [_test(s, b, m) for m, *_ in metrics]
                first = next((t for t in tests if t is not None), None)
                rows.append([*(head if k == 0 else [Cell("") for _ in head]), Cell(b),
                             *(_against(t, m) for t, (m, *_) in zip(tests, metrics,
                                                                      strict=True)),
                             _failures(first)])  # fmt: skip
    return Table(
        "baselines-against", "Every controller against the baselines",
        "Per group and controller: the median (IQR) of the arrival time (over the runs that "
        "arrived without collision) and of the closest centre distance to a target (also over "
        "those that only never arrived: a run that collided or whose controller failed "
        "measures nothing); then a row against each other baseline that ran there, per metric "
        "the paired-by-scene comparison on the pairs where both are measured: better or worse "
        f"at uncorrected p < {ALPHA} (a description, not a claim; worse also when the "
        "controller fails significantly more often), equivalent (TOST against the metric's "
        "smallest effect of interest), n.s. otherwise, with the Hodges-Lehmann shift in the "
        "metric's units (controller - baseline), the relative change of the medians (> 0 "
        "better) and the matched-pairs rank-biserial r (> 0: the controller better); and the "
        "failures, each side's failed of the paired runs with exact McNemar's p, uncorrected. "
        f"'-' with fewer than {LEAST} paired runs. Each comparison's runs, intervals and p in "
        "the appendix.",
        ["group", "controller", *(f"{h}: median (IQR)" for _, _, h, _ in metrics), "against",
         *(SHORT.get(m, m) for m, *_ in metrics), "failures"], rows)  # fmt: skip


def comparisons_table(found: list[Group]) -> Table | None:
    """Every comparison of a controller with a baseline, per group and main metric, as the
    claims section gives them (:func:`~.other_methods.row_cells`)."""
    rows = []
    for g in found:
        for s in g.standings:
            for baseline, metric, t in s.tests:
                claim = claim_of("runs", s.method, baseline, metric, g.name)
                rows.append([Cell(g.name), Cell(s.method), Cell(baseline), Cell(metric),
                             *row_cells(t, claim)])  # fmt: skip
    if not rows:
        return None
    return Table(
        "baselines-comparisons", "Every comparison with the baselines",
        "Per group, controller, baseline and metric, the runs paired by scene, as the claims "
        f"section gives its comparisons: {ROW_CAPTION}. Controllers with fewer than {LEAST} "
        "paired runs are left out.",
        ["group", "controller", "baseline", "metric", *ROW_COLUMNS], rows,
        placement=APPENDIX)  # fmt: skip


def section(results: Results) -> Section | None:
    found = standings(results)
    if not found:
        return None
    ran = [b for b in BASELINES if any(b in g.baselines for g in found)]
    top = Section("baselines", "Against the field's baselines")
    top.paragraphs.append(
        f"The field's baseline controllers {', '.join(f'{b}, {BASELINES[b]}' for b in ran)} "
        "(docs/controllers.md) beside every controller that ran the same scenes, in each scene "
        f"family group where a baseline ran ({', '.join(g.name for g in found)}): per "
        "controller its outcomes and COLREGs counts, and against each baseline, compared scene "
        "by scene as the claims are: its failures (a run that collided or did not arrive, "
        "exact McNemar), and its arrival time and closest distance to a target on the pairs "
        "where both runs measured them (a run that collided or whose controller failed "
        "measures nothing; one that only never arrived keeps its closest distance), by the "
        "Wilcoxon signed-rank test, with the Hodges-Lehmann shift in seconds or metres and "
        "its 95 % interval, the relative change, the matched-pairs rank-biserial r and TOST "
        "against the metric's smallest effect of interest (equivalent). The p are "
        "uncorrected, each comparison alone: they describe, they judge no claim (to have one "
        "judged, declare it in the pipeline: docs/pipelines.md).")
    top.paragraphs.append(JUDGES)
    top.blocks += [outcomes_table(found), against_table(found)]
    if (table := comparisons_table(found)) is not None:
        top.blocks.append(table)
    return top


#: Whose rules judge the runs: ours alone, and why the field's published evaluations are not
#: beside them (docs/judges.md, docs/design-changes.md).
JUDGES = (
    "Judged by whose rules: every COLREGs count here is our verdicts' (docs/colregs.md). The "
    "field's published evaluations are not beside them: Woerner, Benjamin, Novitzky and "
    "Leonard's protocol metrics (Autonomous Robots 43, 2019) and Hagen, Brekke, Vassbotn et "
    "al.'s safety and COLREG scores (Ocean Engineering 288, 2023) are built only from their "
    "papers' own texts, which could not be read here (docs/judges.md says what was searched and "
    "what building them needs), and the temporal-logic monitor commonocean-rules does not "
    "install beside usvtool's dependencies (docs/design-changes.md).")
