"""usvtool.gym's environment (docs/gym.md): gymnasium's own checks, truncation at the duration,
the same world as usvtool simulate's (driven by a controller's decisions, its trace is the
simulator's byte for byte), arrival and collision with their rewards, the same seed's same
episode."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

gymnasium = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

from usvtool.encounter import domain_semi_axes  # noqa: E402
from usvtool.gym import ENV_ID, Reward, UsvEnv  # noqa: E402
from usvtool.sim.controllers import make_controller  # noqa: E402
from usvtool.trace import format_trace, read_events  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SCENARIOS = ROOT / "charts" / "scenarios"


def scenario_file(tmp_path: Path, name: str, own: dict, targets=(), sim=None) -> Path:
    path = tmp_path / f"{name}.yaml"
    data = {"name": name, "sim": sim or {"dt": 0.1, "duration": 60, "goal_tolerance": 5},
            "own": own}  # fmt: skip
    if targets:
        data["targets"] = list(targets)
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path


# gymnasium recommends a [-1, 1] action box; ours is the vessel's (v, omega) (docs/gym.md)
@pytest.mark.filterwarnings("ignore:.*symmetric and normalized space")
@pytest.mark.parametrize("kwargs", [
    {"family": "imazu", "kind": "13"},
    {"family": "iwso", "kind": "static", "scenes": 3},  # a map
    {"scenario": [SCENARIOS / "emergency-head-on.yaml", SCENARIOS / "env1-head-on.yaml"]},
], ids=["imazu-13", "iwso-static", "two-files"])  # fmt: skip
def test_gymnasium_check_env_passes(kwargs):
    env = gymnasium.make(ENV_ID, **kwargs)
    check_env(env.unwrapped)
    env.close()


def test_the_environment_is_registered_and_its_spaces_are_the_vessels():
    env = gymnasium.make(ENV_ID, family="emergency", kind="head-on")
    assert env.spec.id == "usvtool/Encounter-v0"
    space = env.action_space  # udwa-usv: 0-7 m/s, ±20 deg/s
    assert space.dtype == np.float64
    assert space.low.tolist() == [0.0, -math.radians(20)]
    assert space.high.tolist() == [7.0, math.radians(20)]
    assert env.observation_space.shape == (38,) and env.observation_space.dtype == np.float32
    obs, info = env.reset(seed=0)
    assert env.observation_space.contains(obs)
    assert info["time"] == 0.0 and info["encounter"] == "head-on"  # the family's promise
    assert info["nearest_m"] > 0
    env.close()


def test_a_constant_action_is_truncated_at_the_scenarios_duration(tmp_path):
    """12.3 s in steps of 0.1 s: 123 steps, circling at 1 m/s and 60 deg/s (a 0.95 m radius)
    100 m from the goal, so that neither arrival nor collision ends it."""
    path = scenario_file(tmp_path, "circle", {"start": [0, 0], "goal": [0, 100], "speed": 1},
                         sim={"dt": 0.1, "duration": 12.3, "goal_tolerance": 5})  # fmt: skip
    env = UsvEnv(path)
    env.reset(seed=1)
    steps, done = 0, False
    while not done:
        obs, reward, terminated, truncated, info = env.step([1.0, math.radians(60)])
        steps += 1
        done = terminated or truncated
    assert steps == 123 and truncated and not terminated
    assert info["time"] == pytest.approx(12.3) and info["arrived"] is False
    assert info["collision"] is None
    with pytest.raises(Exception, match="over"):
        env.step([1.0, 0.0])


def drive(env, controller: str, **reset):
    """An episode of ``env`` whose actions are ``controller``'s decisions on the voyage's view
    (what simulate hands it); the last info."""
    base = env.unwrapped
    env.reset(**reset)
    control = make_controller(controller)
    control.reset(base.voyage.world)
    done = False
    while not done:
        decision = control.decide(*base.view)
        *_, terminated, truncated, info = env.step([decision.v, decision.omega])
        done = terminated or truncated
    control.close()
    return info


@pytest.mark.slow
@pytest.mark.parametrize("case", [
    ("emergency-crossing.yaml", "udwa"),
    ("env1-static.yaml", "gdwa"),  # a map and a route
    ("emergency-head-on.yaml", "dwa"),  # no Rule 2 records: the verdicts compared too
    ("family", "gdwa"),
], ids=lambda c: "-".join(c))  # fmt: skip
def test_driven_by_a_controller_the_episode_is_simulates_run(usv, tmp_path, case):
    """The environment and usvtool simulate share the voyage: an episode whose actions are a
    built-in controller's decisions (its decide() on the episode's view, each inside the
    window, which the clip leaves as it is) writes simulate's trace CSV byte for byte."""
    name, controller = case
    if name == "family":
        env = UsvEnv(family="iwso", kind="crossing-port")
        info = drive(env, controller, seed=5, options={"scene": 3})
        args = ["--family", "iwso", "--kind", "crossing-port", "--scene", "3",
                "--scenario-out", tmp_path / "s.yaml"]  # fmt: skip
    else:
        env = UsvEnv(SCENARIOS / name)
        info = drive(env, controller, seed=5)
        args = [SCENARIOS / name]
    seed = env.voyage_seed
    r = usv("simulate", *args, "--controller", controller, "--seed", seed, "-o",
            tmp_path / "t.csv", "--events", tmp_path / "t.json")  # fmt: skip
    assert r.exit_code == 0, r.output
    summary = json.loads(r.stdout)
    assert format_trace(env.voyage.trace()) == (tmp_path / "t.csv").read_text(encoding="utf-8")
    assert info["arrived"] == summary["arrived"] and info["collision"] == summary["collision"]
    if controller == "dwa":
        judged = [e["compliant"] for e in read_events(tmp_path / "t.json")["encounters"]
                  if e["compliant"] is not None]  # fmt: skip
        assert info["verdicts"] == {"judged": len(judged), "compliant": sum(judged),
                                    "non_compliant": len(judged) - sum(judged)}  # fmt: skip
    env.close()


def straight_run(env, v: float) -> list:
    """Steps at ``v`` straight on until the episode ends: (reward, terminated, truncated,
    info) of each."""
    env.reset(seed=0)
    out = []
    while not out or not (out[-1][1] or out[-1][2]):
        _, reward, terminated, truncated, info = env.step([v, 0.0])
        out.append((reward, terminated, truncated, info))
    return out


def test_arrival_terminates_with_the_arrival_bonus(tmp_path):
    """North at 2 m/s from (0, 0) to (0, 20), tolerance 5: 0.2 m a step, within 5 m after 75
    or 76 steps (where the floats put 15 m); progress sums to (20 - d) / 20, the last step's
    reward is its progress plus the bonus; nothing else earns or costs."""
    path = scenario_file(tmp_path, "arrive", {"start": [0, 0], "goal": [0, 20], "speed": 2})
    env = UsvEnv(path, reward=Reward(arrival=3.0))
    steps = straight_run(env, 2.0)
    reward, terminated, truncated, info = steps[-1]
    assert terminated and not truncated and info["arrived"] and info["collision"] is None
    assert len(steps) in (75, 76)
    y = env.voyage.y
    assert 15.0 <= y < 15.2 + 1e-9
    assert info["reward"]["arrival"] == 3.0
    assert reward == pytest.approx((20 - (y - 0.2)) / 20 - (20 - y) / 20 + 3.0, abs=1e-12)
    total = sum(s[0] for s in steps)
    assert total == pytest.approx((20 - (20 - y)) / 20 + 3.0, abs=1e-9)


def test_collision_terminates_with_the_collision_penalty(tmp_path):
    """A target stopped 10 m ahead on the own ship's path (both 2.5 m): contact once the
    centres are closer than 2.5 m, at y > 7.5, 0.2 m a step: the 38th step (7.6 m). The last
    reward is its progress, its domain cost (the target 2.4 m ahead: q = (2.4 / 8.75)^2), and
    the penalty; the verdict term is switched off here (its own test is the controller's)."""
    own = {"start": [0, 0], "goal": [0, 100], "speed": 2}
    target = {"name": "buoy", "start": [0, 10], "heading": 0, "speed": 0, "length": 2.5}
    path = scenario_file(tmp_path, "hit", own, [target])
    weights = Reward(collision=5.0, verdict=0.0, colregs=0.0)
    env = UsvEnv(path, reward=weights)
    steps = straight_run(env, 2.0)
    reward, terminated, truncated, info = steps[-1]
    assert terminated and not truncated and info["collision"] == "buoy"
    assert len(steps) == 38 and env.voyage.y == pytest.approx(7.6)
    gap = 10 - env.voyage.y
    along, _ = domain_semi_axes(2.5)
    domain = -weights.domain * 0.1 * (1 - gap / along)
    assert info["reward"]["domain"] == pytest.approx(domain)
    assert info["reward"]["collision"] == -5.0
    assert reward == pytest.approx(0.2 / 100 + domain - 5.0)


def test_the_same_seed_gives_the_same_episode_bit_for_bit():
    def episode(seed: int) -> tuple[np.ndarray, list]:
        env = UsvEnv(family="emergency", scenes=20)
        actions = np.random.default_rng(0)
        obs, _ = env.reset(seed=seed)
        seen, rewards = [obs], []
        for _ in range(400):
            a = env.action_space.low + actions.random(2) * (env.action_space.high -
                                                            env.action_space.low)  # fmt: skip
            obs, reward, terminated, truncated, _ = env.step(a)
            seen.append(obs)
            rewards.append(reward)
            if terminated or truncated:
                obs, _ = env.reset()  # the next episode, from the same generator
                seen.append(obs)
        env.close()
        return np.stack(seen), rewards

    a, ra = episode(7)
    b, rb = episode(7)
    assert a.tobytes() == b.tobytes() and ra == rb
    c, _ = episode(8)
    assert c.shape != a.shape or c.tobytes() != a.tobytes()


def test_reset_options_and_bad_actions(tmp_path):
    env = UsvEnv(family="imazu", kind=["01", "02"])
    _, info = env.reset(seed=3, options={"kind": "02", "scene": 0})
    assert info["scenario"] == "imazu-02-s000"
    with pytest.raises(ValueError, match="two finite numbers"):
        env.step([float("nan"), 0.0])
    with pytest.raises(Exception, match="unknown option"):
        env.reset(options={"sceen": 1})
    with pytest.raises(Exception, match="no kind"):
        UsvEnv(family="imazu", kind="23")
    with pytest.raises(Exception, match="a scenario file"):
        UsvEnv()


def test_the_example_of_docs_gym_runs(capsys):
    import re

    text = (ROOT / "docs" / "gym.md").read_text(encoding="utf-8")
    (block,) = re.findall(r"^```python\n(.*?)^```", text, re.S | re.M)
    exec(compile(block, "docs/gym.md", "exec"), {})
    time_s, arrived, collision, *_ = capsys.readouterr().out.split()
    assert float(time_s) > 0 and arrived in ("True", "False")
