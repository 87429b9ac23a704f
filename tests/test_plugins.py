"""Plugins by entry points (usvtool/registry.py): a distribution installed beside usvtool (here a
``.dist-info`` folder and its module on PYTHONPATH, which is what ``pip install`` leaves) declares
a controller, an optimizer, an exact planner and a scene family under ``usvtool.controllers``,
``usvtool.planners`` and ``usvtool.families``; each runs through the command line as built-in
ones do (simulate, plan with the variants, scene, a pipeline in batch -j 2 and on a Dask cluster
of a scheduler and two workers, the same table), and each plugin that cannot be used (an import
that fails, a class of the wrong kind, a name taken) is named in one line while the rest works."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from usvtool.registry import Registry

ROOT = Path(__file__).resolve().parent.parent
SCENARIO = ROOT / "charts" / "scenarios" / "emergency-head-on.yaml"
GRID = ROOT / "charts" / "grid20.tif"

MODULE = '''
from usvtool.plan.optimizers.pso import PSO
from usvtool.plan.planners import AStar
from usvtool.sim.controllers.dwa import DWA
from usvtool.sim.families.emergency import Emergency


class SlowDWA(DWA):
    """DWA under another name, its parameters DWA's."""
    name = "slow-dwa"


class WidePSO(PSO):
    name = "wide-pso"


class MyAStar(AStar):
    """A* under another name: a plugin's exact planner, without the built-ins' +s."""
    name = "my-astar"
    variants = ()


class MyEmergency(Emergency):
    """The emergencies under another name (other scenes: the name seeds the draws), run by the
    plugin's controller."""
    name = "my-emergency"
    controller = "slow-dwa"


class NotAController:
    name = "plain"


class Taken(DWA):
    name = "dwa"
'''
ENTRY_POINTS = """[usvtool.controllers]
slow-dwa = usvplug:SlowDWA
broken = usvplug.missing:Nothing
plain = usvplug:NotAController
taken = usvplug:Taken

[usvtool.planners]
wide-pso = usvplug:WidePSO
my-astar = usvplug:MyAStar

[usvtool.families]
my-emergency = usvplug:MyEmergency
"""


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """A folder holding the distribution ``usvplug`` 1.2 as pip installs one."""
    site = tmp_path_factory.mktemp("site")
    (site / "usvplug").mkdir()
    (site / "usvplug" / "__init__.py").write_text(MODULE)
    info = site / "usvplug-1.2.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: usvplug\nVersion: 1.2\n")
    (info / "entry_points.txt").write_text(ENTRY_POINTS)
    return site


def usvtool(site: Path, *args) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(site)}
    return subprocess.run([sys.executable, "-m", "usvtool.cli", *map(str, args)], env=env,
                          capture_output=True, text=True)  # fmt: skip


def test_a_plugin_controller_runs_and_each_bad_plugin_is_one_line(site, tmp_path):
    r = usvtool(site, "simulate", SCENARIO, "--controller", "slow-dwa", "-o", tmp_path / "t.csv")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["controller"] == "slow-dwa"
    assert (tmp_path / "t.csv").read_text().startswith("t,ship,x,y")
    where = "(usvplug 1.2, usvtool.controllers)"
    problems = [line for line in r.stderr.splitlines() if "plugin" in line]
    assert len(problems) == 3 and all(where in line for line in problems), r.stderr
    broken, plain, taken = problems  # sorted by their entry points' names
    assert broken.startswith("usvtool: plugin broken = usvplug.missing:Nothing ")
    assert broken.endswith("cannot be imported: ModuleNotFoundError: No module named "
                           "'usvplug.missing'")  # fmt: skip
    assert plain.startswith("usvtool: plugin plain = usvplug:NotAController ")
    assert plain.endswith("is not a subclass of Controller")
    assert taken.endswith("controller 'dwa': already registered (by usvtool)")


def test_a_plugin_optimizer_plans_like_a_built_in_one(site, tmp_path):
    args = ("plan", GRID, "--start", 0.5, 0.5, "--goal", 18.5, 18.5, "--pop", 10, "--iters", 20,
            "--seed", 3)  # fmt: skip
    plugin = usvtool(site, *args, "--algo", "wide-pso", "-o", tmp_path / "a.geojson")
    built_in = usvtool(site, *args, "--algo", "pso", "-o", tmp_path / "b.geojson")
    assert plugin.returncode in (0, 3) and built_in.returncode == plugin.returncode, plugin.stderr
    assert json.loads(plugin.stdout)["algorithm"] == "wide-pso"
    # the same equations under another name: the same route, bit for bit
    a, b = (json.loads((tmp_path / f"{n}.geojson").read_text())["features"] for n in "ab")
    assert [f["geometry"] for f in a] == [f["geometry"] for f in b]


def test_the_registry_checks_kind_name_and_origin():
    class Base:
        pass

    class One(Base):
        name = "one"

    registry = Registry("thing", Base, "usvtool.no-such-group",
                        lambda cls: "has a '+'" if "+" in cls.name else None)  # fmt: skip
    registry.register(One)
    assert list(registry) == ["one"] and registry["one"] is One
    assert registry.origin("one")[0] == "usvtool" and registry.problems == []
    for cls, why in [(type("Two", (Base,), {"name": "one"}), "thing 'one': already registered"),
                     (type("Three", (Base,), {"name": "a+b"}), "thing 'a+b': has a '+'"),
                     (type("Four", (Base,), {}), "thing None: no name"),
                     (type("Five", (), {"name": "five"}), "is not a subclass of Base")]:
        with pytest.raises(ValueError, match=why.replace("+", r"\+")):
            registry.register(cls)
    registry.unregister("one")
    assert len(registry) == 0


def test_registries_sharing_a_group_share_its_names_and_problems():
    """The optimizers and the exact planners share usvtool.planners: a name is one method of
    the group, and a built-in registered after a plugin took its name takes it back."""

    class A:
        pass

    class B:
        pass

    a = Registry("a-thing", A, "usvtool.no-such-group")
    b = Registry("b-thing", B, "usvtool.no-such-group", shares=a)
    a.register(type("One", (A,), {"name": "one"}))
    with pytest.raises(ValueError, match=r"^b-thing 'one': already registered \(by usvtool\)$"):
        b.register(type("Other", (B,), {"name": "one"}))
    where = "plugin two = plug:P (plug 1.0, usvtool.no-such-group)"
    b.register(type("P", (B,), {"name": "two"}), ("plug", "1.0"), where)
    with pytest.raises(ValueError, match=r"^a-thing 'two': already registered \(by plug\)$"):
        a.register(type("Q", (A,), {"name": "two"}), ("other", "2"))
    a.register(type("Two", (A,), {"name": "two"}))  # a built-in
    assert list(a) == ["one", "two"] and list(b) == [] and a.problems is b.problems
    assert a.problems == [f"{where}: b-thing 'two': already registered (by usvtool)"]
    with pytest.raises(ValueError, match="shares group usvtool.no-such-group, not other"):
        Registry("c-thing", A, "other", shares=a)


def test_plugins_lists_every_method_with_its_origin_and_parameters(site):
    r = usvtool(site, "plugins")
    assert r.returncode == 0, r.stderr
    listed = json.loads(r.stdout)
    methods = {m["name"]: m for m in listed["methods"]}
    assert methods["slow-dwa"] == {**methods["dwa"], "name": "slow-dwa", "distribution":
                                   "usvplug", "version": "1.2"}  # fmt: skip
    assert methods["wide-pso"]["kind"] == "optimizer" and methods["wide-pso"]["version"] == "1.2"
    assert methods["pso"]["distribution"] == "usvtool"
    # every parameter with its default and its range or choices, from the one declaration
    assert methods["pso"]["parameters"]["c1"] == {
        "default": 2.0, "kind": "number", "takes": "a finite number >= 0", "range": ">= 0",
        "help": "the pull toward the particle's own best"}  # fmt: skip
    assert methods["udwa"]["parameters"]["sides"]["choices"] == ["none", "paper", "colregs",
                                                                 "iwso"]  # fmt: skip
    assert methods["udwa"]["parameters"]["v_samples"]["takes"] == "an integer >= 2"
    assert methods["ais"]["parameters"]["tracks"]["required"] is True
    assert methods["wide-pso"]["parameters"] == methods["pso"]["parameters"]
    assert all(m["parameters"] for m in listed["methods"] if m["kind"] != "exact planner")
    assert {m["kind"] for m in listed["methods"]} == {"optimizer", "exact planner", "controller",
                                                      "scene family"}  # fmt: skip
    assert methods["imazu"]["kind"] == "scene family" and "astar" in methods
    assert len(listed["problems"]) == 3 and methods["dwa"]["distribution"] == "usvtool"


@pytest.mark.slow  # whole pipelines: batches, and a Dask cluster
def test_a_plugins_batch_jobs_run_in_workers_and_again_once_it_is_upgraded(tmp_path_factory):
    site = tmp_path_factory.mktemp("upgraded")
    (site / "usvplug").mkdir()
    (site / "usvplug" / "__init__.py").write_text(MODULE)
    info = site / "usvplug-1.2.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: usvplug\nVersion: 1.2\n")
    (info / "entry_points.txt").write_text("[usvtool.controllers]\nslow-dwa = usvplug:SlowDWA\n")
    pipeline = site / "p.yaml"
    pipeline.write_text(f"simulation: {{scenarios: ['{SCENARIO}'], controllers: [slow-dwa, dwa], "
                        "seeds: [1]}\n")  # fmt: skip
    out = site / "out"
    first = usvtool(site, "batch", pipeline, "-j", 2, "-o", out)
    assert first.returncode == 0, first.stderr
    assert (json.loads(first.stdout)["done"], json.loads(first.stdout)["failed"]) == (2, 0)
    rows = (out / "metrics.csv").read_text()
    assert ",slow-dwa," in rows and ",dwa," in rows
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: usvplug\nVersion: 1.3\n")
    info.rename(site / "usvplug-1.3.dist-info")
    again = json.loads(usvtool(site, "batch", pipeline, "-j", 2, "-o", out).stdout)
    assert (again["done"], again["skipped"]) == (1, 1)  # the plugin's run again, dwa's kept


def test_a_plugin_exact_planner_plans_without_a_seed_nor_variants(site, tmp_path):
    args = ("plan", GRID, "--start", 0.5, 0.5, "--goal", 18.5, 18.5)
    plugin = usvtool(site, *args, "--algo", "my-astar", "-o", tmp_path / "a.geojson")
    built_in = usvtool(site, *args, "--algo", "astar", "-o", tmp_path / "b.geojson")
    assert plugin.returncode == 0 and built_in.returncode == 0, plugin.stderr
    a, b = (json.loads((tmp_path / f"{n}.geojson").read_text())["features"] for n in "ab")
    assert a[0]["properties"]["algorithm"] == "my-astar" and a[0]["properties"]["seed"] is None
    assert [f["geometry"] for f in a] == [f["geometry"] for f in b]  # A*'s route
    for algo in ("my-astar+s", "my-astar+g"):
        r = usvtool(site, *args, "--algo", algo, "-o", tmp_path / "c.geojson")
        assert r.returncode == 1 and not (tmp_path / "c.geojson").exists()
        assert r.stderr.splitlines()[-1] == (f"Error: {algo!r}: my-astar has no {algo[-2:]} "
                                             "variant (its variants: none)")  # fmt: skip
    # and a pipeline naming one is refused when it loads, before any job runs
    pipeline = tmp_path / "p.yaml"
    pipeline.write_text(f"root: {ROOT}\ncharts: {{g: {{source: charts/grid20.geojson, start: "
                        "[0.5, 0.5], goal: [18.5, 18.5]}}\nroutes: {r: {charts: [g], "
                        "algorithms: [astar+s, my-astar, my-astar+s], seeds: [1]}}\n")  # fmt: skip
    r = usvtool(site, "batch", pipeline, "-o", tmp_path / "out")
    assert r.returncode == 1 and not (tmp_path / "out").exists()
    assert "routes.r.algorithms[2]: unknown algorithm 'my-astar+s'" in r.stderr, r.stderr
    listed = {m["name"]: m for m in json.loads(usvtool(site, "plugins").stdout)["methods"]}
    mine = listed["my-astar"]
    assert (mine["kind"], mine["distribution"], mine["parameters"]) == ("exact planner",
                                                                        "usvplug", {})  # fmt: skip
    assert (listed["my-emergency"]["kind"], listed["my-emergency"]["version"]) == (
        "scene family", "1.2")  # fmt: skip


def test_a_planners_plugin_of_neither_kind_is_named_with_both_bases(tmp_path):
    (tmp_path / "oddplug.py").write_text("class Odd:\n    name = 'odd'\n")
    info = tmp_path / "oddplug-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: oddplug\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text("[usvtool.planners]\nodd = oddplug:Odd\n")
    r = usvtool(tmp_path, "plugins")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["problems"] == [
        "plugin odd = oddplug:Odd (oddplug 0.1, usvtool.planners): <class 'oddplug.Odd'> is not "
        "a subclass of Optimizer or ExactPlanner"]  # fmt: skip


PIPELINE = """root: {root}
charts:
  grid20: {{source: charts/grid20.geojson, options: {{cell-size: 1, no-swell: true,
           occupancy: 0.5}}, start: [0.5, 0.5], goal: [19.5, 19.5]}}
routes:
  plugins:
    charts: [grid20]
    algorithms: [wide-pso, wide-pso+s, wide-pso+g, my-astar, astar]
    seeds: [1]
    options: {{pop: 10, iters: 10}}
simulation:
  scenarios: [tests/batch/scenarios/open-head-on.yaml]
  controllers: [slow-dwa]
  seeds: [1]
families:
  - family: my-emergency
    kinds: [head-on]
    scenes: [0]
    controllers: [slow-dwa, dwa]
    seeds: [1]
    options: {{duration: 6}}
functions:
  functions: [F1]
  algorithms: [wide-pso]
  seeds: [1]
  pop: 10
  iters: 20
  dim: 5
"""
#: The pipeline's jobs: the grid, 5 routes, a run, 2 family runs, a benchmark function.
PIPELINE_JOBS = 1 + 5 + 1 + 2 + 1


def test_plugins_plan_with_their_variants_and_draw_and_run_scenes(site, tmp_path):
    """The plugin's optimizer with its +s and +g, and its family's scene (a file), run by the
    plugin's controller the family names."""
    for algo in ("wide-pso", "wide-pso+s", "wide-pso+g"):
        r = usvtool(site, "plan", GRID, "--start", 0.5, 0.5, "--goal", 18.5, 18.5, "--pop", 10,
                    "--iters", 10, "--algo", algo, "-o", tmp_path / f"{algo}.geojson")  # fmt: skip
        assert r.returncode in (0, 3) and json.loads(r.stdout)["algorithm"] == algo, r.stderr
    r = usvtool(site, "scene", "--family", "my-emergency", "--kind", "head-on",
                "--family-option", "duration=6", "-o", tmp_path / "s.yaml")  # fmt: skip
    assert r.returncode == 0, r.stderr
    scene = json.loads(r.stdout)
    assert (scene["family"], scene["name"]) == ("my-emergency",
                                                "my-emergency-head-on-s000-duration=6")
    r = usvtool(site, "simulate", tmp_path / "s.yaml", "-o", tmp_path / "s.csv")
    assert r.returncode == 0 and json.loads(r.stdout)["controller"] == "slow-dwa", r.stderr


@pytest.mark.slow  # whole pipelines: batches, and a Dask cluster
def test_a_pipeline_of_plugins_gives_one_table_locally_and_on_a_dask_cluster(site, dask_cluster,
                                                                             tmp_path):  # fmt: skip
    """The plugin's controller, optimizer (and its +s, +g), exact planner and family in one
    pipeline, in batch -j 2 and on a scheduler and two workers: the same results table, byte
    for byte (the jobs' keys hash usvtool's code: run it on a tree nobody edits meanwhile)."""
    pipeline = tmp_path / "plugins.yaml"
    pipeline.write_text(PIPELINE.format(root=ROOT))
    local = usvtool(site, "batch", pipeline, "-j", 2, "-o", tmp_path / "local")
    assert local.returncode == 0, local.stderr
    summary = json.loads(local.stdout)
    assert (summary["done"], summary["failed"]) == (PIPELINE_JOBS, 0), local.stderr
    table = (tmp_path / "local" / "metrics.csv").read_text()
    for method in ("wide-pso", "wide-pso+s", "wide-pso+g", "my-astar", "slow-dwa"):
        assert f",{method}," in table, method
    assert ",my-emergency/head-on/s000," in table
    remote = usvtool(site, "batch", pipeline, "--scheduler", dask_cluster, "-o",
                     tmp_path / "dask")  # fmt: skip
    assert remote.returncode == 0, remote.stderr
    summary = json.loads(remote.stdout)
    assert summary["executor"].startswith(f"dask {dask_cluster}, 2 worker threads")
    assert (summary["done"], summary["failed"]) == (PIPELINE_JOBS, 0), remote.stderr
    assert (tmp_path / "dask" / "metrics.csv").read_bytes() == table.encode()
