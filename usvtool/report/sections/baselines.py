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
metrics over the runs that did not fail and, against each baseline but itself, per main metric
(arrival time, closest distance), the paired-by-scene comparison of the judging module
(:func:`usvtool.report.sections.other_methods.metric_tests`, on
:func:`usvtool.report.judging.comparison`: a failed run the worst) with the uncorrected p: a
description, not a claim.

Three layers, kept apart: :func:`groups` and :func:`standings` judge (no page, no file read
beyond the results table; computed once per :class:`Results` and process: the summary's line
is derived from them by :func:`record`); the tables (:func:`outcomes_table`,
:func:`against_table`, :func:`comparisons_table`) and :func:`section` write the page. No
figure: the tables say it. The part's cost is its comparisons' (about 60 ms each, most of it
the bootstrap: 64 on ``pipelines/full.yaml``, about 4 s, paid again by the summary, which the
report builds in another process).
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
from usvtool.report.sections.other_methods import (
    BUNDLED,
    LEAST,
    MAIN,
    effect_text,
    group,
    metric_tests,
    p_text,
    value_text,
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
    ended because the controller failed, each main metric's values over the runs that did not
    fail, and its comparisons against each baseline but itself: (baseline, metric, test), when
    both sides have :data:`LEAST` paired runs or more."""

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
    values = {metric: [v for j in jobs if j.succeeded and (v := j.number(metric)) is not None]
              for metric, *_ in MAIN["runs"]}  # fmt: skip
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


def record(s: Standing, baseline: str | None = None) -> tuple[int, int, int]:
    """The controller's comparisons (against ``baseline``, or every baseline): how many it is
    better in, worse in (uncorrected p < :data:`ALPHA`, by the effect's sign) and of how many."""
    mine = [t for b, _, t in s.tests if baseline in (None, b)]
    return (sum(t.outcome == "better" for t in mine), sum(t.outcome == "worse" for t in mine),
            len(mine))  # fmt: skip


# --- the page --------------------------------------------------------------------------------

#: An outcome as the tables word it.
WORDS = {"better": "better", "worse": "worse", "neither": "n.s."}
CSS = {"better": "holds", "worse": "fails"}


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


def _against(s: Standing, baseline: str, metric: str) -> Cell:
    """The controller against a baseline on a metric: better, worse or n.s. with the
    effect; ``itself``; ``-`` with too few paired runs."""
    if s.method == baseline:
        return Cell("itself")
    t = next((t for b, m, t in s.tests if b == baseline and m == metric), None)
    if t is None:
        return Cell("-")
    return Cell(f"{WORDS.get(t.outcome, t.outcome)}, r {t.comparison.effect:+.2f}",
                CSS.get(t.outcome, ""))


def against_table(found: list[Group]) -> Table:
    """Per group and controller: the main metrics' median (IQR) over the runs that did not
    fail, and against each baseline per metric the outcome of the paired comparison."""
    ran = [b for b in BASELINES if any(b in g.baselines for g in found)]
    metrics = MAIN["runs"]
    rows = []
    for g in found:
        for i, s in enumerate(g.standings):
            rows.append([_first(g, i), Cell(_name(s.method)),
                         *(_figure(s.values[m]) for m, *_ in metrics),
                         *(_against(s, b, m) if b in g.baselines else Cell("did not run")
                           for b in ran for m, *_ in metrics)])  # fmt: skip
    return Table(
        "baselines-against", "Every controller against the baselines",
        "Per group and controller: the median (IQR) of the arrival time and of the closest "
        "centre distance to a target over the runs that arrived without collision; then, "
        "against each baseline, per metric, the paired-by-scene comparison (a run that "
        "collided or did not arrive the worst): better or worse at uncorrected p < "
        f"{ALPHA} (a description, not a claim), n.s. otherwise, with the matched-pairs "
        "rank-biserial effect r (> 0: the controller better than the baseline); '-' with fewer "
        f"than {LEAST} paired runs. Each comparison's n, medians, interval and p in the "
        "appendix.",
        ["group", "controller", *(f"{h}: median (IQR)" for _, _, h, _ in metrics),
         *(f"against {b}: {SHORT.get(m, m)}" for b in ran for m, *_ in metrics)],
        rows)  # fmt: skip


def _side(side) -> str:
    return f"{value_text(side.median)} ({value_text(side.iqr)})"


def comparisons_table(found: list[Group]) -> Table | None:
    """Every comparison of a controller with a baseline, per group and main metric: the runs
    n (failed) of each side, their median (IQR; failures the worst), the test, the effect with
    its 95 % interval, the uncorrected p and the outcome."""
    rows = []
    for g in found:
        for s in g.standings:
            for baseline, metric, t in s.tests:
                a, b = t.sides
                c = t.comparison
                test = "W" if c.test == inference.WILCOXON else "U"
                rows.append([Cell(g.name), Cell(s.method), Cell(baseline), Cell(metric),
                             Cell(f"{a.n}/{b.n} ({a.failed}/{b.failed})", "num"),
                             Cell(_side(a), "num"), Cell(_side(b), "num"), Cell(test),
                             Cell(effect_text(c), "num"), Cell(p_text(c.p), "num"),
                             Cell(WORDS.get(t.outcome, t.outcome),
                                  CSS.get(t.outcome, ""))])  # fmt: skip
    if not rows:
        return None
    return Table(
        "baselines-comparisons", "Every comparison with the baselines",
        "Per group, controller, baseline and metric: the runs paired by scene, n (failed) of "
        "each side; the median (IQR) of each over every paired run, a run that collided or did "
        "not arrive the worst ('failed' where the median or a quartile reaches one); the test "
        "(W: Wilcoxon signed-rank on the paired differences); the effect (r: matched-pairs "
        "rank-biserial, > 0 the controller better than the baseline) with its 95 % bootstrap "
        "interval; the test's two-sided p, uncorrected (a description: a pipeline's claims are "
        f"judged with Holm's correction in Your claims) and the outcome at p < {ALPHA}. "
        f"Controllers with fewer than {LEAST} paired runs are left out.",
        ["group", "controller", "baseline", "metric", "n (failed)", "controller: median (IQR)",
         "baseline: median (IQR)", "test", "effect [95 %]", "p (uncorrected)", "outcome"],
        rows, placement=APPENDIX)  # fmt: skip


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
        "controller its outcomes and COLREGs counts, and against each baseline its arrival "
        "time and closest distance to a target compared scene by scene (the Wilcoxon "
        "signed-rank test with the matched-pairs rank-biserial effect and its 95 % bootstrap "
        "interval, the claims' comparison; a run that collided or did not arrive counts as the "
        "worst). The p are uncorrected, each comparison alone: they describe, they judge no "
        "claim (to have one judged, declare it in the pipeline: docs/pipelines.md).")
    top.blocks += [outcomes_table(found), against_table(found)]
    if (table := comparisons_table(found)) is not None:
        top.blocks.append(table)
    return top
