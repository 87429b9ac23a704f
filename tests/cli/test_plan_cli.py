"""``usvtool plan`` through click's CliRunner: outputs, georeferenced grids, bad input."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from affine import Affine
from click.testing import CliRunner

from usvtool.cli import cli
from usvtool.grid import Grid, write_grid
from usvtool.route import read_path_geojson

FIGURES = {
    "algorithm", "parameters", "seed", "length_m", "turns", "mot", "fitness",
    "planning_time_s", "collision_free", "convergence", "attempt",
}  # fmt: skip


def run(*args):
    return CliRunner().invoke(cli, ["plan", *map(str, args)])


@pytest.fixture(scope="module")
def local_grid(tmp_path_factory):
    """30 x 20 cells of 2 m, no CRS: an island with a margin, and a closed-off pond."""
    cells = np.zeros((20, 30), np.uint8)
    cells[6:14, 10:18] = 2
    cells[7:13, 11:17] = 1
    cells[1:6, 22:29] = 1
    cells[2:5, 23:28] = 0  # a pond (rows 2-4) enclosed by land
    path = tmp_path_factory.mktemp("grids") / "local.tif"
    write_grid(path, Grid(cells, Affine(2, 0, 0, 0, -2, 40)))
    return path


@pytest.fixture(scope="module")
def utm_grid(tmp_path_factory):
    """100 x 100 cells of 10 m in UTM zone 19N near Boston, a block of land in the middle."""
    from rasterio.crs import CRS

    cells = np.zeros((100, 100), np.uint8)
    cells[30:70, 40:60] = 1
    path = tmp_path_factory.mktemp("grids") / "utm.tif"
    grid = Grid(cells, Affine(10, 0, 330000, 0, -10, 4690000), CRS.from_epsg(32619))
    write_grid(path, grid)
    return path


def test_plan_writes_the_route_and_prints_the_same_figures(local_grid, tmp_path):
    out = tmp_path / "path.geojson"
    result = run(local_grid, "--start", 3, 3, "--goal", 59, 39, "--algo", "iwso", "--pop", 10,
                 "--iters", 15, "--seed", 4, "--waypoints", 3, "-o", out)  # fmt: skip
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    points, props = read_path_geojson(out)
    assert FIGURES <= set(props) and FIGURES <= set(summary)
    for key in FIGURES:
        assert summary[key] == props[key]
    assert props["algorithm"] == "iwso" and props["seed"] == 4
    assert props["parameters"]["pop"] == 10 and props["parameters"]["waypoints"] == 3
    assert len(props["convergence"]) == 15
    assert "frame" in props and "crs" not in props
    assert points[0].tolist() == [3, 3] and points[-1].tolist() == [59, 39]
    assert len(points) == 5 == summary["points"]
    data = json.loads(out.read_text())
    assert data["features"][0]["geometry"]["type"] == "LineString"
    assert props["length_m"] == pytest.approx(np.hypot(*np.diff(points, axis=0).T).sum())


def test_same_seed_same_file(local_grid, tmp_path):
    texts = []
    for name in ("a", "b"):
        out = tmp_path / f"{name}.geojson"
        result = run(local_grid, "--start", 3, 3, "--goal", 59, 39, "--algo", "pso", "--pop", 8,
                     "--iters", 10, "--seed", 9, "-o", out)  # fmt: skip
        assert result.exit_code == 0, result.output
        props = json.loads(out.read_text())["features"][0]["properties"]
        props.pop("planning_time_s")
        texts.append(json.dumps(props))
    assert texts[0] == texts[1]


def test_no_timing_gives_byte_identical_files(local_grid, tmp_path):
    outs = [tmp_path / "a.geojson", tmp_path / "b.geojson"]
    for out in outs:
        result = run(local_grid, "--start", 3, 3, "--goal", 59, 39, "--algo", "iwso", "--pop", 8,
                     "--iters", 10, "--seed", 9, "--no-timing", "-o", out)  # fmt: skip
        assert result.exit_code == 0, result.output
        assert json.loads(result.stdout)["planning_time_s"] is None
    assert outs[0].read_bytes() == outs[1].read_bytes()


@pytest.mark.parametrize("algo", ["astar", "anyangle", "astar+s", "gwo+s"])
def test_every_kind_of_algorithm(local_grid, tmp_path, algo):
    out = tmp_path / "path.geojson"
    result = run(local_grid, "--start", 3, 3, "--goal", 59, 39, "--algo", algo, "--pop", 8,
                 "--iters", 10, "-o", out)  # fmt: skip
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["algorithm"] == algo
    if algo in ("anyangle", "astar", "astar+s"):
        assert summary["collision_free"] and summary["convergence"] == []
        assert summary["seed"] is None
    if algo.endswith("+s"):
        assert summary["parameters"]["shorten"] is True


def test_columns_encoding(local_grid, tmp_path):
    out = tmp_path / "path.geojson"
    result = run(local_grid, "--start", 1, 1, "--goal", 59, 39, "--encoding", "columns",
                 "--algo", "issa", "--pop", 10, "--iters", 10, "-o", out)  # fmt: skip
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["parameters"]["encoding"] == "columns"
    assert summary["points"] == 30 + 2  # start, one cell per column, goal


def test_georeferenced_grid_takes_lonlat_and_writes_lonlat(utm_grid, tmp_path):
    from pyproj import Transformer

    to_lonlat = Transformer.from_crs(32619, 4326, always_xy=True)
    start = to_lonlat.transform(330050, 4689050)
    goal = to_lonlat.transform(330950, 4689950)
    out = tmp_path / "path.geojson"
    result = run(utm_grid, "--start-lonlat", *start, "--goal-lonlat", *goal, "--algo",
                 "anyangle", "-o", out)  # fmt: skip
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    data = json.loads(out.read_text())
    feature = data["features"][0]
    lonlat = np.array(feature["geometry"]["coordinates"])
    props = feature["properties"]
    assert "32619" in props["crs"]
    assert lonlat[0] == pytest.approx(start) and lonlat[-1] == pytest.approx(goal)
    mapped = np.array(props["map_coordinates"])
    assert mapped[0] == pytest.approx([330050, 4689050]) and len(mapped) == len(lonlat)
    planar = np.hypot(*np.diff(mapped, axis=0).T).sum()
    assert summary["length_m"] == pytest.approx(planar, rel=2e-3)  # geodesic vs UTM metres
    assert summary["length_m"] != planar
    assert summary["collision_free"]
    assert planar > math.hypot(900, 900)  # the land block is in the way


BAD = [  # arguments, exit status, words of the message (exit 1: the grid's name leads it)
    (["--start", -5, 3, "--goal", 59, 39], 1, ": start (-5, 3) is outside the grid"),
    (["--start", 25, 20, "--goal", 59, 39], 1, ": start (25, 20) is on an obstacle"),
    (["--start", 3, 3, "--goal", 21, 13], 1, ": goal (21, 13) is in the safety margin"),
    (["--start", 3, 3, "--goal", 50, 34], 1, ": no navigable connection"),
    (["--start", 3, 3, "--goal", 59, 39, "--algo", "dijkstra"], 2, "'dijkstra' is not one of"),
    (["--start", 3, 3, "--goal", 59, 39, "--pop", 1], 2, "--pop"),
    (["--start", 3, 3, "--goal", 59, 39, "--iters", 0], 2, "--iters"),
    (["--start", 3, 3, "--goal", 59, 39, "--attempts", 0], 2, "--attempts"),
    (["--start", 3, 3], 2, "--goal"),
    (["--start", 3, 3, "--start-lonlat", 1, 2, "--goal", 59, 39], 2, "exactly one of --start"),
    (["--start-lonlat", -71, 42, "--goal", 59, 39], 1, "--start-lonlat: "),
    (["--start", 3, 3, "--goal", 59, 39, "--param", "nope"], 2, "NAME=VALUE"),
    (["--start", 3, 3, "--goal", 59, 39, "--param", "bogus=1"], 1, "iwso: unknown parameter"),
]


@pytest.mark.parametrize("args, code, words", BAD)
def test_bad_requests_fail_in_one_line_and_write_nothing(local_grid, tmp_path, args, code, words):
    out = tmp_path / "path.geojson"
    result = run(local_grid, *args, "-o", out)
    assert result.exit_code == code, result.output
    assert words in result.stderr
    if code == 1:
        assert result.stderr.count("\n") == 1
        assert str(local_grid) in result.stderr or not words.startswith(":")
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_missing_output_directory_and_missing_grid(local_grid, tmp_path):
    result = run(local_grid, "--start", 3, 3, "--goal", 59, 39, "-o", tmp_path / "no" / "p.json")
    assert result.exit_code == 1 and "does not exist" in result.stderr
    result = run(tmp_path / "none.tif", "--start", 3, 3, "--goal", 5, 5, "-o", tmp_path / "p.json")
    assert result.exit_code == 1 and "no such file" in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_colliding_best_route_is_written_flagged_and_warned(tmp_path):
    """One iteration of a tiny population cannot get round a wall: the route is still written,
    flagged, and a warning goes to stderr."""
    cells = np.zeros((10, 10), np.uint8)
    cells[1:10, 5] = 1  # a wall with a gap at the top row only
    grid = tmp_path / "wall.tif"
    write_grid(grid, Grid(cells, Affine(1, 0, 0, 0, -1, 10)))
    out = tmp_path / "r.geojson"
    result = run(grid, "--start", 1.5, 1.5, "--goal", 8.5, 1.5, "--algo", "pso", "--pop", 2,
                 "--iters", 1, "--waypoints", 1, "--seed", 0, "-o", out)  # fmt: skip
    assert result.exit_code == 0
    assert json.loads(result.stdout)["collision_free"] is False
    assert "touches obstacle" in result.stderr and out.exists()
    assert "in 1 run(s)" in result.stderr and "--attempts" in result.stderr
