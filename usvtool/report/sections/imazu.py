"""The report's Imazu section: the 22 encounters of the Imazu problem (Imazu 1987, as tabulated
by Sawada, Sato and Majima 2021, J. Mar. Sci. Technol. 26, Table 4; docs/families.md) with
every controller that ran them: one case x controller grid figure and a table of each run's
arrival, collision, closest distance and COLREGs counts, with the totals per controller.

The runs are those of the ``imazu`` scene family (their ``job.json``'s ``scene.family``), whatever
the pipeline's entry is named; a case is the family's kind (``01`` ... ``22``). The scale the
cases ran at is read from the runs' own files, never from the family's defaults nor the
scenario YAML: the ships' starts, headings and speeds from the trace's first step (so the
targets' classes, ranges and time to CPA at the start, by :func:`usvtool.encounter.assess`),
lengths, the goal and the duration from the events' ``run`` object
(:mod:`usvtool.report.runs`). docs/report-imazu.md says what each cell means.

The family may run at several scales, one pipeline entry each (``imazu`` at the published
proportions, ``imazu-compressed`` at the compressed USV scale: :func:`entries`). The grid, the
totals and the table of every run are then the main entry's (:func:`main_entry`: the one run
at the family's defaults), and a table of the scales (:func:`sensitivity_table`) sets each
entry's scale, in own ship lengths and against the verdicts' onset TCPA, beside every
controller's outcomes there.

In the HTML report only, every run of the main entry is a player (:func:`players`, folded
until opened), and a table under the grid (:func:`players_table`) links each cell to its run's
player; the section's text says so in the PDF too (:data:`ANIMATED`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from usvtool.encounter import CLASS_NAMES, assess
from usvtool.errors import UsvError
from usvtool.pipeline import split_family_case
from usvtool.report import inference
from usvtool.report.data import JobResults, Results
from usvtool.report.document import APPENDIX, HTML, Cell, Figure, Section, Table, anchor
from usvtool.report.figures.imazu import Cell as GridCell
from usvtool.report.figures.imazu import imazu_grid, outcome
from usvtool.report.runs import (
    COUNTS,
    OUTCOMES,
    TALLY_COLUMNS,
    VERDICTS,
    RunTally,
    family_runs,
    job_events,
    job_facts,
    median_iqr,
    run_files,
    ship_lengths,
)
from usvtool.report.runs import start as first_states
from usvtool.report.sections.encounters import thresholds_table
from usvtool.trace import OWN

FAMILY = "imazu"
#: Short names of the encounter classes at the start, for the case labels.
SHORT = {"head-on": "HO", "crossing-give-way": "GW", "crossing-stand-on": "SO",
         "overtaking": "OT", "overtaken": "OD", "none": "-"}  # fmt: skip


@dataclass(frozen=True)
class Start:
    """A case's situation at the start: the own ship's speed, each target's class,
    speed, range and CPA (distance, time), the distance to the goal, every length, the
    scenario's duration."""

    own_speed: float
    classes: tuple[str, ...]
    speeds: tuple[float, ...]
    ranges: tuple[float, ...]
    dcpa: tuple[float, ...]
    tcpa: tuple[float, ...]
    goal_m: float
    own_length: float
    lengths: tuple[float, ...]
    duration: float | None


def imazu_runs(results: Results) -> dict[str, dict[str, JobResults]]:
    """The Imazu family's runs: case (``ENTRY/KIND/sNNN``) -> controller -> the run of its
    lowest seed."""
    return family_runs(results, FAMILY)


Runs = dict[str, dict[str, JobResults]]


def entries(runs: Runs) -> dict[str, Runs]:
    """The runs by the pipeline's entry (the cases' ``ENTRY``: one entry per scale the family
    ran at), the entries in :func:`main_entry` order (the main one first, then by name)."""
    found: dict[str, Runs] = {}
    for case, by in runs.items():
        found.setdefault(split_family_case(case)[0], {})[case] = by
    return {name: found[name] for name in sorted(found, key=lambda n: _rank(n, found[n]))}


def options(runs: Runs) -> dict:
    """The family options the entry's runs were made with (their ``job.json``'s
    ``scene.options``; {} at the family's defaults)."""
    for by in runs.values():
        for job in by.values():
            return dict((job.config.get("scene") or {}).get("options") or {})
    return {}


def _rank(name: str, runs: Runs) -> tuple:
    return (bool(options(runs)), name != FAMILY, name)


def main_entry(found: dict[str, Runs]) -> str:
    """The entry the grid, the totals and the table of every run show: the one run at the
    family's defaults (no ``options``: the published proportions); among several such, or
    none, the one named ``imazu``, else the first by name."""
    return min(found, key=lambda n: _rank(n, found[n]))


#: The keys of the events' ``run`` object the section reads (docs/simulate.md).
FACTS = ("goal", "duration_s")


def start(job: JobResults) -> Start | None:
    """The case's situation at the start of the run ``job``: the ships' positions, headings
    and speeds at the trace's first step, their lengths, the goal and the duration from the
    events' ``run`` object; None without the files."""
    run = job_facts(job, FACTS)
    states = first_states(job)
    if run is None or states is None:
        return None
    where = job.dir / "trace.events.json"
    lengths = ship_lengths({"run": run}, where)
    names = [s["name"] for s in run["ships"]]
    if names[0] != OWN or set(names) != set(states):
        raise UsvError(f"{job.dir / 'trace.csv'}: its first step's ships {', '.join(states)} "
                       f"are not run.ships' {', '.join(map(str, names))} ({where})")  # fmt: skip
    own, targets = states[OWN], [states[n] for n in names[1:]]
    try:
        goal = np.asarray(run["goal"], float).reshape(2)
        duration = float(run["duration_s"])
    except (TypeError, ValueError) as e:
        raise UsvError(f"{where}: run.goal must be two numbers and run.duration_s a number "
                       f"({e})") from None  # fmt: skip
    at = assess(np.array([own.x, own.y]), own.heading, own.speed,
                np.array([[t.x, t.y] for t in targets], float).reshape(-1, 2),
                [t.heading for t in targets], [t.speed for t in targets])  # fmt: skip
    return Start(own.speed, tuple(CLASS_NAMES[c] for c in at.cls),
                 tuple(t.speed for t in targets), tuple(map(float, at.range)),
                 tuple(map(float, at.dcpa)), tuple(map(float, at.tcpa)),
                 float(np.hypot(*(goal - (own.x, own.y)))), lengths[0], tuple(lengths[1:]),
                 duration)  # fmt: skip


def counts(job: JobResults) -> tuple[int, int, int, int]:
    """The run's COLREGs counts (:data:`~usvtool.report.runs.VERDICTS`; 0 where
    the table has none)."""
    return tuple(int(job.number(c) or 0) for c in VERDICTS)  # type: ignore[return-value]


def grid_cell(job: JobResults) -> GridCell:
    arrived, collided = bool(job.number("arrived")), bool(job.text("collision"))
    c = counts(job)
    return GridCell(outcome(arrived, collided, c), job.number("closest_distance_m"), c)


def _span(values, unit: str, digits: int = 0) -> str:
    """``lo-hi unit`` (or one value) of the values."""
    lo, hi = min(values), max(values)
    text = f"{lo:.{digits}f}" if round(lo, digits) == round(hi, digits) else \
        f"{lo:.{digits}f}-{hi:.{digits}f}"
    return f"{text} {unit}"


def scale_text(starts: list[Start]) -> str:
    """The scale the cases ran at, from their starts."""
    speeds = sorted({round(v, 1) for s in starts for v in s.speeds})
    durations = {s.duration for s in starts if s.duration is not None}
    parts = [
        f"own ship {_span([s.own_length for s in starts], 'm')} long at "
        f"{_span([s.own_speed for s in starts], 'm/s', 1)}, its goal "
        f"{_span([s.goal_m for s in starts], 'm')} ahead",
        f"targets {_span([v for s in starts for v in s.lengths], 'm')} long at "
        f"{' or '.join(f'{v:.1f}' for v in speeds)} m/s",
        f"at the start every target {_span([r for s in starts for r in s.ranges], 'm')} off, "
        f"its CPA {_span([t for s in starts for t in s.tcpa], 's', 1)} ahead at "
        f"{_span([d for s in starts for d in s.dcpa], 'm', 2)}",
    ]
    if durations:
        parts.append(f"runs end at the goal or after {_span(sorted(durations), 's')}")
    return "; ".join(parts)


def _run_text(job: JobResults) -> Cell:
    """A table cell: failure first, closest distance, the COLREGs counts."""
    cell = grid_cell(job)
    c, e, n, j = cell.counts
    distance = "-" if cell.closest_m is None else f"{cell.closest_m:.1f} m"
    head = {"collided": f"collided ({job.text('collision')}); ",
            "not-arrived": "did not arrive; "}.get(cell.outcome, "")  # fmt: skip
    css = {"collided": "fails", "not-arrived": "fails", "compliant": "holds"}.get(cell.outcome, "")
    return Cell(f"{head}{distance}; {c}/{e}/{n}/{j}", css)


def totals_table(runs: dict[str, dict[str, JobResults]], controllers: list[str]) -> Table:
    """Per controller over the cases: the runs' outcomes and their encounters' COLREGs counts
    (the columns of the encounters section's families table) and the closest distance."""
    rows = []
    for c in controllers:
        jobs = [r[c] for r in runs.values() if c in r]
        closest = [v for v in (j.number("closest_distance_m") for j in jobs) if v is not None]
        rows.append([Cell(c), Cell(str(len(jobs)), "num"), *RunTally.of(jobs).cells(),
                     median_iqr(closest)])  # fmt: skip
    return Table("imazu-totals", "The Imazu cases: totals per controller",
                 f"Each controller's runs of the cases and their encounters. {COUNTS} "
                 "Closest: the median over the runs of the closest centre distance to a target "
                 "(m) and the width of its IQR; every run's in the appendix's table.",
                 ["controller", "cases", *TALLY_COLUMNS, "closest (m)"], rows)  # fmt: skip


def _label(case: str) -> str:
    return split_family_case(case)[1]


def horizons(runs: Runs) -> list[float]:
    """The verdicts' onset TCPA of the runs (their events' ``thresholds.horizon_s``, every
    distinct value; docs/colregs.md, Latching): an encounter starts when its TCPA falls below
    it."""
    found = set()
    for by in runs.values():
        for job in by.values():
            events = job_events(job)
            value = None if events is None else (events[0].get("thresholds") or {}).get(
                "horizon_s")  # fmt: skip
            if isinstance(value, int | float) and not isinstance(value, bool):
                found.add(float(value))
    return sorted(found)


def scale_cell(name: str, starts: list[Start], onset: list[float],
               short: bool = False) -> str:  # fmt: skip
    """An entry's scale in ship lengths (L: the own ship's) and against the verdicts' onset
    TCPA; ``short``: the lengths, the ranges and the CPA's time against the onset alone."""
    if not starts:
        return f"{name}: the runs' files are missing"
    tcpa = [t for s in starts for t in s.tcpa]
    ranges = _span([r / s.own_length for s in starts for r in s.ranges], "L")
    ratio = (_span([t / h for t in (min(tcpa), max(tcpa)) for h in onset], "x", 2)
             if onset else "")  # fmt: skip
    if short:
        return (f"{name}: L {_span([s.own_length for s in starts], 'm')}, {ranges} off, CPA "
                f"{ratio + ' the onset TCPA' if onset else _span(tcpa, 's') + ' ahead'}")
    text = (f"{name}: own ship {_span([s.own_length for s in starts], 'm')} (L) at "
            f"{_span([s.own_speed for s in starts], 'm/s', 1)}; targets "
            f"{_span([v for s in starts for v in s.lengths], 'm')}; at the start "
            f"{ranges} off, the CPA {_span(tcpa, 's')} ahead")  # fmt: skip
    if onset:
        text += f" = {ratio} the onset TCPA ({' or '.join(f'{h:g}' for h in onset)} s)"
    return text


def entry_starts(runs: Runs, starts: dict[str, Start | None]) -> list[Start]:
    """The starts of the entry's cases that have their files."""
    return [s for case in runs if (s := starts.get(case)) is not None]


def sensitivity_table(found: dict[str, Runs], controllers: list[str],
                      starts: dict[str, Start | None]) -> Table:  # fmt: skip
    """One row per scale (an entry) and controller that ran there: its runs, arrived,
    collided, did not arrive, compliant / judged (excused), not judged and the median closest
    distance (m and own ship lengths)."""
    rows = []
    for name, runs in found.items():
        known = entry_starts(runs, starts)
        text = scale_cell(name, known, horizons(runs), short=True)
        own = inference.median([s.own_length for s in known]) if known else None
        first = True
        for c in controllers:
            jobs = [r[c] for r in runs.values() if c in r]
            if not jobs:
                continue
            tally = RunTally.of(jobs)
            if tally.verdicts is None:
                judged, blind = "-", "-"
            else:
                v = tally.verdicts
                total = v["compliant"] + v["compliant_excused"] + v["noncompliant"]
                judged = f"{v['compliant']} / {total} ({v['compliant_excused']})"
                blind = str(v["not_judged"])
            closest = [x for j in jobs if (x := j.number("closest_distance_m")) is not None]
            median = inference.median(closest) if closest else None
            distance = "-" if median is None else f"{median:.1f} m" + (
                f" ({median / own:.1f} L)" if own else "")  # fmt: skip
            outcomes = [Cell(str(tally.outcomes[o]), "num" + (" fails" if tally.outcomes[o]
                                                             and o != "arrived" else ""))
                        for o in OUTCOMES]  # fmt: skip
            rows.append([Cell(text if first else ""), Cell(c), Cell(str(len(jobs)), "num"),
                         *outcomes, Cell(judged, "num"),
                         Cell(blind, "num" + (" untested" if blind not in ("-", "0") else "")),
                         Cell(distance, "num")])  # fmt: skip
            first = False
    return Table(
        "imazu-scales", "The Imazu cases at each scale",
        f"The {len(found)} scales the family ran at (each an entry of the pipeline, its scale "
        "read from its runs' files, in full in the paragraph above: L the own ship's length, "
        "the targets' ranges at the start in L, the time to the CPA at the start over the TCPA "
        "below which the verdicts start an encounter, from the events' thresholds), each with "
        "every controller that ran it: its "
        "runs, their outcomes (a run that collided or did not arrive is a failure, its "
        "encounters never judged), the encounters compliant (no rule failed, none excused) of "
        "those judged, the compliant only through an excused Rule 2 departure in brackets (among "
        "the judged, not the compliant), the encounters not judged, and the median over the "
        "runs of the closest centre distance to a target, in m and in L.",
        ["scale", "controller", "runs", *OUTCOMES, "compliant / judged (excused)", "not judged",
         "closest: median"], rows)  # fmt: skip


#: The line of the section (in the PDF too) that says where its animations are.
ANIMATED = ("Every run of the grid can be watched as it happened in the HTML report (index.html): "
            "the table under the grid opens each run's player.")


def player_id(case: str, controller: str) -> str:
    """The id of the player of the run of ``case`` by ``controller``."""
    return anchor("imazu-run", case, controller)


def players(runs: Runs, controllers: list[str], labels: list[str]) -> Section:
    """Every run of the entry as a player (HTML only, each folded until opened: none starts
    before), case by case, from its trace and events (each read once per report:
    :func:`usvtool.report.runs.run_files`); a run without its files has none."""
    from usvtool.report.animation.embed import run_player

    part = Section("imazu-players", "The Imazu runs, played", placement=HTML)
    part.paragraphs.append(
        "Each run of the grid as it happened (a player: Play, the time slider, the speed; "
        "the keys Space, arrows, comma and full stop, Home and End once it has the focus): "
        "every ship's hull to scale along her heading, the own ship's domain, the wakes, the "
        "route and goal, each target's COLREGs class, the verdict events on the timeline, the "
        "clock and the distance to the nearest ship (docs/animate.md). Open one here or from "
        "the table under the grid.")
    for case, label in zip(runs, labels, strict=True):
        for c in controllers:
            job = runs[case].get(c)
            files = None if job is None else run_files(job)
            if files is None:
                continue
            cell = grid_cell(job)
            part.blocks.append(run_player(
                *files, player_id(case, c), f"Case {label} with {c}: {_run_text(job).text}",
                f"{case}, {c}, seed {job.seed}: the outcome, the closest centre distance to a "
                "target and the encounters compliant / excused only / non-compliant / not "
                "judged." + (" A failure." if cell.outcome in ("collided", "not-arrived")
                             else "")))  # fmt: skip
    return part


def players_table(runs: Runs, controllers: list[str], labels: list[str],
                  played: set[str]) -> Table:  # fmt: skip
    """The grid's cells as links to their players (``played``: the ids of those there; HTML
    only)."""
    rows = []
    for case, label in zip(runs, labels, strict=True):
        row = [Cell(label)]
        for c in controllers:
            job = runs[case].get(c)
            if job is None:
                row.append(Cell("no run"))
                continue
            cell = grid_cell(job)
            text = {"collided": "collided", "not-arrived": "did not arrive"}.get(
                cell.outcome, "-" if cell.closest_m is None else f"{cell.closest_m:.0f} m")
            css = {"collided": "fails", "not-arrived": "fails"}.get(cell.outcome, "")
            known = player_id(case, c) in played
            row.append(Cell(("▶ " if known else "") + text, css,
                            player_id(case, c) if known else ""))  # fmt: skip
        rows.append(row)
    return Table("imazu-players-table", "The Imazu grid's runs, played",
                 "The grid's cells as links: each opens its run's player (in the part below, "
                 "The Imazu runs, played). Each cell: the outcome of a failure, else the "
                 "closest centre distance to a target.",
                 ["case", *controllers], rows, placement=HTML)  # fmt: skip


def section(results: Results) -> Section | None:
    every = imazu_runs(results)
    if not every:
        return None
    found = entries(every)
    main = main_entry(found)
    runs = found[main]
    order = results.methods("runs")
    controllers = sorted({c for r in runs.values() for c in r}, key=order.index)
    cases = list(runs)
    starts = {case: start(next(iter(r.values()))) for case, r in every.items()}
    classes = {case: " ".join(SHORT.get(c, c) for c in s.classes) if s else "?"
               for case, s in starts.items()}  # fmt: skip
    labels = [f"{_label(case)} {classes[case]}" for case in cases]
    tallies = {c: RunTally.of([r[c] for r in runs.values() if c in r]) for c in controllers}
    headers = [f"{c}\n{sum(t.outcomes.values())} runs: {t.outcomes['arrived']} arrived\n"
               f"{t.outcomes['collided']} collided" for c, t in tallies.items()]  # fmt: skip
    cells = {(case, c): grid_cell(job) for case, r in runs.items() for c, job in r.items()}
    known = [s for case in cases if (s := starts[case]) is not None]
    scale = scale_text(known) if known else "the runs' files are missing"
    seeds = sorted({j.seed for r in runs.values() for j in r.values() if j.seed is not None})
    top = Section("imazu", "The Imazu problem")
    top.paragraphs.append(
        f"The {len(cases)} encounters of the Imazu problem (Imazu 1987; as tabulated by Sawada, "
        "Sato and Majima 2021, J. Mar. Sci. Technol. 26, Table 4; docs/families.md says how the "
        "cases were read from two public implementations of that table), a standard benchmark "
        f"of multi-ship collision avoidance, run with every controller ({', '.join(controllers)}"
        f"; seed {', '.join(map(str, seeds)) or 'none'}). Every target meets the own ship at one "
        f"point if neither gives way. At the scale run here (read from the runs): {scale}. "
        f"Classes at the start: HO head-on, GW crossing give-way, SO crossing stand-on, OT "
        "overtaking.")
    if len(found) > 1:
        others = [n for n in found if n != main]
        why = ("run at the family's defaults, the published proportions" if not options(runs)
               else "named as the family" if main == FAMILY else "the first by name")
        top.paragraphs.append(
            f"The family ran at {len(found)} scales, one pipeline entry each ({', '.join(found)})"
            f": the totals, the grid and every run below are those of {main} ({why}); "
            f"{', '.join(others)} {'is' if len(others) == 1 else 'are'} beside it in the table "
            "of the scales, after the totals. The scales, read from the runs (L the own ship's "
            "length; the onset TCPA the verdicts': an encounter starts when its TCPA falls "
            "below it): " + "; ".join(scale_cell(n, entry_starts(r, starts), horizons(r))
                                     for n, r in found.items()) + ".")  # fmt: skip
    top.blocks.append(totals_table(runs, controllers))  # short: it fills a page before the grid
    if len(found) > 1:
        every_controller = sorted({c for r in every.values() for c in r}, key=order.index)
        top.blocks.append(sensitivity_table(found, every_controller, starts))
    plot = imazu_grid(cases, labels, controllers, cells, headers)
    top.blocks.append(Figure(
        "imazu-grid", "The Imazu cases with every controller",
        "Each cell one run: its outcome (colour; the failures hatched), its closest centre "
        "distance to a target and its compliant encounters of all (no rule failed, none "
        "excused). A run that did not arrive is a failure, its encounters never compliant; an "
        "arrived run's colour is its worst encounter.", plot.png, plot.data))
    played = players(runs, controllers, labels)
    if played.blocks:
        top.paragraphs.append(ANIMATED)
        top.blocks.append(players_table(runs, controllers, labels,
                                        {b.id for b in played.blocks}))  # fmt: skip
        top.subsections.append(played)
    rows = [[Cell(_label(case)), Cell(classes[case])]
            + [_run_text(runs[case][c]) if c in runs[case] else Cell("no run")
               for c in controllers] for case in cases]  # fmt: skip
    thresholds = thresholds_table([j for r in every.values() for j in r.values()])
    top.blocks.append(Table(
        "imazu-table", "The Imazu cases: every run",
        "Per run: a failure first (a collision, naming what was hit, or no arrival), the "
        "closest centre distance to a target, then its encounters compliant / compliant only "
        "through an excused Rule 2 departure / non-compliant / not judged (every encounter of "
        "a failed run is not judged; docs/colregs.md, Counting)."
        + (" The thresholds of the verdicts: the next table." if thresholds else ""),
        ["case", "targets", *controllers], rows, placement=APPENDIX))
    if thresholds is not None:
        top.blocks.append(replace(
            thresholds, id="imazu-thresholds", title="The thresholds of the Imazu verdicts",
            caption=thresholds.caption.replace("the tables above", "the Imazu cases"),
            placement=APPENDIX))
    return top
