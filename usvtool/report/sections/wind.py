"""The report's wind section (UDWA paper 4.2): the controllers' runs through wind fields, over
the ``wind`` scene family (seeded fields, paired by scene across controllers) and the bundled
wind scenarios (those whose run had a wind field: ``wind-*.yaml``).

Shown: the tracks over the field on the bundled scenes (or the family's first when there are
none), told apart by their offset from the start-goal line; the speed made good toward the goal
against time over the family; each controller's arrival times over the family (a run that did
not arrive, or collided, is a failure, counted in its own column and passed to the statistics
as the worst time, never as an arrival time); and each controller's arrival difference from
the reference (the paper's "traditional DWA") with its 95 % interval, by
:func:`usvtool.report.inference.compare` paired by scene. docs/report-wind.md says more.
"""

from __future__ import annotations

import math

from usvtool.pipeline import split_family_case
from usvtool.report.data import JobResults, Results
from usvtool.report.document import Cell, Figure, Section, Table, number
from usvtool.report.figures.wind import (
    MARK_EVERY_S,
    SMG_STEP,
    Difference,
    WindScene,
    arrival_differences,
    speed_made_good,
    wind_tracks,
)
from usvtool.report.inference import compare, iqr, median
from usvtool.report.papers import UDWA_WIND
from usvtool.report.runs import run_file, run_files
from usvtool.wind import read_wind_field

FAMILY = "wind"
#: The controller the others are compared with: the UDWA paper's "traditional DWA" (4.2).
REFERENCE = "dwa"
#: The bundled scenes drawn at most.
SHOWN = 2
#: A family group's runs: controller -> (case, seed) -> run.
Group = dict[str, dict[tuple, JobResults]]


def arrival(job: JobResults) -> float:
    """The run's arrival time (s); ``inf`` (a failure, the worst time) when it did not arrive
    or collided."""
    time = job.number("arrival_time_s")
    if not job.number("arrived") or job.text("collision") or time is None:
        return math.inf
    return time


def family_groups(results: Results) -> dict[str, Group]:
    """The wind family's runs: ``ENTRY/KIND`` -> controller -> (case, seed) -> run."""
    groups: dict[str, Group] = {}
    for job in results.select("runs"):
        parts = split_family_case(job.case)
        if parts is None or (job.config.get("scene") or {}).get("family") != FAMILY:
            continue
        group = groups.setdefault(f"{parts[0]}/{parts[1]}", {})
        group.setdefault(job.method, {})[(job.case, job.seed)] = job
    return dict(sorted(groups.items()))


def bundled(results: Results) -> list[str]:
    """The bundled scenarios (cases without ``/``) whose runs had a wind field."""
    found = []
    for case in results.cases("runs"):
        if "/" in case:
            continue
        files = next((f for f in map(run_files, results.select("runs", case)) if f), None)
        if files is not None and files.events.get("run", {}).get("wind_field"):
            found.append(case)
    return found


def scene(name: str, jobs: dict[str, JobResults]) -> WindScene | None:
    """A scene's field and every controller's run of it (None without the files)."""
    files = {c: run_files(j) for c, j in jobs.items()}
    files = {c: f for c, f in files.items() if f is not None}
    if not files:
        return None
    first = next(iter(files.values()))
    path = run_file(first.events, "wind_field", first.path)
    if path is None:
        return None
    field = read_wind_field(path)
    arrivals = {c: arrival(jobs[c]) for c in files}
    return WindScene(name, field.layers[0], field.layers[1], field.extent,
                     {c: f.trace for c, f in files.items()},
                     {c: None if math.isinf(a) else a for c, a in arrivals.items()},
                     tuple(first.events["run"]["goal"]))  # fmt: skip


def _time(value: float) -> Cell:
    return Cell("did not arrive", "num fails") if math.isinf(value) else number(value, 1)


def family_table(group: str, runs: Group,
                 controllers: list[str]) -> tuple[Table, list[Difference]]:  # fmt: skip
    """Each controller's arrivals over the group's scenes and, but for :data:`REFERENCE`'s, its
    difference from the reference's (paired by scene and seed), and those differences for the
    figure."""
    reference = runs.get(REFERENCE, {})
    rows, differences = [], []
    for c in controllers:
        times = [arrival(runs[c][k]) for k in sorted(runs[c])]
        failed = sum(1 for t in times if math.isinf(t))
        row = [Cell(c), Cell(str(len(times)), "num"), Cell(str(len(times) - failed), "num"),
               Cell(str(failed), "num" + (" fails" if failed else "")), _time(median(times)),
               _time(iqr(times))]  # fmt: skip
        keys = sorted(set(runs[c]) & set(reference))
        if c == REFERENCE or not keys:
            rows.append(row + [Cell("reference" if c == REFERENCE else "no pairs"), Cell(""),
                               Cell("")])  # fmt: skip
            continue
        mine = [arrival(runs[c][k]) for k in keys]
        theirs = [arrival(reference[k]) for k in keys]
        cmp = compare(mine, theirs, paired=True, better="lower")
        # compare's shift is the reference's time less the method's (> 0: the method earlier)
        shift = None if cmp.shift is None else (-cmp.shift, -cmp.shift_high, -cmp.shift_low)
        both = {k[0]: m - r for k, m, r in zip(keys, mine, theirs, strict=True)
                if math.isfinite(m) and math.isfinite(r)}  # fmt: skip
        differences.append(Difference(f"{c} − {REFERENCE}", c, both, len(keys) - len(both),
                                      *(shift or (None, None, None)),
                                      "" if shift else "no estimate: a run did not arrive"))
        rows.append(row + [
            Cell("-" if shift is None else f"{shift[0]:+.1f} [{shift[1]:+.1f}, {shift[2]:+.1f}]",
                 "num"),
            Cell(f"{cmp.effect:+.2f} [{cmp.low:+.2f}, {cmp.high:+.2f}]", "num"),
            Cell("-" if cmp.p is None else f"{cmp.p:.3g}", "num")])  # fmt: skip
    columns = ["controller", "scenes", "arrived", "did not arrive", "median (s)", "IQR (s)",
               f"− {REFERENCE} (s) [95 %]", "effect r [95 %]", "Wilcoxon p"]  # fmt: skip
    caption = (
        f"Arrival times over the scenes of {group}. A run that did not arrive or collided is a "
        "failure, counted in its own column and ranked as the worst time in the statistics "
        "(never as an arrival time; a median or IQR that failures reach reads 'did not "
        f"arrive'). − {REFERENCE}: the Hodges-Lehmann estimate of the controller's arrival "
        f"time less {REFERENCE}'s on the same scene (< 0: earlier) with its 95 % bootstrap "
        "interval, defined only when every run of both arrived; effect: the matched-pairs "
        "rank-biserial r (> 0: the controller earlier) with its 95 % bootstrap interval; "
        "Wilcoxon signed-rank p, two-sided, uncorrected (docs/statistics.md).")
    return Table(f"wind-{group.replace('/', '-')}-arrivals", f"Arrival in wind: {group}",
                 caption, columns, rows), differences  # fmt: skip


def bundled_table(results: Results, cases: list[str]) -> Table:
    """Each bundled wind scenario's arrival time per controller (one run each, its lowest
    seed), beside the paper's (UDWA 4.2; its setup differs: minutes, not seconds)."""
    controllers = sorted({c for s in cases for c in results.methods("runs", s)},
                         key=lambda m: results.methods("runs").index(m))  # fmt: skip
    rows = []
    for case in cases:
        cells = [Cell(case)]
        for c in controllers:
            jobs = sorted(results.select("runs", case, c), key=lambda j: j.seed or 0)
            cells.append(_time(arrival(jobs[0])) if jobs else Cell("-", "num"))
        paper = [f"{r.paper_method} {r.printed[0]} min" for r in UDWA_WIND.rows if r.case == case]
        cells.append(Cell("; ".join(paper) or "-", "paper"))
        rows.append(cells)
    return Table("wind-bundled-arrivals", "Arrival in the bundled wind scenarios",
                 "Arrival time (s) of each controller's run (one run each); the paper's arrival "
                 f"times (grey) are of runs of about an hour: {UDWA_WIND.setup}",
                 ["scenario", *controllers, "paper (UDWA 4.2)"], rows)  # fmt: skip


def illustrated(results: Results, cases: list[str], groups: dict[str, Group]) -> list[WindScene]:
    """The scenes whose tracks are drawn: the first :data:`SHOWN` bundled ones (every
    controller's run of its lowest seed), else the first scene of the first family group."""
    scenes = []
    for case in cases[:SHOWN]:
        jobs = {m: min(results.select("runs", case, m), key=lambda j: j.seed or 0)
                for m in results.methods("runs", case)}  # fmt: skip
        scenes.append(scene(case, jobs))
    if not cases and groups:
        runs = next(iter(groups.values()))
        first = min(k for r in runs.values() for k in r)
        scenes.append(scene(first[0], {c: r[first] for c, r in runs.items() if first in r}))
    return [s for s in scenes if s is not None]


def group_blocks(group: str, runs: Group, controllers: list[str]) -> list[Figure | Table]:
    """A family group's speed made good, arrival differences and arrival table."""
    name = group.replace("/", "-")
    blocks: list[Figure | Table] = []
    pairs = {c: [(f.trace, tuple(f.events["run"]["goal"]))
                 for f in map(run_files, (runs[c][k] for k in sorted(runs[c]))) if f]
             for c in controllers}  # fmt: skip
    pairs = {c: p for c, p in pairs.items() if p}
    if pairs:
        plot = speed_made_good(pairs, f"{group}: speed made good toward the goal")
        blocks.append(Figure(
            f"wind-{name}-smg", f"Speed made good in wind: {group}",
            f"The rate at which each controller's own ship closes the goal (the distance lost "
            f"over {SMG_STEP:g} s windows) against time: the median over the scenes (line) and "
            "the quartiles (band) of the runs still under way, drawn while at least half of "
            "them are (a run ends when it arrives).", plot.png, plot.data))
    table, differences = family_table(group, runs, controllers)
    if differences:
        plot = arrival_differences(differences, f"{group}: arrival time against {REFERENCE}, "
                                                "scene by scene")  # fmt: skip
        blocks.append(Figure(
            f"wind-{name}-differences", f"Arrival differences in wind: {group}",
            f"Each scene's arrival time less {REFERENCE}'s (dots: the scenes where both "
            "arrived) and the Hodges-Lehmann estimate with its 95 % bootstrap interval (diamond "
            "and bar; over every pair, so undefined when a run did not arrive). A scene far "
            "enough to squash the axis is a triangle at its edge with its value "
            "(docs/report-figures.md, 'Outliers at the axis's edge'); the data keep it.",
            plot.png, plot.data))
    blocks.append(table)
    return blocks


def section(results: Results) -> Section | None:
    groups = family_groups(results)
    cases = bundled(results)
    if not groups and not cases:
        return None
    top = Section("wind", "Runs in wind")
    top.paragraphs.append(
        "The UDWA paper's wind runs (4.2): the own ship crosses a field that blows strong on "
        "one side of the start-goal line and weak on the other, and UDWA, which weighs the "
        "wind, should arrive before the traditional DWA. The comparison rests on the wind "
        "family (docs/families.md: seeded fields, every controller on the same scenes); the "
        "bundled scenarios are examples.")
    shown = illustrated(results, cases, groups)
    if shown:
        plot = wind_tracks(shown)
        top.blocks.append(Figure(
            "wind-tracks", "Tracks through the wind field",
            "Wind speed (grey, darker stronger) and direction (arrows, where it blows) beneath "
            f"each controller's own-ship track (its style, a marker every {MARK_EVERY_S:g} s), "
            "start (triangle) and goal (star); below, each track's offset from the start-goal "
            "line against its progress along it, at a larger scale across (UDWA paper, Figs. "
            "19-20).", plot.png, plot.data))
    order = results.methods("runs")
    for group, runs in groups.items():
        top.blocks += group_blocks(group, runs, sorted(runs, key=order.index))
    if cases:
        top.blocks.append(bundled_table(results, cases))
    return top
