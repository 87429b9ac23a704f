"""What ``usvtool simulate`` pays beyond its stepping (docs/simulate.md, "Start-up"): a scenario
file's run imports no scene family, the console script leaves the last collections over numba's
kernels out of its exit, and a run loads only the kernels it calls."""

import subprocess
import sys

import pytest
import yaml

PROBE = """
import atexit, gc, json, sys

def report():  # registered before main(): runs after its handlers, as the process ends
    print(json.dumps({"frozen": gc.get_freeze_count() > 0,
                      "families": sorted(m for m in sys.modules if ".families" in m)}))

atexit.register(report)
sys.argv = ["usvtool", "-q", *sys.argv[1:]]
from usvtool.cli import main
main()
"""


def test_a_scenario_file_runs_without_the_families_and_exits_frozen(charts, tmp_path):
    scenario = yaml.safe_load((charts / "scenarios" / "emergency-head-on.yaml").read_text())
    scenario["sim"]["duration"] = 1.0  # ten steps: the process's own costs are the point
    path = tmp_path / "short.yaml"
    path.write_text(yaml.safe_dump(scenario))
    out = subprocess.run([sys.executable, "-c", PROBE, "simulate", str(path), "-o",
                          str(tmp_path / "t.csv")], capture_output=True, text=True, check=True,
                         cwd=tmp_path)  # fmt: skip
    last = out.stdout.strip().splitlines()[-1]
    assert yaml.safe_load(last) == {"frozen": True, "families": []}
    assert (tmp_path / "t.csv").read_text().startswith("t,ship,x,y")


def test_a_family_scene_still_finds_its_family(tmp_path):
    out = subprocess.run([sys.executable, "-c", PROBE, "simulate", "--family", "imazu", "--kind",
                          "01", "--family-option", "duration=1", "--scenario-out",
                          "s.yaml", "-o", "t.csv"], capture_output=True, text=True, check=True,
                         cwd=tmp_path)  # fmt: skip
    report = yaml.safe_load(out.stdout.strip().splitlines()[-1])
    assert report["frozen"] and "usvtool.sim.families.imazu" in report["families"]
    assert "name: imazu-01-s000" in (tmp_path / "s.yaml").read_text()


KERNELS = """
import atexit, json, sys

def report():  # after main(): which kernels the run loaded, and how many specialisations
    from usvtool.lazy_kernels import loaded
    names = ("sim.rollout_kernels", "sim.tracking_kernels", "sim.weather_kernels",
             "collision_kernels")
    mods = {n.split(".")[-1]: sys.modules["usvtool." + n] for n in names
            if "usvtool." + n in sys.modules}
    print(json.dumps({n: loaded(m) for n, m in mods.items()}))

atexit.register(report)
sys.argv = ["usvtool", "-q", *sys.argv[1:]]
from usvtool.cli import main
main()
"""


@pytest.mark.parametrize(
    ("controller", "rollouts"),
    [("udwa", {"period_sweep", "weighted_shares", "heading_reward", "candidates"}),
     ("vo", {"vo_candidates", "vo_contacts", "vo_near"}),
     ("sbmpc", set())],
)  # fmt: skip
def test_a_run_loads_only_the_kernels_it_calls(charts, tmp_path, controller, rollouts):
    """The kernels' signatures are loaded at their first calls (usvtool.lazy_kernels.declared),
    not at import: a DWA run loads its step's few, not the period sweep's callees (compiled into
    it) nor vo's; one specialisation each."""
    scenario = yaml.safe_load((charts / "scenarios" / "emergency-head-on.yaml").read_text())
    scenario["sim"]["duration"] = 1.0
    path = tmp_path / "short.yaml"
    path.write_text(yaml.safe_dump(scenario))
    out = subprocess.run([sys.executable, "-c", KERNELS, "simulate", str(path), "--controller",
                          controller, "-o", str(tmp_path / "t.csv")], capture_output=True,
                         text=True, check=True, cwd=tmp_path)  # fmt: skip
    loaded = yaml.safe_load(out.stdout.strip().splitlines()[-1])
    assert loaded["tracking_kernels"] == {"track_urgent": 1, "first_touching": 1}
    mine = loaded.get("rollout_kernels", {})  # sbmpc's run imports none of them
    assert set(mine) >= rollouts
    assert set(mine) <= rollouts | {"favour", "offsets", "wrap_angles"}
    assert set(mine.values()) <= {1}
    assert not loaded.get("weather_kernels")


def test_a_plan_loads_the_collision_check_it_calls_not_every_kernel(charts, tmp_path):
    """The collision kernels are declared too (usvtool.lazy_kernels): a plan's checker loads
    the check and the traversal, not the strips (compiled into them) nor the line of sight of
    the exact planners."""
    out = subprocess.run([sys.executable, "-c", KERNELS, "plan", str(charts / "grid20.tif"),
                          "--start", "0.5", "0.5", "--goal", "19.5", "19.5", "--algo", "pso",
                          "--pop", "10", "--iters", "5", "--allow-collision", "-o",
                          str(tmp_path / "r.geojson")],
                         capture_output=True, text=True, check=True, cwd=tmp_path)  # fmt: skip
    loaded = yaml.safe_load(out.stdout.strip().splitlines()[-1])
    assert loaded["collision_kernels"] == {"check": 1, "traverse": 1}
    assert "rollout_kernels" not in loaded
