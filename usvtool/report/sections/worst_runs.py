"""The report's part "The worst runs, played": for every scene family entry (a group: the
cases' ``ENTRY``, ``emergency``, ``imazu-compressed``, ``trafficgen``, ...) and every
controller that ran it, its worst run, and in the HTML report that run's player.

The worst run is the one that failed worst, else came closest (:func:`worst`): a run that
collided, then one that did not arrive (a controller that failed among them: a failure as the
others), then the rest, each by its closest centre distance to a target (the results table's
``closest_distance_m``; unknown after any known), then its case and seed. Judged from the
results table alone (:func:`worst_runs`: no file read); only the runs chosen have their trace
and events read, once (:func:`usvtool.report.runs.run_files`), for their players
(:func:`players`, HTML only, folded until opened). The recorded-traffic runs are left out (the
traffic section plays every one), and so are the main Imazu entry's: the Imazu section plays
every one, and the table links to its player.
"""

from __future__ import annotations

import math

from usvtool.report.data import JobResults, Results
from usvtool.report.document import HTML, Cell, Section, Table, anchor, number
from usvtool.report.runs import EVENTS, TRACE, family, is_family, outcome, run_files

#: Families whose every run a section of their own plays: left out here.
PLAYED_ELSEWHERE = ("ais",)
#: Outcomes from the worst.
RANK = {"collided": 0, "did not arrive": 1, "arrived": 2}


# --- judging: the results table only --------------------------------------------------------


def worst(jobs: list[JobResults]) -> JobResults:
    """The worst of the runs (module docstring)."""

    def key(job: JobResults) -> tuple:
        closest = job.number("closest_distance_m")
        return (RANK[outcome(job)], math.inf if closest is None else closest, job.case,
                job.seed or 0, job.key)  # fmt: skip

    return min(jobs, key=key)


def worst_runs(results: Results) -> dict[tuple[str, str], tuple[JobResults, int]]:
    """(group, controller) -> the worst run and how many runs it is the worst of, every scene
    family entry's (but :data:`PLAYED_ELSEWHERE`'s), the groups by name, the controllers in
    the results' order."""
    found: dict[tuple[str, str], list[JobResults]] = {}
    for job in results.select("runs"):
        if is_family(job.case) and family(job) not in PLAYED_ELSEWHERE:
            found.setdefault((job.case.split("/")[0], job.method), []).append(job)
    order = results.methods("runs")
    keys = sorted(found, key=lambda k: (k[0], order.index(k[1])))
    return {k: (worst(found[k]), len(found[k])) for k in keys}


# --- the page -------------------------------------------------------------------------------


def player_id(group: str, controller: str) -> str:
    return anchor("worst-run", group, controller)


def _outcome_cell(job: JobResults) -> Cell:
    what = outcome(job)
    if what == "collided":
        return Cell(f"collided ({job.text('collision')})", "fails")
    return Cell(what, "fails" if what != "arrived" else "")


def players(chosen: dict[tuple[str, str], tuple[JobResults, int]],
            elsewhere: dict[str, str]) -> Section:  # fmt: skip
    """The chosen runs' players (HTML only), but those another section plays (``elsewhere``:
    a run's key -> its player's id there)."""
    from usvtool.report.animation.embed import run_player

    part = Section("worst-runs-players", "The worst runs, played", placement=HTML)
    for (group, c), (job, n) in chosen.items():
        if job.key in elsewhere:
            continue
        files = run_files(job)
        if files is None:
            continue
        closest = job.number("closest_distance_m")
        part.blocks.append(run_player(
            *files, player_id(group, c),
            f"{group} with {c}: {job.case}, {outcome(job)}"
            + ("" if closest is None else f", closest {closest:.1f} m"),
            f"The worst of {c}'s {n} runs of {group} (seed {job.seed}), as it happened "
            "(docs/animate.md)."))  # fmt: skip
    return part


def table(chosen: dict[tuple[str, str], tuple[JobResults, int]], links: dict[str, str]) -> Table:
    """One row a group and controller: its runs, the worst one, how it ended, its closest
    distance; the run's name links to its player (``links``: a run's key -> its id)."""
    rows = []
    for (group, c), (job, n) in chosen.items():
        rows.append([Cell(group), Cell(c), Cell(str(n), "num"),
                     Cell(f"{job.case} (seed {job.seed})", link=links.get(job.key, "")),
                     _outcome_cell(job), number(job.number("closest_distance_m"), 1)])  # fmt: skip
    return Table("worst-runs-table", "The worst run of each scene family per controller",
                 "Per scene family entry and controller: its runs and the worst of them (a run "
                 "that collided, then one that did not arrive, then the smallest closest centre "
                 "distance to a target), how it ended and its closest distance (m). In the HTML "
                 "report the run's name opens its player.",
                 ["family", "controller", "runs", "worst run", "outcome", "closest (m)"],
                 rows)  # fmt: skip


def section(results: Results) -> Section | None:
    chosen = worst_runs(results)
    if not chosen:
        return None
    elsewhere = imazu_players(results)
    part = players(chosen, elsewhere)
    played = {b.id for b in part.blocks}
    links = {job.key: elsewhere.get(job.key, player_id(g, c)) for (g, c), (job, _) in
             chosen.items() if job.key in elsewhere or player_id(g, c) in played}  # fmt: skip
    top = Section("worst-runs", "The worst runs, played")
    top.paragraphs.append(
        f"The worst run of every controller in each of the {len({g for g, _ in chosen})} scene "
        "family entries (the recorded traffic's apart: its section plays every run): the one "
        "that collided, else did not arrive, else came closest to a target. Each can be "
        "watched as it happened in the HTML report (index.html), from its name in the table"
        + (" (the main Imazu entry's in the Imazu section, which plays every run)"
           if any(k in elsewhere for k in links) else "") + ".")  # fmt: skip
    top.blocks.append(table(chosen, links))
    if part.blocks:
        top.subsections.append(part)
    return top


def imazu_players(results: Results) -> dict[str, str]:
    """The runs the Imazu section plays (its main entry's, with their files: the condition of
    :func:`usvtool.report.runs.run_files`, without reading them here): a run's key -> its
    player's id there."""
    from usvtool.report.sections import imazu

    every = imazu.imazu_runs(results)
    if not every:
        return {}
    found = imazu.entries(every)
    return {job.key: imazu.player_id(case, c)
            for case, by in found[imazu.main_entry(found)].items() for c, job in by.items()
            if all((job.dir / name).is_file() for name in (TRACE, EVENTS))}  # fmt: skip
