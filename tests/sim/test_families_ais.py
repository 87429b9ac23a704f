"""The ``ais`` scene family (usvtool/sim/families/ais.py) on the committed New York Harbor
encounters: a scene is the encounter of its number (by rank, or among those under way), the same
scenario ``usvtool ais scenario --encounter`` writes, its files beside it under the scene's
stem; the own vessel a or b; options in the name, files not; bad scenes and options refused in
one line."""

from pathlib import Path

import pytest
import yaml

from usvtool.errors import UsvError
from usvtool.sim.families import make_scene, write_scene
from usvtool.sim.scenario import read_scenario
from usvtool.tracks import read_tracks

AIS = Path(__file__).resolve().parents[2] / "charts" / "ais"
FILES = {"encounters": str(AIS / "nyharbor-encounters.csv"),
         "tracks": str(AIS / "nyharbor-tracks.parquet")}  # fmt: skip
#: Rank 3, the closest encounter of two vessels under way: H203 overtaking CYCLONE SHARK.
H203, SHARK = 367782880, 368139870


def test_a_scene_is_the_scenario_ais_scenario_writes_of_its_encounter():
    from usvtool.ais import ScenarioOptions, make_scenario

    scene = make_scene("ais", "under-way", 1, FILES)
    s = scene.draw.scenario
    assert scene.name == "ais-367782880-20220103T000820"  # H203; 00:09:20 less the 60 s pad
    assert scene.draws == 1 and s["controller"] == {"name": "udwa"}
    cli = make_scenario(read_tracks(FILES["tracks"]),
                        ScenarioOptions(encounter=3, encounters=FILES["encounters"]))
    theirs = yaml.safe_load(cli.files["scenario.yaml"])
    assert theirs["name"] == s["name"] and theirs["own"] == s["own"]
    assert theirs["sim"] == s["sim"] and theirs["targets"] == s["targets"]
    assert f"ais-{SHARK}" in [t["name"] for t in s["targets"]]
    for where, (name, text) in scene.draw.files.items():
        assert text.text == cli.files[name], where
    assert make_scene("ais", "any", 3, FILES).draw.scenario == s  # the same encounter


def test_the_scene_file_names_its_files_beside_it(tmp_path):
    scene = make_scene("ais", "any", 6, FILES)  # the ferries head-on; the USV takes H203's place
    written = write_scene(scene, tmp_path / "scene.yaml")
    names = sorted(p.name for p in written)
    assert "scene.route.geojson" in names and "scene.ais-367791540.csv" in names
    assert sorted(p.name for p in tmp_path.iterdir()) == names
    text = (tmp_path / "scene.yaml").read_text()
    assert "# Other vessel: MMSI 367791540." in text and "# Frame: local metres: x = E - " in text
    read = read_scenario(tmp_path / "scene.yaml")
    assert read.route == tmp_path / "scene.route.geojson"
    assert {t.track.name for t in read.targets} == {n for n in names if n.endswith(".csv")}
    assert len(read.targets) == len(scene.draw.scenario["targets"]) > 1


def test_the_own_vessel_b_and_the_options_in_the_name():
    b = make_scene("ais", "any", 3, {**FILES, "own": "b", "radius": 1500})
    assert b.name.startswith(f"ais-{SHARK}-") and b.name.endswith("-radius=1500")
    assert "nyharbor" not in b.name  # the files are not in the name (the encounter is)
    assert f"ais-{H203}" in [t["name"] for t in b.draw.scenario["targets"]]
    short = make_scene("ais", "any", 3, {**FILES, "duration": 30, "pad": 0})
    assert short.draw.scenario["sim"]["duration"] == 30
    wide = make_scene("ais", "any", 3, FILES)
    assert wide.draw.scenario["sim"]["duration"] == 2 * (270 + 120)  # the window and the pads


@pytest.mark.parametrize("kind, scene, options, words", [
    ("any", 0, {}, "family ais, kind any, scene 0: no such rank in"),
    ("under-way", 31, {}, "scene 31: " + FILES["encounters"] + " holds 30 encounters"),
    ("any", 3, {"radius": 10}, "MMSI 368139870, never comes within the radius, 10 m"),
    ("any", 3, {"own": "c"}, "option own must be one of a, b for family ais, not 'c'"),
    ("any", 3, {"tracks": "no/such.parquet"},
     "option tracks must be an existing file's path, not 'no/such.parquet'"),
    ("any", 3, {"encounters": None},
     "option encounters must be given for family ais: the encounters CSV"),
    ("any", 3, {"tracks": 3}, "option tracks must be a file's path, not 3"),
])  # fmt: skip
def test_bad_scenes_and_options_are_refused_in_one_line(kind, scene, options, words):
    given = {k: v for k, v in {**FILES, **options}.items() if v is not None}
    with pytest.raises(UsvError) as e:
        make_scene("ais", kind, scene, given)
    assert words in str(e.value) and "\n" not in str(e.value)


def _grid(tmp_path, value: int):
    """A 40 km square grid of one class (100 m cells) in UTM 18N around the sample."""
    import numpy as np
    from affine import Affine
    from rasterio.crs import CRS

    from usvtool.geodesy import lonlat_to_map
    from usvtool.grid import Grid, write_grid

    t = read_tracks(FILES["tracks"])
    e, n = lonlat_to_map("EPSG:32618", float(t.lon.mean()), float(t.lat.mean()))
    grid = Grid(np.full((400, 400), value, np.uint8),
                Affine(100, 0, e - 20000, 0, -100, n + 20000), CRS.from_epsg(32618))  # fmt: skip
    path = tmp_path / f"grid{value}.tif"
    write_grid(path, grid)
    return path, grid


def test_with_a_map_the_scene_runs_on_a_copy_of_it_in_lon_lat(tmp_path):
    """The map option: points in lon/lat, the grid written beside the scene as <stem>.map.tif
    (the same cells, transform and CRS), read back by the scenario reader; a file option, so
    not in the name; a map whose cells under the own ship are land is refused in one line."""
    import numpy as np

    from usvtool.grid import read_grid

    water, grid = _grid(tmp_path, 0)
    plain = make_scene("ais", "under-way", 1, FILES)
    scene = make_scene("ais", "under-way", 1, {**FILES, "map": str(water)})
    assert scene.name == plain.name  # a file option: not in the name
    assert set(scene.draw.scenario["own"]["start"]) == {"lon", "lat"}
    (tmp_path / "out").mkdir()
    written = write_scene(scene, tmp_path / "out" / "s.yaml")
    assert written[0].name == "s.yaml" and tmp_path / "out" / "s.map.tif" in written
    copy = read_grid(tmp_path / "out" / "s.map.tif")
    assert np.array_equal(copy.cells, grid.cells) and copy.transform == grid.transform
    assert copy.crs == grid.crs
    assert yaml.safe_load((tmp_path / "out" / "s.yaml").read_text())["map"] == "s.map.tif"
    read_scenario(tmp_path / "out" / "s.yaml")  # reads, its points on the map's frame
    land, _ = _grid(tmp_path, 1)
    with pytest.raises(UsvError, match="on an obstacle"):
        make_scene("ais", "under-way", 1, {**FILES, "map": str(land)})
    with pytest.raises(UsvError, match=r"^option map must be an existing file's path, not "):
        make_scene("ais", "under-way", 1, {**FILES, "map": str(tmp_path / "none.tif")})


def test_a_line_break_in_an_option_stays_in_its_comment(tmp_path):
    """A file option's path holding a line break and a YAML key used to end the scene file's
    header comment: the scene then ran in that weather."""
    hostile = tmp_path / "x\nweather: {wind_speed: 30}\n.csv"
    hostile.write_bytes(Path(FILES["encounters"]).read_bytes())
    scene = make_scene("ais", "any", 6, {**FILES, "encounters": str(hostile)})
    write_scene(scene, tmp_path / "scene.yaml")
    text = (tmp_path / "scene.yaml").read_text()
    assert "weather" not in yaml.safe_load(text)
    assert "x\\nweather: {wind_speed: 30}\\n.csv" in text  # escaped, on its comment's line
