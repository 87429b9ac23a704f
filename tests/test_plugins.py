"""Plugins by entry points (usvtool/registry.py): a distribution installed beside usvtool (here a
``.dist-info`` folder and its module on PYTHONPATH, which is what ``pip install`` leaves) declares
a controller and an optimizer under ``usvtool.controllers`` and ``usvtool.planners``; both run
through the command line as built-in ones do, and each plugin that cannot be used (an import
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
from usvtool.sim.controllers.dwa import DWA


class SlowDWA(DWA):
    """DWA under another name, its parameters DWA's."""
    name = "slow-dwa"


class WidePSO(PSO):
    name = "wide-pso"


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
