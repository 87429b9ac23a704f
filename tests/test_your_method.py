"""The worked example of docs/your-method.md: examples/usvtool-example, installed with pip into a
folder of its own (never into the running environment), is found by usvtool through its entry
points, and its two methods do what their docstrings say (hand-computed decisions of ``apf``,
``de`` on the sphere). The doc's commands themselves (batch and report included) run in
tests/test_documented_commands.py."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from usvtool.sim.controllers.base import Own, Targets, World
from usvtool.sim.vessel import vessel_from

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "usvtool-example"


@pytest.fixture(scope="module")
def example():
    """The example's modules, imported from its source without registering them (the
    registries here stay as they are)."""
    sys.path.insert(0, str(EXAMPLE / "src"))
    try:
        from usvtool_example import apf, de

        yield apf, de
    finally:
        sys.path.remove(str(EXAMPLE / "src"))
        for name in [m for m in sys.modules if m.startswith("usvtool_example")]:
            del sys.modules[name]


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    site = tmp_path_factory.mktemp("plugins")
    subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--target",
                    str(site), str(EXAMPLE)], check=True, capture_output=True)  # fmt: skip
    return site


def test_the_installed_example_is_listed_with_its_distribution_and_parameters(site):
    env = {**os.environ, "PYTHONPATH": str(site)}
    r = subprocess.run([sys.executable, "-m", "usvtool.cli", "plugins"], env=env,
                       capture_output=True, text=True)  # fmt: skip
    assert r.returncode == 0, r.stderr
    listed = json.loads(r.stdout)
    methods = {m["name"]: m for m in listed["methods"]}
    assert (methods["apf"]["kind"], methods["apf"]["distribution"],
            methods["apf"]["version"]) == ("controller", "usvtool-example", "0.1.0")  # fmt: skip
    assert methods["de"]["distribution"] == "usvtool-example"
    assert set(methods["apf"]["parameters"]) == {"reach", "push", "gain"}
    assert set(methods["de"]["parameters"]) >= {"f", "cr"}
    assert listed["problems"] == []
    assert not any(p.name.startswith("usvtool_example") for p in ROOT.rglob("*.egg-info"))


def world(goal=(100.0, 0.0)) -> World:
    return World(vessel_from("udwa-usv"), np.array(goal), period=0.1)


def test_apf_heads_for_the_goal_within_the_vessels_limits(example):
    apf, _ = example
    c = apf.PotentialField()
    c.reset(world())
    v = c.world.vessel
    # heading north, the goal due east: the error is -pi/2 (to starboard), the yaw rate the
    # gain times it, clipped to what the yaw acceleration reaches in one period
    d = c.decide(Own(0.0, 0.0, math.pi / 2, 1.0, 0.0), Targets.none())
    assert d.omega == pytest.approx(max(-math.pi / 2, -v.max_yaw_accel * 0.1))
    assert d.v == pytest.approx(min(v.max_speed, 1.0 + v.max_accel * 0.1))


def test_apf_turns_to_starboard_of_a_target_ahead(example):
    apf, _ = example
    c = apf.PotentialField(gain=100.0)
    c.reset(world())
    v = c.world.vessel
    # a target dead ahead 50 m off, on the line to the goal: its push, 2 (120 / 50 - 1) = 2.8,
    # is to the right of the line of sight (south), the force (1, -2.8) points 70 degrees to
    # starboard: a turn to starboard (a negative yaw rate), as hard as the limits allow
    head_on = Targets(np.array([[50.0, 0.0]]), np.array([[-2.0, 0.0]]), np.array([5.0]))
    d = c.decide(Own(0.0, 0.0, 0.0, 2.0, 0.0), head_on)
    assert d.omega == pytest.approx(-min(v.max_yaw_rate, v.max_yaw_accel * 0.1))
    alone = c.decide(Own(0.0, 0.0, 0.0, 2.0, 0.0), Targets.none())
    assert alone.omega == 0.0


def test_de_minimises_the_sphere(example):
    _, de = example
    from usvtool.plan.benchmark_functions import sphere

    result = de.DifferentialEvolution(pop=30, iters=200, seed=1).minimize(sphere, -100, 100)
    # a 1-D box: DE/rand/1/bin (F 0.5, CR 0.9) converges to the optimum, 0, and a seed
    # gives the same run
    assert result.f < 1e-12
    assert result.history[-1] <= result.history[0]
    again = de.DifferentialEvolution(pop=30, iters=200, seed=1).minimize(sphere, -100, 100)
    assert again.f == result.f


def test_de_keeps_a_trial_only_when_it_is_no_worse(example):
    _, de = example
    # the best so far never gets worse, and on a 5-D sphere the search makes progress
    lower, upper = np.full(5, -10.0), np.full(5, 10.0)
    r = de.DifferentialEvolution(pop=20, iters=60, seed=3).minimize(
        lambda X: (X**2).sum(axis=1), lower, upper
    )
    assert np.all(np.diff(r.history) <= 0)
    assert r.history[-1] < r.history[0] / 100


PIPELINE = """root: {root}
charts:
  grid20: {{source: charts/grid20.geojson, options: {{cell-size: 1, no-swell: true,
           occupancy: 0.5}}, start: [0.5, 0.5], goal: [19.5, 19.5]}}
routes:
  example:
    charts: [grid20]
    algorithms: [de, de+g, pso]
    seeds: [1, 2]
    options: {{pop: 10, iters: 20}}
families:
  - family: emergency
    kinds: [head-on]
    scenes: [0, 1]
    controllers: [apf, udwa]
    seeds: [1]
claims:
  - id: apf-hits-nothing
    method: apf
    metric: collision
    better: lower
    target: 0
    cases: [emergency/head-on]
"""
#: The grid, 6 routes, 4 family runs.
JOBS = 1 + 6 + 4


@pytest.mark.slow  # whole pipelines: batches, and a Dask cluster
def test_the_example_gives_one_table_in_local_workers_and_on_a_dask_cluster(site, dask_cluster,
                                                                            tmp_path):  # fmt: skip
    """The pip-installed example's planner (with its +g) and controller in a pipeline with a
    claim, in batch -j 2 and on a scheduler with two workers (the example on their PYTHONPATH):
    the same results table and claims, byte for byte; the report judges the claim."""
    env = {**os.environ, "PYTHONPATH": str(site)}
    pipeline = tmp_path / "example.yaml"
    pipeline.write_text(PIPELINE.format(root=ROOT))

    def usvtool(*args):
        return subprocess.run([sys.executable, "-m", "usvtool.cli", *map(str, args)], env=env,
                              capture_output=True, text=True)  # fmt: skip

    local = usvtool("batch", pipeline, "-j", 2, "-o", tmp_path / "local")
    assert local.returncode == 0, local.stderr
    assert (json.loads(local.stdout)["done"], json.loads(local.stdout)["failed"]) == (JOBS, 0)
    table = (tmp_path / "local" / "metrics.csv").read_bytes()
    for method in (b",de,", b",de+g,", b",apf,"):
        assert method in table, method
    remote = usvtool("batch", pipeline, "--scheduler", dask_cluster, "-o", tmp_path / "dask")
    assert remote.returncode == 0, remote.stderr
    assert json.loads(remote.stdout)["done"] == JOBS
    for name in ("metrics.csv", "claims.json"):
        assert (tmp_path / "dask" / name).read_bytes() == (tmp_path / "local" / name).read_bytes()
    report = usvtool("report", tmp_path / "local" / "metrics.csv", "--no-pdf", "-o",
                     tmp_path / "report")  # fmt: skip
    assert report.returncode == 0, report.stderr
    summary = json.loads(report.stdout)
    assert "your-claims" in summary["sections"] and sum(summary["your_claims"].values()) == 1
