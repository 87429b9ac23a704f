"""``ais``: recorded traffic, one scene per close-quarters encounter of an encounters file
(``usvtool ais encounters``) and the tracks it was found in (``usvtool ais read``), the USV
under test in the place of one of the encounter's two vessels (docs/ais.md).

Scene ``n`` of kind ``any`` is the encounter of rank ``n``; of kind ``under-way``, the ``n``-th
closest encounter whose two vessels both make ``min_speed`` kn at first detection
(:func:`usvtool.traffic.pick_encounter`): scenes count from 1, as ranks do. The scenario is
:func:`usvtool.traffic.traffic_scenario`'s, the one ``usvtool ais scenario --encounter``
writes: the own ship is vessel ``own`` (``a``, the encounter's first, or ``b``) with the
``vessel`` preset, from her position at the window's start (the encounter's, ``pad`` seconds
wider on each side) toward her position at its end, her recorded track the ``route``; every
other vessel within ``radius`` m of her recorded track is replayed from its track; the local
UTM metre frame (its origin in the file's comments), or with ``map`` (a navigation grid with a
CRS) on that grid: every point in lon/lat, the own ship's start and goal navigable cells
(refused in one line otherwise), the grid copied beside the scene as ``<stem>.map.tif``. The
run lasts ``duration`` s (0: twice the window). The scene's name is that scenario's
(``ais-MMSI-TIME``: the own vessel and the window's start) with the options given that differ
from the defaults appended.

Nothing is drawn: the scene number is the encounter's. Promise, checked as the scene is made
(refused in one line otherwise): the encounter's other vessel is one of the targets (a
``radius`` smaller than the encounter's CPA loses her). A recorded start need not be clear: a
vessel alongside the own ship at the window's start is a target in contact at once.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from usvtool.errors import UsvError
from usvtool.grid import read_grid
from usvtool.params import NON_NEGATIVE, POSITIVE, Param
from usvtool.sim.families.base import Draw, Family, MapFile, vessel_option
from usvtool.tracks import read_tracks
from usvtool.traffic import (
    KINDS,
    pick_encounter,
    read_encounters,
    scene_encounter,
    traffic_scenario,
)


class TextFile:
    """A scene's text file (a replayed track, the route): ``write(path)`` writes it."""

    def __init__(self, text: str):
        self.text = text

    def write(self, path) -> None:
        Path(path).write_text(self.text, encoding="utf-8")


class Ais(Family):
    name = "ais"
    kinds = KINDS
    controller = "udwa"
    max_draws = 1
    parameters = {
        "encounters": Param("", "the encounters CSV (usvtool ais encounters)", file=True,
                            required=True),
        "tracks": Param("", "the tracks file the encounters were found in (usvtool ais read)",
                        file=True, required=True),
        "own": Param("a", "the encounter's vessel the USV replaces", choices=("a", "b")),
        "radius": Param(2000.0, "vessels within this of the own ship's track are targets, m",
                        POSITIVE),
        "pad": Param(60.0, "seconds added on each side of the encounter's window", NON_NEGATIVE),
        "min_speed": Param(1.0, "under-way: both vessels make this at first detection, kn",
                           NON_NEGATIVE),
        "vessel": vessel_option("udwa-usv"),
        "duration": Param(0.0, "sim.duration, s (0: twice the window)", NON_NEGATIVE),
        "map": Param("", "a navigation grid with a CRS (usvtool preprocess) the scene runs on",
                     file=True),
    }  # fmt: skip
    about = {"any": "scene n: the encounter of rank n (ranked by CPA)",
             "under-way": "scene n: the n-th closest encounter of two vessels under way"}

    def draw_scene(self, kind: str, scene: int, rng: np.random.Generator, opts: dict) -> Draw:
        path = opts["encounters"]
        row = pick_encounter(read_encounters(path), kind, scene, opts["min_speed"], path,
                             f"family ais, kind {kind}, scene")  # fmt: skip
        tracks = read_tracks(opts["tracks"])
        at = scene_encounter(tracks, row, opts["own"], opts["pad"], path)
        chart = opts["map"] or None
        made = traffic_scenario(tracks, at.own, at.window, radius=opts["radius"],
                                vessel=opts["vessel"], controller=self.controller,
                                duration=opts["duration"] or None, map_path=chart,
                                what=f"encounter {row['rank']} of {Path(path).name}")
        if at.other not in made.figures["target_mmsis"]:
            raise UsvError(f"family ais, kind {kind}, scene {scene}: the other vessel, MMSI "
                           f"{at.other}, never comes within the radius, {opts['radius']:g} m, "
                           f"of the own ship's track (the encounter's CPA: {row['cpa_m']:g} m)")
        route = made.scenario["route"]
        files = {"route": (route, TextFile(made.files[route]))}
        if chart is not None:  # a copy beside the scene, as every family's map
            files["map"] = ("map.tif", MapFile(read_grid(chart)))
        for i, target in enumerate(made.scenario["targets"]):
            files[f"targets.{i}.track"] = (target["track"], TextFile(made.files[target["track"]]))
        return Draw(made.scenario, files, (*made.comments, f"Other vessel: MMSI {at.other}."))

    def reject(self, kind: str, draw: Draw, opts: dict) -> str | None:
        return None  # the recorded scene is checked as it is made: nothing to draw again
