"""Extension in one place (docs/extending.md): an optimizer, an exact planner and a controller
added through their registries' ``register`` functions alone, in this process, then seen to plan
and run through the API and the command line, to be known to the pipelines and the report, and
to appear in the report's tables built from a tiny results table holding them."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import yaml
from affine import Affine
from click.testing import CliRunner

from usvtool.cli import cli
from usvtool.errors import UsvError
from usvtool.grid import Grid, write_grid
from usvtool.params import Param, Range
from usvtool.plan import exact, optimizers
from usvtool.plan.optimizers.base import Optimizer
from usvtool.plan.planner import PlanOptions, plan_route
from usvtool.plan.planners import EXACT, ExactPlanner, Planned
from usvtool.results import Row, write_results
from usvtool.sim import controllers
from usvtool.sim.controllers.base import Controller, Decision

START, GOAL = (2.0, 20.0), (38.0, 20.0)


class RandomSearch(Optimizer):
    """Random search: every iteration draws a share of the population uniformly in the box."""

    name = "random"
    parameters = {"share": Param(1.0, "the share of the population drawn each iteration",
                                 Range(0.0, 1.0, open_low=True))}

    def _run(self) -> None:
        self.evaluate(self.uniform())
        drawn = max(1, round(self.params["share"] * self.pop))
        for t in range(self.iters):
            self.evaluate(self.uniform(drawn))
            self.record(t)


class EightConnected(ExactPlanner):
    """A* on the 8-connected grid, as usvtool's astar; a plugin's own search goes here."""

    name = "my-astar"

    def plan(self, request) -> Planned:
        cells = exact.astar(request.problem.grid.blocked, request.start, request.goal)
        if cells is None:
            raise UsvError(f"{self.name}: no route found between start and goal")
        return Planned(cells, {})


class StraightToGoal(Controller):
    """Heads for the goal at the vessel's top speed within its limits, blind to other ships."""

    name = "straight"

    def decide(self, own, targets, encounter=None) -> Decision:
        w, vessel = self.world, self.world.vessel
        bearing = math.atan2(w.goal[1] - own.y, w.goal[0] - own.x)
        turn = math.remainder(bearing - own.psi, 2 * math.pi) / w.period
        reach = vessel.max_yaw_accel * w.period
        omega = np.clip(turn, own.omega - reach, own.omega + reach)
        omega = float(np.clip(omega, -vessel.max_yaw_rate, vessel.max_yaw_rate))
        return Decision(min(vessel.max_speed, own.v + vessel.max_accel * w.period), omega)


SCENARIO = {
    "name": "open-crossing",
    "sim": {"dt": 0.2, "duration": 30, "goal_tolerance": 5},
    "map": "map.tif",
    "own": {"start": [100, 10], "goal": [100, 80], "heading": 0, "speed": 3},
    "targets": [{"start": [180, 40], "heading": 0, "speed": 1, "length": 5}],
    "controller": {"name": "straight"},
}


@pytest.fixture(scope="module")
def registered():
    optimizers.register(RandomSearch)
    EXACT.register(EightConnected)
    controllers.register(StraightToGoal)
    yield
    optimizers.unregister("random")
    EXACT.unregister("my-astar")
    controllers.unregister("straight")


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A 40 m open grid with a block in the middle, and the scenario on a 200 m open map."""
    root = tmp_path_factory.mktemp("extending")
    cells = np.zeros((40, 40), np.uint8)
    cells[15:25, 18:22] = 1
    write_grid(root / "grid.tif", Grid(cells, Affine(1, 0, 0, 0, -1, 40)))
    write_grid(root / "map.tif", Grid(np.zeros((100, 100), np.uint8),
                                      Affine(2, 0, 0, 0, -2, 200)))  # fmt: skip
    (root / "s.yaml").write_text(yaml.safe_dump(SCENARIO, sort_keys=False))
    return root


def usvtool(*args) -> object:
    return CliRunner().invoke(cli, [str(a) for a in args])


def test_the_registries_add_and_remove(registered):
    assert optimizers.OPTIMIZERS["random"] is RandomSearch
    assert controllers.CONTROLLERS["straight"] is StraightToGoal
    with pytest.raises(ValueError, match="already registered"):
        optimizers.register(RandomSearch)
    with pytest.raises(ValueError, match="already registered"):
        controllers.register(StraightToGoal)


@pytest.mark.parametrize("algo", ["random", "random+s", "random+g"])
def test_the_optimizer_plans_through_the_api(registered, files, reference, algo):
    from usvtool.grid import read_grid

    grid = read_grid(files / "grid.tif")
    options = PlanOptions(algo, pop=10, iters=20, seed=4, attempts=5)
    route = plan_route(grid, START, GOAL, options).route
    assert route.algorithm == algo and route.seed == 4
    assert route.parameters["share"] == 1.0 and route.parameters["pop"] == 10
    assert len(route.convergence) == 20 or algo == "random+g" and not route.convergence
    col, row = grid.to_cell_coords(*np.asarray(route.points).T)
    assert route.collision_free == reference(grid.blocked).route_free(np.column_stack([col, row]))
    again = plan_route(grid, START, GOAL, options).route
    assert np.array_equal(again.points, route.points)  # the seed decides


def test_the_exact_planner_plans_as_astar_without_a_seed_nor_variants(registered, files):
    from usvtool.grid import read_grid

    grid = read_grid(files / "grid.tif")
    mine = plan_route(grid, START, GOAL, PlanOptions("my-astar", seed=4)).route
    astar = plan_route(grid, START, GOAL, PlanOptions("astar")).route
    assert mine.algorithm == "my-astar" and mine.seed is None and mine.collision_free
    assert np.array_equal(mine.points, astar.points)
    with pytest.raises(UsvError, match=r"^'my-astar\+s': my-astar has no \+s variant \(its "
                                       r"variants: none\)$"):  # fmt: skip
        plan_route(grid, START, GOAL, PlanOptions("my-astar+s"))


def test_the_optimizer_plans_through_the_command_line(registered, files):
    out = files / "route.geojson"
    r = usvtool("plan", files / "grid.tif", "--start", *START, "--goal", *GOAL, "--algo",
                "random", "--pop", 10, "--iters", 20, "--seed", 4, "--attempts", 5,
                "--no-timing", "-o", out, "--allow-collision")  # fmt: skip
    assert r.exit_code == 0, r.output
    props = json.loads(out.read_text())["features"][0]["properties"]
    assert props["algorithm"] == "random" and props["parameters"]["share"] == 1.0
    r = usvtool("plan", files / "grid.tif", "--start", *START, "--goal", *GOAL, "--algo",
                "random+g", "--param", "share=0", "-o", files / "no.geojson")  # fmt: skip
    assert r.exit_code == 1
    assert r.stderr == "Error: --param share must be in (0, 1] for random, not 0\n"


def test_the_controller_runs_through_the_api_and_the_command_line(registered, files):
    from usvtool.sim.run import simulate
    from usvtool.sim.scenario import read_scenario

    summary = simulate(read_scenario(files / "s.yaml")).summary()
    assert summary["controller"] == "straight" and summary["arrived"]
    # heading north from (100, 10) to (100, 80): straight, stopping within 5 m of the goal
    assert summary["turns"] == 0 and 65 <= summary["path_length_m"] < 70
    out = files / "runs" / "k2"
    out.mkdir(parents=True)
    r = usvtool("simulate", files / "s.yaml", "-o", out / "trace.csv", "--events",
                out / "trace.events.json")  # fmt: skip
    assert r.exit_code == 0, r.output
    printed = json.loads(r.stdout)
    assert printed["controller"] == "straight" and printed["arrived"]
    assert printed["time_s"] == summary["time_s"]


def test_the_pipelines_and_the_report_know_both(registered, files):
    from usvtool.cli.batch import stage_names
    from usvtool.cli.report import stage_methods
    from usvtool.pipeline import load

    (files / "chart.geojson").write_text("{}")
    path = files / "pipeline.yaml"
    path.write_text(yaml.safe_dump({
        "charts": {"m": {"source": "chart.geojson", "start": [1, 1], "goal": [5, 5]}},
        "routes": {"a": {"charts": ["m"], "algorithms": ["random", "random+g", "anyangle"],
                         "seeds": [1]}},
        "simulation": {"scenarios": ["s.yaml"], "controllers": ["straight", "dwa"], "seeds": [1]},
        "functions": {"functions": ["F1"], "algorithms": ["random"], "seeds": [1]},
    }))  # fmt: skip
    names = stage_names()
    p = load(path, names)
    assert [(j.algorithm, j.seed) for j in p.route_jobs(names)] == [("random", 1),
                                                                  ("random+g", 1),
                                                                  ("anyangle", None)]  # fmt: skip
    assert [c for _, c, _ in p.simulation_jobs()] == ["straight", "dwa"]
    assert p.function_jobs() == [("F1", "random", 1)]
    order = stage_methods()
    assert order.index("boa") < order.index("random") < order.index("anyangle")
    assert order.index("udwa+") < order.index("straight")  # after the built-in ones


def test_the_report_tables_show_both(registered, files, tmp_path):
    from usvtool.cli.report import stage_methods
    from usvtool.report.data import load
    from usvtool.report.sections.encounters import compliance_table, primary, run_table
    from usvtool.report.sections.planning import metrics_table

    rows = [Row(k, "routes", "open", m, 1, metric, value) for k, m in (("a1", "astar"),
            ("a2", "random"), ("a3", "iwso")) for metric, value in (("length_m", "41.5"),
            ("collision_free", "True"))]  # fmt: skip
    rows += [Row(k, "runs", "open-crossing", c, 1, metric, value) for k, c in (("b1", "dwa"),
             ("b2", "straight")) for metric, value in (("arrived", "True"),
             ("arrival_time_s", "22.4"), ("encounters", "1"), ("judged", "1"),
             ("compliant", "1"))]  # fmt: skip
    table = tmp_path / "metrics.csv"
    write_results(table, rows)
    results = load([table], stage_methods())
    assert results.methods("routes", "open") == ["iwso", "random", "astar"]  # registry order
    planning = metrics_table(results, "open", results.methods("routes", "open"))
    assert [r[0].text for r in planning.rows] == ["iwso", "random", "astar"]
    runs = results.methods("runs", "open-crossing")
    assert runs == ["dwa", "straight"]
    assert [r[0].text for r in run_table(results, "open-crossing", runs).rows] == runs
    assert [r[1].text for r in compliance_table(results).rows] == ["dwa", "straight"]
    assert primary("open-crossing", ["straight"]) == "straight"  # where it ran alone


def test_the_snapshots_controller_comes_from_the_papers_claims():
    """No table of controller names in the report: the controller the papers' claims test on
    a scenario's family (the one its paper runs there), else the first a claim tests (gdwa),
    else the first that ran."""
    from usvtool.report.sections import encounters

    assert not hasattr(encounters, "PRIMARY")
    every = list(controllers.CONTROLLERS)
    chosen = {s: encounters.primary(s, every) for s in ("env1-head-on", "env2-static",
              "emergency-crossing", "wind-northwest-strong", "rudee-inlet-channel")}  # fmt: skip
    assert chosen == {"env1-head-on": "gdwa", "env2-static": "gdwa", "emergency-crossing": "udwa",
                      "wind-northwest-strong": "udwa", "rudee-inlet-channel": "gdwa"}  # fmt: skip
    assert encounters.primary("env1-head-on", ["dwa", "udwa"]) == "dwa"
