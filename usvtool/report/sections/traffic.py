"""The report's real-traffic section: the runs of the ``ais`` scene family (recorded
close-quarters encounters, docs/ais.md), every controller in each encounter beside what the
real vessel did there.

A scene is one encounter of an encounters file (``usvtool ais encounters``), the USV in the
place of one of its two vessels, the others replayed from their tracks. What the scene was is
read from the run's own files: its ``summary.json`` names the family's options (every one, the
defaults filled in: the encounters file, the tracks file, which vessel the USV replaces, the
pad), and from those files, through :mod:`usvtool.traffic` (the contract the family made the
scenario with), the encounter's row (its vessels, class at first detection, window and
recorded CPA), and the own vessel's recorded manoeuvre over the encounter's window
(:func:`usvtool.traffic.manoeuvre`). Per run: its outcome (a run that did not arrive or
collided is a failure), the closest distance to any ship (the results table's) and to the
encounter's other vessel (its summary's ``per_target``), and its encounters' COLREGs counts.
The tables read no trace (a run of real traffic writes some 12 MB of it); in the HTML report
only, each run is a player (:func:`players`: its trace and events read once, folded until
opened), linked from its row of the runs' table, and the section's text says so in the PDF too
(:data:`ANIMATED`).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from usvtool.digest import sha256
from usvtool.errors import UsvError
from usvtool.report.data import JobResults, Results
from usvtool.report.document import HTML, Cell, Section, Table, anchor, number
from usvtool.report.runs import (
    COUNTS,
    MARKS,
    VERDICT_HEADINGS,
    VERDICTS,
    family_runs,
    outcome,
    run_files,
)
from usvtool.tracks import NS, Tracks, read_tracks
from usvtool.traffic import (
    Manoeuvre,
    SceneEncounter,
    manoeuvre,
    pick_encounter,
    read_encounters,
    scene_encounter,
)

FAMILY = "ais"


@cache
def _tracks(path: str) -> Tracks:
    return read_tracks(path)


@cache
def _encounters(path: str) -> list[dict]:
    return read_encounters(path)


@dataclass(frozen=True)
class Recorded:
    """A scene's encounter as recorded: which it is, its files, the own vessel's letter
    (``a``/``b``), her name and MMSI, the other's, the encounter as a scene and her
    manoeuvre over the encounter's window."""

    kind: str
    number: int
    encounters: str
    at: SceneEncounter
    own: str
    manoeuvre: Manoeuvre

    def vessel(self, letter: str) -> str:
        row = self.at.row
        name = row[f"name_{letter}"]
        return f"{name} ({row[f'mmsi_{letter}']})" if name else str(row[f"mmsi_{letter}"])

    @property
    def other_letter(self) -> str:
        return "b" if self.own == "a" else "a"


def traffic_runs(results: Results) -> dict[str, dict[str, JobResults]]:
    """The ``ais`` family's runs (their ``job.json``'s ``scene.family``): case
    (``ENTRY/KIND/sNNN``) -> controller -> the run of its lowest seed."""
    return family_runs(results, FAMILY)


def recorded(job: JobResults) -> Recorded | None:
    """The encounter of the run ``job`` as recorded, from its ``summary.json``'s scene and the
    files it names (None without the summary; refused when those files are gone)."""
    summary = _summary(job)
    if summary is None:
        return None
    path = job.dir / "summary.json"
    try:
        scene = summary["scene"]
        options, kind, number = scene["options"], scene["kind"], int(scene["scene"])
        files = {k: str(options[k]) for k in ("encounters", "tracks")}
        own, pad, min_speed = options["own"], float(options["pad"]), float(options["min_speed"])
    except (KeyError, TypeError, ValueError) as e:
        raise UsvError(f"{path}: not the summary of an ais family run ({e})") from None
    digests = (job.config.get("scene") or {}).get("sha256") or {}  # job.json's, when there
    for key, file in files.items():
        if not Path(file).is_file():
            raise UsvError(f"{path}: scene.options.{key} {file}: no such file (moved or removed "
                           "since the run?)")  # fmt: skip
        if key in digests and _sha256(file) != digests[key]:
            raise UsvError(f"{path}: scene.options.{key} {file}: changed since the run (not "
                           "the bytes its job.json records): run the batch again")  # fmt: skip
    tracks = _tracks(files["tracks"])
    row = pick_encounter(_encounters(files["encounters"]), kind, number, min_speed,
                         files["encounters"], f"{path}: scene")  # fmt: skip
    at = scene_encounter(tracks, row, own, pad, files["encounters"])
    return Recorded(kind, number, files["encounters"], at, own,
                    manoeuvre(tracks, at.own, *at.times))  # fmt: skip


@cache
def _sha256(path: str) -> str:
    """A file's SHA-256, read once per report (a tracks file may be large)."""
    return sha256(path)


def _summary(job: JobResults) -> dict | None:
    path = job.dir / "summary.json"
    if not path.is_file():
        return None
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except ValueError as e:
        raise UsvError(f"{path}: not JSON ({e})") from None


def per_target(job: JobResults, other: int) -> tuple[int, float | None] | None:
    """The run's targets (its contacts) and its closest distance to the encounter's other
    vessel (any of her tracks: ``ais-MMSI`` or ``ais-MMSI-TRACK``), from its summary's
    ``per_target`` (None without it)."""
    summary = _summary(job)
    if summary is None or not isinstance(summary.get("per_target"), list):
        return None
    name = f"ais-{other}"
    distances = [t.get("closest_distance_m") for t in summary["per_target"]
                 if t.get("target") == name or str(t.get("target")).startswith(name + "-")]
    distances = [d for d in distances if isinstance(d, int | float)]
    return len(summary["per_target"]), (min(distances) if distances else None)


def _course(m: Manoeuvre) -> str:
    return (f"{m.course_start:.0f} → {m.course_end:.0f} (net {m.course_change:+.0f}, largest "
            f"{m.largest_turn:+.0f})")


def _speed(m: Manoeuvre) -> str:
    return f"{m.speed_start:.1f} → {m.speed_end:.1f} ({m.speed_min:.1f}-{m.speed_max:.1f})"


def _outcome(job: JobResults) -> Cell:
    """The run's outcome, a failure marked: arrived (its time), collided (with what), did not
    arrive."""
    what = outcome(job)
    if what == "arrived":
        time = job.number("arrival_time_s")
        return Cell("arrived" + ("" if time is None else f" ({time:.0f} s)"), "holds")
    if what == "collided":
        return Cell(f"collided ({job.text('collision')})", "fails")
    return Cell("did not arrive", "fails")


def _counts(job: JobResults) -> list[Cell]:
    cells = []
    for v in VERDICTS:
        n = job.number(v)
        cells.append(Cell("-" if n is None else str(int(n)),
                          "num" + (MARKS.get(v, "") if n else "")))  # fmt: skip
    return cells


def encounters_table(scenes: dict[str, Recorded], contacts: dict[str, int | None]) -> Table:
    """Each scene's encounter as recorded (module docstring)."""
    rows = []
    for case, rec in scenes.items():
        row, own = rec.at.row, rec.own
        t0, t1 = rec.at.times
        cls = row[f"class_{own}"] + (" (censored)" if row["censored"] else "")
        n = contacts.get(case)
        rows.append([Cell(case), Cell(str(row["rank"]), "num"), Cell(rec.vessel(own)),
                     Cell(rec.vessel(rec.other_letter)), Cell(cls),
                     number((t1 - t0) / NS, 0), Cell("-" if n is None else str(n), "num"),
                     number(row["cpa_m"], 1), Cell(_course(rec.manoeuvre)),
                     Cell(_speed(rec.manoeuvre))])  # fmt: skip
    files = ", ".join(sorted({Path(r.encounters).name for r in scenes.values()}))
    return Table("traffic-encounters", "Recorded encounters: what the real vessels did",
                 f"The encounters of {files} (usvtool ais encounters, ranked by CPA) that the "
                 "runs replay: the USV in the place of the own vessel, the other vessels "
                 "replayed from their AIS tracks. Class: the other vessel seen from the own at "
                 "first detection (docs/colregs.md; censored: the encounter may have begun "
                 "before the recording or gone on after it). Window: the encounter's, from "
                 "first detection to its end. Contacts: the vessels the scenario replays "
                 "(within its radius of the own vessel's track). Recorded CPA: between the two "
                 "vessels, refined between the 10 s samples. Her course over ground (deg) at "
                 "the window's start and end, the net change and the largest turn from the "
                 "first course (> 0 to starboard), and her speed over ground (kn) at the start "
                 "and end (slowest-fastest), over her track's segments in the window.",
                 ["scene", "rank", "own vessel (the USV's place)", "other vessel", "class",
                  "window (s)", "contacts", "recorded CPA (m)", "her course (deg)",
                  "her speed (kn)"], rows)  # fmt: skip


#: The line of the section (in the PDF too) that says where its animations are.
ANIMATED = ("Each run can be watched as it happened, every recorded vessel with it, in the HTML "
            "report (index.html): its controller's name in the runs' table opens its player.")


def player_id(case: str, controller: str) -> str:
    """The id of the player of the run of ``case`` by ``controller``."""
    return anchor("traffic-run", case, controller)


def players(scenes: dict[str, Recorded], runs: dict[str, dict[str, JobResults]],
            controllers: list[str]) -> Section:  # fmt: skip
    """Each run of each recorded encounter as a player (HTML only, folded until opened), from
    its trace and events (read once per report: :func:`usvtool.report.runs.run_files`); a run
    without them has none."""
    from usvtool.report.animation.embed import run_player

    part = Section("traffic-players", "The recorded encounters, played", placement=HTML)
    part.paragraphs.append(
        "Each controller's run of each recorded encounter as it happened (docs/animate.md): the "
        "USV in the own vessel's place, every other vessel replayed from her AIS track, each "
        "hull to scale along her heading, the wakes, the route (the own vessel's recorded "
        "track) and goal, each target's COLREGs class, the verdict events on the timeline, the "
        "clock and the distance to the nearest ship.")
    for case, rec in scenes.items():
        for c in controllers:
            job = runs[case].get(c)
            files = None if job is None else run_files(job)
            if files is None:
                continue
            part.blocks.append(run_player(
                *files, player_id(case, c),
                f"{case} with {c}: {_outcome(job).text}, the USV in the place of "
                f"{rec.vessel(rec.own)}",
                f"{case}, {c}, seed {job.seed}; the other vessel of the encounter: "
                f"{rec.vessel(rec.other_letter)}, recorded CPA "
                f"{number(rec.at.row['cpa_m'], 1).text} m."))  # fmt: skip
    return part


def runs_table(scenes: dict[str, Recorded], runs: dict[str, dict[str, JobResults]],
               controllers: list[str], played: frozenset[str] = frozenset()) -> Table:
    """Per scene, the recorded vessel's row and each controller's run (module docstring); a
    run with a player (its id in ``played``) links to it from its controller's name."""
    rows = []
    for case, rec in scenes.items():
        rows.append([Cell(case), Cell("recorded"), Cell("-"), Cell("-", "num"),
                     number(rec.at.row["cpa_m"], 1), *(Cell("") for _ in VERDICTS)])
        for c in controllers:
            job = runs[case].get(c)
            if job is None:
                continue
            targets = per_target(job, rec.at.other)
            link = player_id(case, c)
            rows.append([Cell(case), Cell(c, link=link if link in played else ""), _outcome(job),
                         number(job.number("closest_distance_m"), 1),
                         number(None if targets is None else targets[1], 1), *_counts(job)])
    return Table("traffic-runs", "Recorded encounters: every controller beside the real vessel",
                 "Each scene's recorded vessel (her row: her recorded CPA with the other "
                 "vessel; her manoeuvre in the table before) and each controller's run of it "
                 "(its lowest seed). Outcome: a run that did not arrive or collided is a "
                 "failure. Closest: the smallest centre distance to any ship over the run; to "
                 "the other: to the encounter's other vessel (both m). " + COUNTS,
                 ["scene", "who", "outcome", "closest (m)", "to the other (m)",
                  *VERDICT_HEADINGS], rows)  # fmt: skip


def section(results: Results) -> Section | None:
    runs = traffic_runs(results)
    if not runs:
        return None
    order = results.methods("runs")
    controllers = sorted({c for r in runs.values() for c in r}, key=order.index)
    scenes: dict[str, Recorded] = {}
    for case, mine in runs.items():
        rec = next((r for r in map(recorded, mine.values()) if r is not None), None)
        if rec is not None:
            scenes[case] = rec
    contacts = {}
    for case, rec in scenes.items():
        found = (per_target(job, rec.at.other) for job in runs[case].values())
        contacts[case] = next((t[0] for t in found if t is not None), None)
    top = Section("traffic", "Real traffic: recorded encounters")
    jobs = [j for r in runs.values() for j in r.values()]
    failed = sum(1 for j in jobs if outcome(j) != "arrived")
    top.paragraphs.append(
        f"{len(runs)} close-quarters encounters recorded by AIS (the ais scene family, "
        "docs/ais.md), each a scenario in which the USV under test takes the place of one of "
        "the two vessels, from her position at the window's start toward her position at its "
        "end, her recorded track as the route, every other vessel within the radius replayed "
        f"from its track (they do not react to the USV). {len(controllers)} controllers, "
        f"{len(jobs)} runs: {len(jobs) - failed} arrived, {failed} failed (did not arrive or "
        "collided). Beside each, what the real vessel did: her recorded CPA with the other "
        "vessel and her course and speed over the encounter.")
    if len(scenes) < len(runs):
        top.paragraphs.append(f"{len(runs) - len(scenes)} scene(s) without their runs' summary "
                              "files are left out of the tables.")  # fmt: skip
    if scenes:
        played = players(scenes, runs, controllers)
        ids = frozenset(b.id for b in played.blocks)
        if ids:
            top.paragraphs.append(ANIMATED)
        top.blocks += [encounters_table(scenes, contacts),
                       runs_table(scenes, runs, controllers, ids)]  # fmt: skip
        if ids:
            top.subsections.append(played)
    return top

