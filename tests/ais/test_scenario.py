"""usvtool ais scenario: a window of the New York Harbor sample as a scenario (own ship from a
vessel, targets replayed within the radius, the local UTM frame or lon/lat on a map), run by
usvtool simulate, with every controller in the slow test."""

import json

import numpy as np
import pytest
import yaml
from affine import Affine

from usvtool.ais.encounters import find_encounters, write_encounters
from usvtool.geodesy import lonlat_to_map
from usvtool.grid import Grid, write_grid
from usvtool.tracks import NS, format_time, read_tracks

from .aisdata import NY

#: A head-on pair of the sample: the ferries H203 (367782880) and OPPORTUNITY (367791540).
OWN, OTHER = 367791540, 367782880


@pytest.fixture(scope="module")
def ny_files(tmp_path_factory):
    """The sample's tracks and encounters, made once."""
    from click.testing import CliRunner

    from usvtool.cli import cli

    root = tmp_path_factory.mktemp("ny")
    tracks = root / "ny.parquet"
    result = CliRunner().invoke(cli, ["ais", "read", str(NY), "-o", str(tracks)])
    assert result.exit_code == 0, result.output
    found = find_encounters(read_tracks(tracks))
    write_encounters(root / "enc.csv", found)
    rank = next(r["rank"] for r in found.rows if {r["mmsi_a"], r["mmsi_b"]} == {OWN, OTHER})
    return tracks, root / "enc.csv", rank, found


def _short_window(ny_files) -> tuple[str, str]:
    """A minute before the pair's CPA to the CPA."""
    row = next(r for r in ny_files[3].rows if {r["mmsi_a"], r["mmsi_b"]} == {OWN, OTHER})
    cpa = np.datetime64(row["cpa_time"].rstrip("Z"), "ns").astype(np.int64)
    return tuple(format_time([cpa - 60 * NS, cpa])) + (row,)


def test_scenario_in_the_local_utm_frame(usv, ny_files, tmp_path):
    tracks_path, _, _, _ = ny_files
    start, end, row = _short_window(ny_files)
    out = tmp_path / "sc"
    result = usv("ais", "scenario", tracks_path, "--own", OWN, "--start", start, "--end", end,
                 "--radius", 1500, "-o", out, "--summary", tmp_path / "s.json")  # fmt: skip
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert (tmp_path / "s.json").read_text() == result.stdout
    text = (out / "scenario.yaml").read_text()
    scenario = yaml.safe_load(text)
    # the own ship at her position at the window's start, independently interpolated
    t = read_tracks(tracks_path)
    rows = t.mmsi == OWN
    t0 = np.datetime64(start.rstrip("Z"), "ns").astype(np.int64)
    lon = np.interp(t0, t.time[rows], t.lon[rows])
    lat = np.interp(t0, t.time[rows], t.lat[rows])
    e, n = lonlat_to_map("EPSG:32618", lon, lat)  # New York: UTM zone 18N
    origin = (round(e), round(n))
    assert f"x = E - {origin[0]}, y = N - {origin[1]} in EPSG:32618" in text.split("\n")[3]
    assert scenario["own"]["start"] == pytest.approx([e - origin[0], n - origin[1]], abs=0.01)
    assert scenario["own"]["vessel"] == "udwa-usv" and scenario["controller"] == {"name": "udwa"}
    assert scenario["sim"]["duration"] == 120.0  # twice the window
    names = [target["name"] for target in scenario["targets"]]
    assert f"ais-{OTHER}" in names and f"ais-{OWN}" not in names
    track = np.loadtxt(out / f"ais-{OTHER}.csv", delimiter=",", skiprows=1)
    assert track[0, 0] == 0.0 and track[-1, 0] == 60.0  # t from the window's start
    route = json.loads((out / "route.geojson").read_text())["features"][0]
    assert route["geometry"]["coordinates"][0] == pytest.approx(scenario["own"]["start"],
                                                                abs=0.01)  # fmt: skip
    assert summary["targets"] == len(names) and summary["window"] == [start, end]


def _water_map(tracks_path, folder):
    """A 40 km square all-water grid (100 m cells) in UTM 18N around the sample, and its grid."""
    from rasterio.crs import CRS

    t = read_tracks(tracks_path)
    e, n = lonlat_to_map("EPSG:32618", float(t.lon.mean()), float(t.lat.mean()))
    grid = Grid(np.zeros((400, 400), np.uint8), Affine(100, 0, e - 20000, 0, -100, n + 20000),
                CRS.from_epsg(32618))  # fmt: skip
    folder.mkdir()
    write_grid(folder / "water.tif", grid)
    return folder / "water.tif", grid


def test_scenario_from_an_encounter_on_a_map(usv, ny_files, tmp_path):
    """On a water grid with a CRS: points in lon/lat, tracks t,lon,lat, the map named relative
    to the scenario; a land cell under the own ship's start is refused."""
    tracks_path, enc, rank, found = ny_files
    water, grid = _water_map(tracks_path, tmp_path / "maps")
    out = tmp_path / "sc"
    result = usv("ais", "scenario", tracks_path, "--encounters", enc, "--encounter", rank,
                 "--own", OWN, "--pad", 0, "--map", water, "--duration", 20,
                 "-o", out)  # fmt: skip
    assert result.exit_code == 0, result.output
    scenario = yaml.safe_load((out / "scenario.yaml").read_text())
    assert scenario["map"] == "../maps/water.tif"
    assert set(scenario["own"]["start"]) == {"lon", "lat"}
    first = next(p for p in out.iterdir() if p.name.startswith("ais-"))
    assert first.read_text().startswith("t,lon,lat\n")
    row = next(r for r in found.rows if r["rank"] == rank)
    assert json.loads(result.stdout)["window"][0] >= row["start"]
    land = Grid(np.ones((400, 400), np.uint8), grid.transform, grid.crs)
    write_grid(tmp_path / "maps" / "land.tif", land)
    refused = usv("ais", "scenario", tracks_path, "--encounters", enc, "--encounter", rank,
                  "--own", OWN, "--map", tmp_path / "maps" / "land.tif", "-o", tmp_path / "x")
    assert refused.exit_code == 1 and "on an obstacle" in refused.stderr
    assert not (tmp_path / "x" / "scenario.yaml").exists()


def test_window_and_own_ship_refused_in_one_line(usv, ny_files, tmp_path):
    tracks_path, enc, _, _ = ny_files
    cases = [
        (["--own", OWN], "give --start and --end, or --encounter"),
        (["--own", 1, "--start", "2022-01-03T00:01:00Z", "--end", "2022-01-03T00:02:00Z"],
         "--own 1: no track of that MMSI"),
        (["--encounters", enc, "--encounter", 9999], "--encounter 9999: no such rank"),
        (["--encounters", enc, "--encounter", 1, "--own", 123], "--own 123: not a vessel"),
    ]  # fmt: skip
    for args, words in cases:
        result = usv("ais", "scenario", tracks_path, *args, "-o", tmp_path / "x")
        assert result.exit_code == 1 and words in result.stderr, result.stderr
    assert not (tmp_path / "x").exists()


@pytest.mark.slow
@pytest.mark.parametrize("controller, on_map", [("dwa", False), ("gdwa", False), ("ccdwa", False),
                                                ("udwa", False), ("udwa+", False),
                                                ("udwa", True), ("vo", False),
                                                ("vo", True)])  # fmt: skip
def test_every_controller_runs_the_sample_scenario(usv, ny_files, tmp_path, controller, on_map):
    """A minute of the sample around the ferries' head-on passing, in the local frame with every
    controller and on a map with one."""
    tracks_path = ny_files[0]
    start, end, _ = _short_window(ny_files)
    out = tmp_path / "sc"
    extra = ["--map", _water_map(tracks_path, tmp_path / "maps")[0]] if on_map else []
    made = usv("ais", "scenario", tracks_path, "--own", OWN, "--start", start, "--end", end,
               "--radius", 1000, *extra, "-o", out)  # fmt: skip
    assert made.exit_code == 0, made.output
    run = usv("simulate", out / "scenario.yaml", "--controller", controller,
              "-o", tmp_path / "trace.csv", "--events", tmp_path / "events.json")  # fmt: skip
    assert run.exit_code == 0, run.output
    summary = json.loads(run.stdout)
    assert summary["controller"] == controller
    assert len(summary["per_target"]) == json.loads(made.stdout)["targets"] > 0
    assert (tmp_path / "trace.csv").read_text().count("\n") > 100  # steps were written
