"""The ``policy`` controller (usvtool/sim/controllers/policy.py, docs/gym.md): a policy trained
in the environment evaluated as a controller, through usvtool simulate; its run is the episode
the environment gives the same policy; it needs no gymnasium."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from usvtool.sim.controllers.policy import SHIPPED, NetworkPolicy
from usvtool.sim.observation import Layout, command
from usvtool.trace import format_trace

ROOT = Path(__file__).resolve().parents[2]
SCENARIOS = ROOT / "charts" / "scenarios"


def homing(path: Path) -> Path:
    """A linear policy by hand: nearly full speed, the yaw rate toward the goal (feature 3 is
    the sine of the goal's bearing, positive to port)."""
    layout = Layout()
    w = np.zeros((2, layout.size))
    w[1, 3] = 3.0
    np.savez(path, layout=np.array(json.dumps(layout.to_dict())), W0=w, b0=np.array([3.0, 0.0]))
    return path


def test_the_shipped_policy_is_small_and_loads():
    assert SHIPPED.is_file() and SHIPPED.stat().st_size < 8000
    policy = NetworkPolicy(SHIPPED)
    assert policy.layout == Layout() and len(policy.weights) == 1


def test_the_policy_controller_runs_through_usvtool_simulate(usv, tmp_path):
    npz = homing(tmp_path / "homing.npz")
    for params in ([], ["--param", f"policy={npz}"]):
        r = usv("simulate", SCENARIOS / "env1-head-on.yaml", "--controller", "policy", *params,
                "-o", tmp_path / "t.csv")  # fmt: skip
        assert r.exit_code == 0, r.output
        summary = json.loads(r.stdout)
        assert summary["controller"] == "policy" and summary["controller_failed"] is None
        assert summary["parameters"] == {"policy": str(npz) if params else "shipped"}
    (tmp_path / "open.yaml").write_text(  # open water, the goal astern: the homing turns back
        "name: open\nown: {start: [0, 0], goal: [30, -60], heading: 0, speed: 2}\n",
        encoding="utf-8")  # fmt: skip
    r = usv("simulate", tmp_path / "open.yaml", "--controller", "policy", "--param",
            f"policy={npz}", "-o", tmp_path / "t.csv")  # fmt: skip
    assert r.exit_code == 0 and json.loads(r.stdout)["arrived"], r.output


@pytest.mark.slow
def test_a_policy_run_is_the_environment_episode_under_that_policy(usv, tmp_path):
    """The environment stepped with the policy's commands on its observations, and usvtool
    simulate --controller policy, write the same trace: the controller sees what the agent saw."""
    gymnasium = pytest.importorskip("gymnasium")
    from usvtool.gym import ENV_ID

    npz = homing(tmp_path / "homing.npz")
    policy = NetworkPolicy(npz)
    env = gymnasium.make(ENV_ID, family="emergency", kind="crossing")
    base = env.unwrapped
    obs, _ = env.reset(seed=11, options={"scene": 4})
    done = False
    while not done:
        v, omega = NetworkPolicy.command(base.voyage.vessel, policy(obs))
        obs, _, terminated, truncated, _ = env.step([v, omega])
        done = terminated or truncated
    r = usv("simulate", "--family", "emergency", "--kind", "crossing", "--scene", 4,
            "--scenario-out", tmp_path / "s.yaml", "--controller", "policy", "--param",
            f"policy={npz}", "--seed", base.voyage_seed, "-o", tmp_path / "t.csv")  # fmt: skip
    assert r.exit_code == 0, r.output
    assert format_trace(base.voyage.trace()) == (tmp_path / "t.csv").read_text(encoding="utf-8")
    env.close()


CALLABLES = '''
import math

def steady(obs):
    return 2.0, 0.0

def broken(obs):
    return math.nan, 0.0

def raising(obs):
    raise RuntimeError("no")

steady.observation_layout = {"version": 1, "targets": 1, "time_scale": 30.0,
                             "clearance_scale": 10.0, "probe_time": 5.0}
'''


def test_a_callable_policy_and_its_failures(usv, tmp_path, monkeypatch):
    (tmp_path / "mypolicies.py").write_text(CALLABLES, encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))

    def run(spec: str):
        r = usv("simulate", SCENARIOS / "env1-head-on.yaml", "--controller", "policy", "--param",
                f"policy={spec}", "-o", tmp_path / "t.csv")  # fmt: skip
        return r, (json.loads(r.stdout) if r.exit_code == 0 else None)

    r, summary = run("mypolicies:steady")
    assert r.exit_code == 0 and summary["controller_failed"] is None
    for spec, why in (("mypolicies:broken", "not finite"), ("mypolicies:raising", "RuntimeError")):
        r, summary = run(spec)
        assert r.exit_code == 0, r.output
        assert summary["controller_failed"].startswith("step 0 ") and why in \
            summary["controller_failed"]  # fmt: skip
        assert not summary["arrived"]
    bad = tmp_path / "bad.npz"
    np.savez(bad, W0=np.zeros((2, 3)))
    for spec, line in (("nowhere.npz", "nowhere.npz: no such file"),
                       ("mypolicies", "a .npz file or module:callable"),
                       ("mypolicies:absent", "cannot be loaded: AttributeError"),
                       ("no_such_module_here:f", "cannot be loaded: ModuleNotFoundError"),
                       (str(bad), "no 'layout'")):  # fmt: skip
        r, _ = run(spec)
        assert r.exit_code == 1 and line in r.output, (spec, r.output)


def test_the_command_is_clipped_into_one_periods_reach():
    from usvtool.sim.controllers import Own
    from usvtool.sim.vessel import preset, window

    ship = preset("iwso-dwa-usv")  # 0.7 m/s² up, 0.8 down, 75 deg/s² of yaw
    own = Own(0.0, 0.0, 0.0, 3.0, 0.0)
    v, omega = command(ship, own, 0.1, 10.0, -10.0)
    assert v == pytest.approx(3.07) and omega == pytest.approx(-np.radians(7.5))
    assert command(ship, own, 0.1, 3.01, 0.05) == (3.01, 0.05)  # inside: as given
    rng = np.random.default_rng(0)  # the bounds are vessel.window's, bit for bit
    for _ in range(500):
        now = Own(0.0, 0.0, 0.0, float(rng.uniform(0, 6)), float(rng.uniform(-1.2, 1.2)))
        w = window(ship, now.v, now.omega, 0.1)
        for v, omega in ((-1.0, -9.0), (9.0, 9.0)):
            assert command(ship, now, 0.1, v, omega) == ((w.v_lo, w.omega_lo) if v < 0
                                                         else (w.v_hi, w.omega_hi))


def test_usvtool_and_the_policy_controller_need_no_gymnasium(tmp_path):
    """With gymnasium made unimportable, usvtool's command line and the policy controller work
    (a run with the shipped policy) and usvtool.gym alone says it is missing."""
    code = f"""
import sys
sys.modules["gymnasium"] = None  # import gymnasium now raises ImportError
from usvtool.cli import cli
try:
    cli(["simulate", {str(SCENARIOS / "emergency-head-on.yaml")!r}, "--controller", "policy",
         "-o", {str(tmp_path / "t.csv")!r}])
except SystemExit as exc:
    assert exc.code in (0, None), exc.code
assert "usvtool.gym" not in sys.modules
try:
    import usvtool.gym
except ImportError:
    print("no gymnasium")
"""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                       timeout=300)  # fmt: skip
    assert r.returncode == 0, r.stderr
    out = r.stdout.strip()
    assert out.endswith("\nno gymnasium"), out
    assert json.loads(out[: -len("no gymnasium")])["controller"] == "policy"
