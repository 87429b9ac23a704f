"""usvtool.batch.commands: the one builder of the jobs' command lines (preprocess, plan,
simulate, functions) from the pipeline's plain data, and the files a grid reads."""

from __future__ import annotations

from pathlib import Path

import pytest

from usvtool.batch.commands import (
    chart_files,
    ends_args,
    functions_command,
    option_args,
    plan_command,
    preprocess_command,
    route_args,
    simulate_command,
)
from usvtool.batch.jobs import expand
from usvtool.cli.batch import stage_names
from usvtool.pipeline import BUNDLED, Chart, Ends, RouteJob, load

NAMES = stage_names()


@pytest.fixture(scope="module")
def bundled():
    return load(BUNDLED, NAMES)


def test_options_become_words_and_files_as_asked():
    options = (("cell-size", 1), ("no-swell", True), ("occupancy", 0.5), ("cutline", Path("/c/x")))
    assert option_args(options) == ["--cell-size", "1", "--no-swell", "--occupancy", "0.5",
                                    "--cutline", "/c/x"]  # fmt: skip
    assert option_args(options, lambda p: p.name.upper())[-2:] == ["--cutline", "X"]
    # a float as its shortest repr, an integer as itself
    assert option_args((("cell-size", 12.1), ("iters", 300))) == ["--cell-size", "12.1",
                                                                  "--iters", "300"]  # fmt: skip


def test_a_routes_ends_in_map_metres_or_degrees():
    assert ends_args(Ends((10, 10), (490, 490))) == ["--start", "10", "10", "--goal", "490", "490"]
    assert ends_args(Ends((-70.93391, 42.32119), (-70.79426, 42.31806), "lonlat")) == [
        "--start-lonlat",
        "-70.93391",
        "42.32119",
        "--goal-lonlat",
        "-70.79426",
        "42.31806",
    ]


def test_a_routes_plan_arguments_and_an_exact_planners_without_seed(bundled):
    job = next(j for j in bundled.route_jobs(NAMES)
               if j.chart == "us5ma12m" and j.algorithm == "iwso")  # fmt: skip
    assert route_args(job) == ["--start-lonlat", "-70.93391", "42.32119", "--goal-lonlat",
                               "-70.79426", "42.31806", "--algo", "iwso", "--seed", "1",
                               "--attempts", "5"]  # fmt: skip
    exact = next(j for j in bundled.route_jobs(NAMES) if j.algorithm == "astar")
    assert "--seed" not in route_args(exact) and "--attempts" not in route_args(exact)
    assert plan_command("k" * 16, exact) == ("plan", f"../../grids/{'k' * 16}/grid.tif",
                                             *route_args(exact), "--allow-collision", "-o",
                                             "route.geojson")  # fmt: skip


def test_the_commands_of_each_kind():
    chart = Chart("m", "maps/m.geojson", options=(("cell-size", 2), ("cutline", Path("/c/cut"))))
    assert preprocess_command(Path("/p"), chart) == (
        "preprocess", "/p/maps/m.geojson", "--cell-size", "2", "--cutline", "/c/cut", "-o",
        "grid.tif", "--preview", "preview.png")  # fmt: skip
    route = RouteJob("a", "m", "pso", Ends((1, 2), (3, 4.5)), 7, 2, (("pop", 20),))
    assert route_args(route) == ["--start", "1", "2", "--goal", "3", "4.5", "--algo", "pso",
                                 "--seed", "7", "--attempts", "2", "--pop", "20"]  # fmt: skip
    assert simulate_command(Path("/s/x.yaml"), "dwa", 3) == (
        "simulate", "/s/x.yaml", "--controller", "dwa", "--seed", "3", "-o", "trace.csv",
        "--events", "trace.events.json")  # fmt: skip
    assert functions_command("F1", "gwo", 2, {"pop": 10, "iters": 5, "dim": 4}) == (
        "functions", "--function", "F1", "--algo", "gwo", "--runs", "1", "--seed", "2",
        "--pop", "10", "--iters", "5", "--dim", "4")  # fmt: skip


def test_the_batch_jobs_are_these_command_lines(bundled):
    jobs = expand(bundled, NAMES)
    grids = {j.case: j for j in jobs if j.kind == "grids"}
    assert grids["grid20"].args == ("preprocess", str(bundled.root / "charts/grid20.geojson"),
                                    "--cell-size", "1", "--no-swell", "--occupancy", "0.5",
                                    "-o", "grid.tif", "--preview", "preview.png")  # fmt: skip
    routes = [j for j in jobs if j.kind == "routes"]
    cells = {(r.chart, r.algorithm, r.seed): r for r in bundled.route_jobs(NAMES)}
    assert len(routes) == len(cells) == 8 * 13
    for j in routes:
        assert j.args == plan_command(j.needs, cells[j.case, j.method, j.seed])
    runs = [j for j in jobs if j.kind == "runs"]
    assert len(runs) == len(bundled.simulation_jobs()) and runs[0].args[:2] == (
        "simulate",
        str(bundled.root / bundled.simulation.scenarios[0]),
    )


def test_a_charts_files_are_its_source_inputs_and_option_files_with_companions(tmp_path):
    for name in ("c.tif", "c.tif.aux.xml", "c.TFW", "x/a.dat", "x/b.dat", "x/skip.txt",
                 "cut.geojson", "cut.geojson.aux.xml", "d.tif.aux.xml", "S/CELL.000",
                 "S/CELL.001", "S/CELL.002", "S/OTHER.001"):  # fmt: skip
        (tmp_path / name).parent.mkdir(exist_ok=True)
        (tmp_path / name).write_bytes(b"x")
    chart = Chart("c", "c.tif", ("x/*.dat", "S/CELL.000"),
                  (("cell-size", 1), ("cutline", tmp_path / "cut.geojson")))  # fmt: skip
    names = [p.relative_to(tmp_path).as_posix() for p in chart_files(tmp_path, chart)]
    # the source first; the S-57 cell an input with its updates; each file once
    assert names == ["c.tif", "c.TFW", "c.tif.aux.xml", "S/CELL.000", "S/CELL.001",
                     "S/CELL.002", "x/a.dat", "x/b.dat", "cut.geojson",
                     "cut.geojson.aux.xml"]  # fmt: skip
