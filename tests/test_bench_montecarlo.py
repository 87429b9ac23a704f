"""benchmarks/bench_montecarlo.py: its --peer loader runs a copy of PythonRobotics' DWA at that
file's own defaults and reports the ratio to ours; its family pipeline is families.yaml cut
down. The project does not carry PythonRobotics' file: a stand-in with its names does here."""

import math
import re

import pytest
import yaml

from usvtool.pipeline import load

STAND_IN = """
import time

import numpy as np

show_animation = True
calls = []


class Config:
    def __init__(self):
        self.dt = 0.1
        self.predict_time = 3.0
        self.ob = np.array([[-1.0, -1.0], [0.0, 2.0], [4.0, 2.0]])


def predict_trajectory(x_init, v, y, config):
    return np.zeros((31, 5))


def dwa_control(x, config, goal, ob):
    calls.append((x.copy(), goal.copy(), ob, show_animation))
    time.sleep(0.002)  # a step of some 2 ms, ten times ours or more
    for v in range(4):
        for y in range(5):
            predict_trajectory(x, v, y, config)
    return [0.0, 0.0], np.zeros((31, 5))


def main():
    raise SystemExit("main ran")


if __name__ == "__main__":
    main()
"""


def timer(ms: float):
    """A stand-in for bench_simulate.best_ms: calls the step once and says it took ``ms``."""

    def best_ms(fn, runs, calls):
        fn()
        return ms

    return best_ms


@pytest.fixture(scope="module")
def bench(benchmark):
    return benchmark("bench_montecarlo")


@pytest.fixture
def stand_in(tmp_path):
    path = tmp_path / "dynamic_window_approach.py"
    path.write_text(STAND_IN)
    return path


def test_the_peer_is_called_at_its_own_defaults_without_its_main(bench, stand_in):
    module = bench.load_peer(stand_in)  # its main() would exit: it is not run
    assert module.show_animation is False
    ms, samples, config = bench.peer_step(module, timer(12.5), 1)
    assert (ms, samples) == (12.5, 20)  # 4 x 5 rollouts counted through predict_trajectory
    assert module.predict_trajectory.__name__ == "predict_trajectory"  # the counter removed
    x, goal, ob, animated = module.calls[-1]
    assert x.tolist() == [0.0, 0.0, math.pi / 8, 0.0, 0.0] and goal.tolist() == [10.0, 10.0]
    assert ob is config.ob and not animated


def test_the_peer_line_gives_its_step_and_the_ratio_to_ours(bench, stand_in, capsys):
    bench.peer(stand_in, 1)
    out = capsys.readouterr().out
    theirs = float(re.search(r"20 samples, 3.0 s at 0.1 s, 3 obstacles: ([\d.]+) ms", out)[1])
    ratios = re.findall(r"ours, dwa at (.+?) \((\d+) samples.*: ([\d.]+) ms a step; theirs / ours "
                        r"= ([\d.]+)", out)  # fmt: skip
    assert [r[0] for r in ratios] == ["3 s at 0.1 s", "defaults, 10 s at 0.2 s"]
    assert theirs >= 2.0
    for _, samples, ours, ratio in ratios:
        assert int(samples) > 400 and float(ours) > 0
        # the ratio is printed to 0.1 (half a unit: 0.05), ours to 1 us, theirs to 10 us: the
        # printed ratio lies within those roundings of the printed figures' quotient
        expected = theirs / float(ours)
        slack = 0.05 + expected * (0.005 / theirs + 0.0005 / float(ours)) + 1e-9
        assert abs(float(ratio) - expected) <= slack, (ratio, expected, slack)


def test_without_a_peer_one_line_says_it_is_skipped(bench, capsys):
    bench.peer(None, 1)
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == 1 and "skipped" in lines[0] and "--peer FILE" in lines[0]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (None, "no such file"),
        ("x = 1\n", "has no dwa_control nor Config"),
        ("import no_such_module_here\n", "does not import (ModuleNotFoundError"),
        (STAND_IN.replace("self.ob", "self.obstacles"), "its Config has no ob"),
    ],
)
def test_a_file_that_is_not_the_peer_is_one_line(bench, tmp_path, text, message):
    path = tmp_path / "dwa.py"
    if text is not None:
        path.write_text(text)
    with pytest.raises(SystemExit) as exc:
        bench.peer_step(bench.load_peer(path), timer(1.0), 1)
    assert message in str(exc.value) and "\n" not in str(exc.value)


def test_the_family_pipeline_is_families_yaml_with_fewer_scenes(bench, tmp_path):
    full = yaml.safe_load(bench.FAMILIES.read_text())["families"]
    cut = yaml.safe_load(bench.family_pipeline(2))
    assert [e["family"] for e in cut["families"]] == [e["family"] for e in full]
    for entry, original in zip(cut["families"], full, strict=True):
        expected = {"first": 0, "count": 2} if "scenes" in original else None
        assert entry.get("scenes") == expected
        assert entry["controllers"] == original["controllers"]
    path = tmp_path / "families.yaml"
    path.write_text(bench.family_pipeline(2))
    from usvtool.cli.batch import stage_names

    pipeline = load(path, stage_names())
    # 2 scenes of 3 emergency kinds, 5 IWSO kinds and the wind's halves, the 22 Imazu cases
    counts = {e.family: len(e.kinds) * len(e.scenes) for e in pipeline.families}
    assert counts == {"emergency": 6, "iwso": 10, "imazu": 22, "wind": 2}
    assert len(pipeline.family_jobs()) == 40 * 5
