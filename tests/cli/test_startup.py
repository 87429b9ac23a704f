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
    from usvtool.sim import rollout_kernels
    names = ("rollout_kernels", "tracking_kernels", "weather_kernels")
    mods = {n: sys.modules["usvtool.sim." + n] for n in names if "usvtool.sim." + n in sys.modules}
    print(json.dumps({n: rollout_kernels.loaded(m) for n, m in mods.items()}))

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
    """The kernels' signatures are loaded at their first calls (rollout_kernels.declared), not at
    import: a DWA run loads its step's few, not the period sweep's callees (compiled into it) nor
    vo's; one specialisation each."""
    scenario = yaml.safe_load((charts / "scenarios" / "emergency-head-on.yaml").read_text())
    scenario["sim"]["duration"] = 1.0
    path = tmp_path / "short.yaml"
    path.write_text(yaml.safe_dump(scenario))
    out = subprocess.run([sys.executable, "-c", KERNELS, "simulate", str(path), "--controller",
                          controller, "-o", str(tmp_path / "t.csv")], capture_output=True,
                         text=True, check=True, cwd=tmp_path)  # fmt: skip
    loaded = yaml.safe_load(out.stdout.strip().splitlines()[-1])
    assert loaded["tracking_kernels"] == {"track_urgent": 1, "first_touching": 1}
    assert set(loaded["rollout_kernels"]) >= rollouts
    assert set(loaded["rollout_kernels"]) <= rollouts | {"favour", "offsets", "wrap_angles"}
    assert set(loaded["rollout_kernels"].values()) <= {1}
    assert not loaded.get("weather_kernels")
