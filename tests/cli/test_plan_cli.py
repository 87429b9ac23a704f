"""``usvtool plan`` through click's CliRunner: outputs, georeferenced grids, bad input."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from affine import Affine
from click.testing import CliRunner

from usvtool.cli import cli
from usvtool.collision import is_collision_free
from usvtool.grid import Grid, read_grid, write_grid
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
    # 8 x 10 is a tiny budget: its route may collide (exit 3 without --allow-collision)
    result = run(local_grid, "--start", 3, 3, "--goal", 59, 39, "--algo", algo, "--pop", 8,
                 "--iters", 10, "--allow-collision", "-o", out)  # fmt: skip
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
    # 10 x 10 is a tiny budget: its route may collide (exit 3 without --allow-collision)
    result = run(local_grid, "--start", 1, 1, "--goal", 59, 39, "--encoding", "columns",
                 "--algo", "issa", "--pop", 10, "--iters", 10, "--allow-collision",
                 "-o", out)  # fmt: skip
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
    (["--start", 3, 3, "--goal", 59, 39, "--param", "bogus=1"], 1,
     "Error: --param bogus is not a parameter of iwso (known: f_min, f_max, tau,"),
    # a value of the wrong type, or outside the range the algorithm's equations need (was:
    # internal error: UFuncTypeError for a string)
    (["--start", 3, 3, "--goal", 59, 39, "--algo", "pso", "--param", "c1=abc"], 1,
     "Error: --param c1 must be a finite number, not 'abc'\n"),
    (["--start", 3, 3, "--goal", 59, 39, "--algo", "pso+s", "--param", "c1=true"], 1,
     "Error: --param c1 must be a finite number, not True\n"),
    (["--start", 3, 3, "--goal", 59, 39, "--algo", "gwo", "--param", "a_start=NaN"], 1,
     "Error: --param a_start must be a finite number, not nan\n"),
    (["--start", 3, 3, "--goal", 59, 39, "--algo", "boa", "--param", "p=1.5"], 1,
     "Error: --param p must be in [0, 1] for boa, not 1.5\n"),
    (["--start", 3, 3, "--goal", 59, 39, "--algo", "iwso+g", "--param", "chi=1"], 1,
     "Error: --param chi must be > 1 for iwso, not 1\n"),
    (["--start", 3, 3, "--goal", 59, 39, "--algo", "ssa", "--param", "zeta=0"], 1,
     "Error: --param zeta must be > 0 for ssa, not 0\n"),
    # start equal to goal, or within one cell (2 m) of it: the same point; the same cell
    # [2, 4] x [2, 4] with the points hypot(1.9, 1.9) = 2.69 m apart; neighbouring cells 0.6 m
    # apart
    (["--start", 3, 3, "--goal", 3, 3], 1, ": start and goal are within one cell of each "
     "other (0.00 m apart, cells of 2 m)"),
    (["--start", 2.05, 2.05, "--goal", 3.95, 3.95], 1, "within one cell of each other (2.69 m"),
    (["--start", 3.9, 3, "--goal", 4.5, 3], 1, "within one cell of each other (0.60 m apart"),
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


def test_ends_one_cell_apart_are_accepted(local_grid, tmp_path):
    """(3, 3) and (5, 3) lie in neighbouring 2 m cells exactly one cell side apart."""
    result = run(local_grid, "--start", 3, 3, "--goal", 5, 3, "--algo", "anyangle",
                 "-o", tmp_path / "p.geojson")  # fmt: skip
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["length_m"] == pytest.approx(2.0)


def test_an_outside_point_keeps_its_metres(utm_grid, tmp_path):
    """Half a metre west of a grid whose west edge is x = 330000: the message must not round the
    point onto the edge (nor to tenths of a kilometre)."""
    result = run(utm_grid, "--start", 329999.5, 4689500.5, "--goal", 330950, 4689950,
                 "-o", tmp_path / "p.geojson")  # fmt: skip
    assert result.exit_code == 1
    assert result.stderr.count("\n") == 1
    assert ("start (329999.5, 4689500.5) is outside the grid (x 330000..331000, "
            "y 4689000..4690000)") in result.stderr  # fmt: skip
    assert "lonlat" not in result.stderr
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("name", ["start", "goal"])
def test_lonlat_given_as_map_metres_gets_the_hint(utm_grid, tmp_path, name):
    """Lon/lat near Boston given to --start or --goal of a UTM grid: the message gives the
    values to 1e-6 degree and names the option to use instead."""
    ends = {"start": ["330050", "4689050"], "goal": ["330950", "4689950"]}
    ends[name] = ["-71.0051234", "42.3456789"]
    args = [w for end, xy in ends.items() for w in (f"--{end}", *xy)]
    result = run(utm_grid, *args, "-o", tmp_path / "p.geojson")
    assert result.exit_code == 1
    assert result.stderr.count("\n") == 1 and str(utm_grid) in result.stderr
    assert (f"--{name} -71.005123 42.345679 lies far outside the grid (x 330000..331000, "
            "y 4689000..4690000 map metres)") in result.stderr  # fmt: skip
    assert result.stderr.rstrip().endswith(f"use --{name}-lonlat -71.005123 42.345679")
    assert list(tmp_path.iterdir()) == []


def test_no_lonlat_hint_without_a_crs(local_grid, tmp_path):
    """A grid in local metres takes no lon/lat: a point outside it is just outside."""
    result = run(local_grid, "--start", -71.0051234, 42.3456789, "--goal", 59, 39,
                 "-o", tmp_path / "p.geojson")  # fmt: skip
    assert result.exit_code == 1 and "is outside the grid" in result.stderr
    assert "lonlat" not in result.stderr


@pytest.fixture(scope="module")
def wall(tmp_path_factory):
    """10 x 10 cells of 1 m, a wall down column 5 with a one-cell gap at the top row: a route
    from the bottom left to the bottom right must climb to the gap."""
    cells = np.zeros((10, 10), np.uint8)
    cells[1:10, 5] = 1
    path = tmp_path_factory.mktemp("grids") / "wall.tif"
    write_grid(path, Grid(cells, Affine(1, 0, 0, 0, -1, 10)))
    return path


# one waypoint, two agents and one iteration of PSO cannot find the gap
WEAK = ["--start", 1.5, 1.5, "--goal", 8.5, 1.5, "--algo", "pso", "--pop", 2, "--iters", 1,
        "--waypoints", 1, "--seed", 0, "--no-timing"]  # fmt: skip


def test_a_colliding_best_route_is_written_flagged_and_exits_3(wall, tmp_path, reference):
    out, summary_path = tmp_path / "r.geojson", tmp_path / "r.json"
    result = run(wall, *WEAK, "-o", out, "--summary", summary_path)
    assert result.exit_code == 3, result.output
    # the route is written, and so are the summary file and stdout, before the exit
    points, props = read_path_geojson(out)
    summary = json.loads(result.stdout)
    assert json.loads(summary_path.read_text()) == summary
    assert props["collision_free"] is False and summary["collision_free"] is False
    # the independent check (shapely, closed cell squares) agrees: the route touches the wall
    grid = read_grid(wall)
    col, row = grid.to_cell_coords(*points.T)
    assert not reference(grid.blocked).route_free(np.column_stack([col, row]))
    assert not is_collision_free(grid, points)
    # one line on stderr: what happened, what to try, how to accept it; no traceback
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.output
    line = result.stderr
    assert line.startswith(f"Error: {wall}: the best route pso found in 1 run(s) touches")
    assert f"written to {out} with collision_free false" in line
    assert "--attempts" in line and "--allow-collision" in line


def test_allow_collision_exits_0_with_the_same_files(wall, tmp_path):
    files = {}
    for name, extra in (("strict", []), ("allowed", ["--allow-collision"])):
        out, summary_path = tmp_path / f"{name}.geojson", tmp_path / f"{name}.json"
        result = run(wall, *WEAK, *extra, "-o", out, "--summary", summary_path)
        files[name] = out.read_bytes(), json.loads(summary_path.read_text())
        if extra:
            assert result.exit_code == 0, result.output
            # still said, as a warning
            assert result.stderr.count("\n") == 1 and "usvtool: " in result.stderr
            assert "touches obstacle or margin cells" in result.stderr
    assert files["strict"][0] == files["allowed"][0]
    for summary in (s for _, s in files.values()):
        summary.pop("output")
    assert files["strict"][1] == files["allowed"][1]


def test_help_documents_the_exit_status():
    text = CliRunner().invoke(cli, ["plan", "--help"]).output
    assert "Exit status:" in text and "--allow-collision" in text
    lines = [line.strip() for line in text.splitlines()]
    assert any(line.startswith("3  the best route found collides") for line in lines)
