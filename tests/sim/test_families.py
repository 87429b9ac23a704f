"""Scene families (usvtool/sim/families, docs/families.md): each family keeps its promise on
many seeds, checked here independently of the families' own checks (generation only, no
simulation); a scene is the same bytes from (family, kind, scene, options) alone; the draws
are bounded and counted; the Imazu cases' geometry against the table, by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.ndimage import binary_dilation, label

from usvtool.encounter import CLASS_NAMES, classify, relative_bearing
from usvtool.errors import UsvError
from usvtool.grid import OBSTACLE, read_grid
from usvtool.sim.families import (
    FAMILIES,
    Draw,
    Family,
    make_scene,
    register,
    unregister,
    write_scene,
)
from usvtool.sim.families.imazu import CASES, COMPRESSED
from usvtool.sim.scenario import read_scenario
from usvtool.sim.vessel import PRESETS
from usvtool.sim.weather import beaufort
from usvtool.wind import read_wind_field

MANY = range(200)  # dynamic scenes: about 0.2 ms each
FEW = range(100)  # scenes with a raster to build and check (about 10 ms each)


def classes(s: dict) -> list[str]:
    own, ts = s["own"], s["targets"]
    codes = classify(own["start"], own["heading"], own["speed"], [t["start"] for t in ts],
                     [t["heading"] for t in ts], [t["speed"] for t in ts])  # fmt: skip
    return [CLASS_NAMES[c] for c in codes]


def velocity(heading: float, speed: float) -> np.ndarray:
    h = math.radians(heading)
    return speed * np.array([math.sin(h), math.cos(h)])


def cpa_distance(s: dict, i: int) -> float:
    own, t = s["own"], s["targets"][i]
    p = np.subtract(t["start"], own["start"])
    v = velocity(t["heading"], t["speed"]) - velocity(own["heading"], own["speed"])
    time = max(0.0, -p @ v / (v @ v))
    return float(np.linalg.norm(p + time * v))


def assert_clear(s: dict) -> None:
    """No target in the own ship's 7 L x 3 L ellipse; hulls half their mean length apart."""
    own, ts = s["own"], s.get("targets", [])
    length = own.get("length", PRESETS[own["vessel"]]["length"])  # the override, if any
    h = math.radians(own["heading"])
    for t in ts:
        dx, dy = np.subtract(t["start"], own["start"])
        along, across = dx * math.sin(h) + dy * math.cos(h), dx * math.cos(h) - dy * math.sin(h)
        assert (along / (3.5 * length)) ** 2 + (across / (1.5 * length)) ** 2 > 1, t
    for i, a in enumerate(ts):
        for b in ts[i + 1 :]:
            gap = math.dist(a["start"], b["start"]) - (a["length"] + b["length"]) / 2
            assert gap >= (a["length"] + b["length"]) / 4, (a, b)


def starboard_of(s: dict, a: int, b: int) -> bool:
    """Whether target ``b`` lies to the own ship's starboard of target ``a`` (bearings)."""
    own = s["own"]
    beta = relative_bearing(own["start"], own["heading"], [s["targets"][a]["start"],
                                                           s["targets"][b]["start"]])  # fmt: skip
    signed = (beta + 180.0) % 360.0 - 180.0
    return bool(signed[1] > signed[0])


# ----------------------------------------------------------------------------- promises


@pytest.mark.parametrize("kind", ["head-on", "crossing", "overtaking"])
def test_emergencies_keep_their_promise(kind):
    want = {"head-on": "head-on", "crossing": "crossing-give-way", "overtaking": "overtaking"}
    for n in MANY:
        s = make_scene("emergency", kind, n).draw.scenario
        assert classes(s)[0] == want[kind], n
        assert_clear(s)
        if kind == "crossing":
            assert cpa_distance(s, 0) < 1e-6  # built on a collision course
        else:
            assert starboard_of(s, 0, 1), n


def test_the_emergencies_are_the_scenes_of_the_generator_before_it_moved():
    # tests/sim/emergencies.py (removed) drew scene seed 0 as a head-on: its first two numbers
    # of default_rng(0) are the range and the course
    rng = np.random.default_rng(0)
    range_m, course = rng.uniform(180, 300), 180 + rng.uniform(-5, 5)
    target = make_scene("emergency", "head-on", 0).draw.scenario["targets"][0]
    assert (target["start"][1], target["heading"]) == (range_m, course)
    crossing = make_scene("emergency", "crossing", 2).draw.scenario  # old seed 3 * 2 + 1 = 7
    assert crossing["targets"][0]["speed"] == np.random.default_rng(7).uniform(size=3)[2] * 3 + 3


@pytest.mark.parametrize("kind, want", [("head-on", "head-on"),
                                        ("crossing-port", "crossing-stand-on"),
                                        ("crossing-starboard", "crossing-give-way"),
                                        ("overtaking", "overtaking")])  # fmt: skip
def test_iwso_encounters_keep_their_promise(kind, want):
    for n in MANY:
        s = make_scene("iwso", kind, n).draw.scenario
        assert classes(s) == [want], n
        assert_clear(s)
        if kind.startswith("crossing"):
            assert cpa_distance(s, 0) <= 10.0, n  # 4 lengths of the 2.5 m own ship
            side = s["targets"][0]["start"][0] - s["own"]["start"][0]
            assert (side < 0) == (kind == "crossing-port")


def test_iwso_static_scenes_put_islands_on_the_route_and_leave_a_passage(tmp_path):
    for n in FEW:
        scene = make_scene("iwso", "static", n)
        assert "targets" not in scene.draw.scenario
        grid = scene.draw.files["map"][1].grid
        own = scene.draw.scenario["own"]
        (x0, y0), (x1, y1) = own["start"], own["goal"]
        blocked = np.argwhere(grid.cells == OBSTACLE)
        assert len(blocked), n
        ys, xs = grid.to_map(blocked[:, 1] + 0.5, blocked[:, 0] + 0.5)[::-1]
        # every obstacle cell centre at least 25 m (10 lengths) from the start and the goal
        for x, y in ((x0, y0), (x1, y1)):
            assert np.hypot(xs - x, ys - y).min() >= 25.0 - 1.0, n  # cells, not points
        # the straight line (x = 250) crosses an island
        assert (np.abs(xs - x0) <= 0.5).any(), n
        # a passage one own length (2.5 m) from every island: free of the islands grown by a
        # disk of that radius
        r = np.arange(-3, 4)
        disk = r[:, None] ** 2 + r[None, :] ** 2 < 2.5**2
        regions = label(~binary_dilation(grid.cells == OBSTACLE, disk))[0]
        assert regions[grid.cell_of(x0, y0)] == regions[grid.cell_of(x1, y1)] != 0, n
    # as written: an ordinary navigation grid and a scenario that reads
    files = write_scene(scene, tmp_path / "s.yaml")
    assert [p.name for p in files] == ["s.yaml", "s.map.tif"]
    assert (read_grid(files[1]).cells == grid.cells).all()


def test_imazu_cases_are_tabulated_and_keep_their_promise():
    assert FAMILIES["imazu"].kinds == tuple(f"{i:02d}" for i in range(1, 23))
    for case in FAMILIES["imazu"].kinds:
        scene = make_scene("imazu", case)
        s = scene.draw.scenario
        n = int(case)
        assert len(s["targets"]) == (1 if n <= 4 else 2 if n <= 12 else 3)
        assert classes(s) == [c[2] for c in CASES[case]]
        assert_clear(s)
        # every ship reaches (0, 600) after 150 s: 4 m/s x 150 s, 120 lengths of 5 m
        for t in s["targets"]:
            end = np.add(t["start"], 150.0 * velocity(t["heading"], t["speed"]))
            assert end == pytest.approx([0.0, 600.0], abs=1e-5)
            assert t["length"] == 5.0
        assert s["own"]["goal"] == [0.0, 1200.0] and s["sim"]["duration"] == 450.0
        # the own ship 5 m long, its top speed its 4 m/s (udwa-usv's: 15 m, 7 m/s)
        assert s["own"]["length"] == 5.0 and s["own"]["max_speed"] == 4.0


def test_imazu_compressed_scale_is_the_earlier_scene():
    # udwa-usv at its own 7 m/s and 15 m, the CPA 60 s ahead: no vessel override is written,
    # every ship reaches (0, 420) after 60 s, the goal (0, 840), 180 s
    s = make_scene("imazu", "14", options=COMPRESSED).draw.scenario
    assert s["own"] == {"start": [0.0, 0.0], "goal": [0.0, 840.0], "heading": 0.0,
                        "speed": 7.0, "vessel": "udwa-usv"}  # fmt: skip
    assert s["sim"]["duration"] == 180.0
    for t in s["targets"]:
        end = np.add(t["start"], 60.0 * velocity(t["heading"], t["speed"]))
        assert end == pytest.approx([0.0, 420.0], abs=1e-5) and t["length"] == 15.0
    # case 14's first target, course 350: 2 v T sin(5 deg) = 840 x 0.0872 = 73.2 m off
    assert np.hypot(*s["targets"][0]["start"]) == pytest.approx(73.21, abs=0.01)
    # top_speed: the own ship may speed up to 1.75 x 4 = 7 m/s, the preset's (not written)
    s = make_scene("imazu", "01", options={"top_speed": 1.75}).draw.scenario
    assert "max_speed" not in s["own"] and s["own"]["length"] == 5.0


@pytest.mark.parametrize("case, target, bearing, course", [
    ("01", 0, 0.0, 180.0),  # dead ahead on the reciprocal course
    ("02", 0, 45.0, 270.0),  # from starboard at 90 deg: on a collision course it bears 45
    ("04", 0, 292.5, 45.0),  # 45 deg course from the port quarter: bears 45/2 - 90 = -67.5
    ("13", 1, 275.0, 10.0),  # 10 deg from port: nearly abeam, 5 deg forward of it
    ("18", 0, 22.5, 225.0),  # from the starboard bow: bears 225/2 - 90
    ("06", 0, 85.0, 350.0),
])  # fmt: skip
def test_imazu_bearings_by_hand(case, target, bearing, course):
    # Equal speeds meeting after T: the target starts at CPA - v T (sin c, cos c), the own ship
    # at CPA - v T (0, 1): the bearing is atan2(-sin c, 1 - cos c) = c / 2 - 90 (mod 360)
    s = make_scene("imazu", case).draw.scenario
    t = s["targets"][target]
    assert t["heading"] == course
    got = float(relative_bearing(s["own"]["start"], 0.0, t["start"]))
    assert min(abs(got - bearing), 360 - abs(got - bearing)) < 1e-6


def test_imazu_overtaken_ship_is_slower_and_ahead():
    s = make_scene("imazu", "03", options={"tcpa": 40, "own_speed": 5}).draw.scenario
    (t,) = s["targets"]
    assert t["speed"] == pytest.approx(3.5)  # 0.7 x 5
    assert t["start"] == pytest.approx([0.0, 60.0])  # (5 - 3.5) m/s x 40 s ahead
    assert classes(s) == ["overtaking"]


def test_wind_fields_are_strong_on_one_side_and_weak_on_the_other(tmp_path):
    sides = set()
    for n in FEW:
        scene = make_scene("wind", "halves", n)
        path = write_scene(scene, tmp_path / f"w{n}.yaml")[1]
        field = read_wind_field(path)
        speed = np.hypot(field.layers[0], field.layers[1])
        # about 140 m either side of the diagonal, at its middle: the cells (row, col) holding
        # (250, 450) and (450, 250) in a 70 x 70 raster of 10 m cells, row 0 at y = 700
        north_west, south_east = speed[25, 25], speed[45, 45]
        forces = {int(beaufort(north_west)), int(beaufort(south_east))}
        assert forces == {1, 4}, n
        sides.add(bool(south_east > north_west))
    assert sides == {True, False}  # the strong side is drawn
    assert read_scenario(tmp_path / f"w{n}.yaml").weather.field == path
    for n in MANY:
        w = make_scene("wind", "uniform", n).draw.scenario["weather"]
        assert 1 <= beaufort(w["wind_speed"]) <= 4 and 0 <= w["wind_from"] < 360


# ----------------------------------------------------------------------------- reproducible


@pytest.mark.parametrize("family, kind, scene", [
    ("emergency", "crossing", 3), ("iwso", "static", 5), ("imazu", "17", 0),
    ("wind", "halves", 2)])  # fmt: skip
def test_same_scene_same_bytes_another_scene_other_bytes(tmp_path, family, kind, scene):
    def written(where, n):
        files = write_scene(make_scene(family, kind, n), where / "scene.yaml")
        return [p.read_bytes() for p in files]

    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    assert written(tmp_path / "a", scene) == written(tmp_path / "b", scene)
    if FAMILIES[family].seeded:
        (tmp_path / "c").mkdir()
        assert written(tmp_path / "c", scene + 1)[0] != written(tmp_path / "a", scene)[0]


def test_the_scenario_file_reads_and_names_its_scene(tmp_path):
    scene = make_scene("iwso", "head-on", 4, {"own_speed": 3})
    path = write_scene(scene, tmp_path / "x.yaml")[0]
    text = path.read_text()
    assert text.startswith("# Scene 4 of kind head-on of the scene family iwso")
    assert "--family-option own_speed=3 -o FILE" in text
    s = read_scenario(path)
    assert s.name == "iwso-head-on-s004-own_speed=3" and s.own.speed == 3.0


# ----------------------------------------------------------------------------- bounded draws


class _Picky(Family):
    """Rejects its first ``refusals`` draws (all of them when None)."""

    name, kinds, refusals = "picky", ("any",), 2

    def draw(self, kind, rng, opts):
        self.count = getattr(self, "count", 0) + 1
        own = {"start": [0, 0], "goal": [0, 10], "vessel": "udwa-usv", "heading": 0, "speed": 1}
        return Draw({"name": "", "own": own})

    def reject(self, kind, draw, opts):
        return "too early" if self.refusals is None or self.count <= self.refusals else None


def test_a_scene_records_its_draws_and_rejections(tmp_path):
    scene = _Picky().scene("any", 5)
    assert (scene.draws, scene.rejected) == (3, {"too early": 2})
    text = write_scene(scene, tmp_path / "p.yaml")[0].read_text()
    assert "draw 3 (rejected: 2 too early)" in text


def test_a_family_that_cannot_keep_its_promise_fails_after_its_bound():
    picky = _Picky()
    picky.refusals, picky.max_draws = None, 7
    with pytest.raises(UsvError) as err:
        picky.scene("any", 0)
    assert picky.count == 7
    assert str(err.value) == ("family picky, kind any, scene 0: no draw of 7 keeps its promise "
                              "(7 too early)")  # fmt: skip


def test_real_families_fail_in_one_line_when_options_break_the_promise():
    with pytest.raises(UsvError, match=r"no draw of 100 keeps its promise \(100 forces"):
        make_scene("wind", "halves", 0, {"ramp": 300})  # 50 m off the line is on the ramp
    with pytest.raises(UsvError, match=r"no draw of 1 keeps its promise \(1 target"):
        make_scene("imazu", "01", 0, {"tcpa": 1})  # the target starts 8 m ahead


def test_options_kinds_and_scenes_are_checked():
    for call, message in [
        (lambda: make_scene("nope", "x"), "unknown scene family 'nope'"),
        (lambda: make_scene("emergency", "abeam"), "family emergency has no kind 'abeam'"),
        (lambda: make_scene("imazu", "01", 1), "imazu is not seeded"),
        (lambda: make_scene("iwso", "head-on", -1), "a scene is an integer >= 0"),
        (lambda: make_scene("iwso", "head-on", 0, {"speed": 3}),
         r"^option speed is not a parameter of family iwso \(known: own_speed, "),
        (lambda: make_scene("iwso", "head-on", 0, {"own_speed": 0}),
         "^option own_speed must be > 0 for family iwso, not 0$"),
        (lambda: make_scene("iwso", "head-on", 0, {"own_speed": "4"}),
         "^option own_speed must be a finite number, not '4'$"),
        (lambda: make_scene("iwso", "head-on", 0, {"vessel": "tug"}),
         "^option vessel must be one of iwso-dwa-usv, udwa-usv for family iwso, not 'tug'$"),
    ]:
        with pytest.raises(UsvError, match=message):
            call()


def test_register_refuses_a_taken_name_and_unregister_removes():
    class Extra(_Picky):
        name = "extra"

    register(Extra)
    try:
        with pytest.raises(ValueError, match="already registered"):
            register(Extra)
        assert make_scene("extra", "any").family == "extra"
    finally:
        unregister("extra")
    assert "extra" not in FAMILIES
