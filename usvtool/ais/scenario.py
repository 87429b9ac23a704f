"""``usvtool ais scenario``: a window of real traffic as a scenario YAML that ``usvtool simulate``
runs with any controller (the format of docs/scenario.md; the scenario itself is
:func:`usvtool.traffic.traffic_scenario`'s, which the simulation's ``ais`` scene family makes
too: this stage imports no other).

The own ship is the vessel ``--own`` (the USV under test takes her place, with its own
``--vessel`` preset): she starts at her position at the window's start, on her course over
ground and at her speed over ground there, bound for her position at the window's end, and her
recorded track is the scenario's ``route``. The window is ``--start`` … ``--end`` (her track
that spans most of it), or an encounter's (``usvtool ais encounters``: its start and end)
widened by ``--pad`` seconds on each side; either way cut to the own ship's track. Every other
track that comes within ``--radius`` metres of her recorded track during the window is a target
replaying its track; lon/lat on a ``--map`` with a CRS, else the local UTM metre frame
(:mod:`usvtool.traffic`).

Text from the inputs (a path, a vessel's name) goes into the YAML's header comments with its
line breaks and other control characters escaped (:func:`usvtool.yamlfile.comment`), so it
cannot end a comment. Beside the scenario, :data:`MANIFEST` lists the files written; the next ``ais
scenario`` into that directory removes those of them it does not write again (a previous
window's targets), and nothing else.
"""

from __future__ import annotations

import json
import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from usvtool.errors import UsvError
from usvtool.tracks import Tracks
from usvtool.traffic import (
    pick_encounter,
    read_encounters,
    scenario_yaml,
    scene_encounter,
    traffic_scenario,
)

SCENARIO = "scenario.yaml"
#: The list of the files ``ais scenario`` wrote into its directory.
MANIFEST = "scenario.manifest.json"
#: The names ``ais scenario`` writes (the manifest's other entries are never removed).
_WRITES = re.compile(r"scenario\.yaml|route\.geojson|ais-\d+(-\d+)?\.csv")


@dataclass(frozen=True)
class ScenarioOptions:
    """``own`` MMSI; the window as ``start``/``end`` (ISO 8601 UTC) or ``encounter`` (a rank
    of the ``encounters`` CSV); ``radius`` m; ``map`` a grid GeoTIFF or None; ``vessel`` the
    USV's preset; ``controller``; ``pad`` s; ``duration`` s (None: twice the window)."""

    own: int | None = None
    start: str | None = None
    end: str | None = None
    encounter: int | None = None
    encounters: str | None = None
    radius: float = 2000.0
    map: str | None = None
    vessel: str = "udwa-usv"
    controller: str = "udwa"
    pad: float = 60.0
    duration: float | None = None

    def __post_init__(self):
        if (self.encounter is None) == (self.start is None and self.end is None):
            raise UsvError("ais scenario: give --start and --end, or --encounter (not both)")
        if self.encounter is None and (self.start is None or self.end is None or self.own is None):
            raise UsvError("ais scenario: --start and --end need each other and --own")
        if self.encounter is not None and self.encounters is None:
            raise UsvError("--encounter: name the encounters file with --encounters")
        for name in ("radius", "pad", "duration"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value >= 0):
                raise UsvError(f"--{name}: must be a number >= 0, not {value}")


@dataclass
class ScenarioResult:
    """The files' texts (name relative to the output directory: text) and the summary."""

    files: dict[str, str]
    figures: dict

    def summary(self) -> dict:
        return dict(self.figures)


def make_scenario(tracks: Tracks, options: ScenarioOptions,
                  directory: str | os.PathLike = ".") -> ScenarioResult:  # fmt: skip
    """The scenario files of ``options``' window of ``tracks`` (module docstring), to be written
    into ``directory`` (the map is named relative to it)."""
    own, window, encounter = _window(tracks, options)
    what = (f"usvtool ais scenario, encounter {encounter} of {options.encounters}"
            if encounter is not None else "usvtool ais scenario, a window")  # fmt: skip
    made = traffic_scenario(tracks, own, window, radius=options.radius, vessel=options.vessel,
                            controller=options.controller, duration=options.duration,
                            map_path=options.map, directory=directory, what=what)  # fmt: skip
    return ScenarioResult({**made.files, SCENARIO: scenario_yaml(made.scenario, made.comments)},
                          {**made.figures, "encounter": encounter})  # fmt: skip


def scenario_paths(directory: str | os.PathLike, result: ScenarioResult) -> list[Path]:
    """The paths :func:`write_scenario` writes, the scenario first."""
    out = Path(directory)
    return [out / SCENARIO] + [out / n for n in result.files if n != SCENARIO]


def write_scenario(directory: str | os.PathLike, result: ScenarioResult,
                   extra: dict | None = None) -> list[Path]:  # fmt: skip
    """Write the files and their :data:`MANIFEST` into ``directory`` (made if missing; its
    parent must exist), and the texts ``extra`` (path: text, e.g. the summary), all renamed at
    the end or none (:class:`usvtool.atomic.staged`); then remove the files the previous
    manifest there lists and these do not replace. The paths of :func:`scenario_paths`."""
    from usvtool.atomic import staged

    out = Path(directory)
    if out.exists() and not out.is_dir():
        raise UsvError(f"-o {out}: is a file, not a directory")
    if not out.parent.is_dir():
        raise UsvError(f"-o {out}: directory {out.parent} does not exist")
    out.mkdir(exist_ok=True)
    previous = written_before(out)
    paths = scenario_paths(out, result)
    names = [p.name for p in paths]
    manifest = json.dumps({"written_by": "usvtool ais scenario", "files": names}, indent=1)
    texts = [result.files[n] for n in names] + [manifest + "\n", *(extra or {}).values()]
    with staged(*paths, out / MANIFEST, *(extra or {})) as temporaries:
        for text, tmp in zip(texts, temporaries, strict=True):
            tmp.write_text(text, encoding="utf-8")
    for name in sorted(previous - set(names)):
        (out / name).unlink(missing_ok=True)
    return paths


def written_before(directory: Path) -> set[str]:
    """The files of ``directory`` that its :data:`MANIFEST` says ``ais scenario`` wrote, and
    still there (none without a readable manifest; only names it writes: never a path)."""
    try:
        listed = json.loads((directory / MANIFEST).read_text(encoding="utf-8"))["files"]
    except (OSError, ValueError, KeyError, TypeError):
        return set()
    if not isinstance(listed, list):
        return set()
    return {n for n in listed if isinstance(n, str) and _WRITES.fullmatch(n)
            and (directory / n).is_file()}  # fmt: skip


def _window(tracks: Tracks, options: ScenarioOptions) -> tuple[int, tuple[int, int], int | None]:
    """(the own ship's track ordinal, the window (ns; an encounter's cut to her track), the
    encounter's rank or None)."""
    if options.encounter is not None:
        rows = read_encounters(options.encounters)
        row = pick_encounter(rows, "any", options.encounter, 0.0, options.encounters,
                             "--encounter")  # fmt: skip
        own = options.own if options.own is not None else row["mmsi_a"]
        if own not in (row["mmsi_a"], row["mmsi_b"]):
            raise UsvError(f"--own {own}: not a vessel of encounter {options.encounter} "
                           f"({row['mmsi_a']}, {row['mmsi_b']})")  # fmt: skip
        scene = scene_encounter(tracks, row, "a" if own == row["mmsi_a"] else "b", options.pad,
                                options.encounters)  # fmt: skip
        return scene.own, scene.window, options.encounter
    import pyarrow as pa

    from usvtool.csvtable import time_ns

    try:
        t0, t1 = (int(v) for v in time_ns("--start/--end", pa.array([options.start,
                                                                    options.end]), "", 0))
    except UsvError:
        raise UsvError(f"--start/--end: {options.start!r}, {options.end!r} are not ISO 8601 "
                       "times") from None  # fmt: skip
    if t1 <= t0:
        raise UsvError(f"--end {options.end}: not after --start {options.start}")
    first, stop = tracks.track_bounds()
    candidates = np.flatnonzero((tracks.mmsi[first] == options.own) & (tracks.time[first] < t1)
                                & (tracks.time[stop - 1] > t0))  # fmt: skip
    if candidates.size == 0:
        raise UsvError(f"--own {options.own}: no track of that MMSI in {options.start} … "
                       f"{options.end}")  # fmt: skip
    spans = np.minimum(tracks.time[stop - 1][candidates], t1) - np.maximum(
        tracks.time[first][candidates], t0)  # fmt: skip
    return int(candidates[np.argmax(spans)]), (t0, t1), None
