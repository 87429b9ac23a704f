"""Properties of whole runs on random two- and three-ship geometries (hypothesis), each checked
on the trace by an independent computation in the test."""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from usvtool.sim.run import SimOptions, simulate
from usvtool.sim.scenario import parse
from usvtool.trace import format_trace

pytestmark = pytest.mark.slow  # hypothesis runs of whole encounters

GOAL = (0.0, 160.0)
TOLERANCE = 5.0


def scenario(targets, controller="dwa", noise=0.0):
    return parse({
        "name": "random",
        "sim": {"dt": 0.1, "duration": 45, "goal_tolerance": TOLERANCE},
        "own": {"start": [0, 0], "goal": list(GOAL), "heading": 0, "speed": 4},
        "targets": [
            {"name": f"t{i}", "start": [x, y], "heading": h, "speed": v, "length": 2.5,
             "noise": {"heading_sd": noise, "speed_sd": noise / 10}}
            for i, (x, y, h, v) in enumerate(targets)
        ],
        "controller": {"name": controller},
    }, "random.yaml")  # fmt: skip


target = st.tuples(
    st.floats(-60, 60), st.floats(20, 150), st.floats(0, 359), st.floats(0.5, 4.0)
)


@settings(max_examples=16, deadline=None, suppress_health_check=[HealthCheck.too_slow],
          derandomize=True)  # fmt: skip
@given(st.lists(target, min_size=1, max_size=2),
       st.sampled_from(["dwa", "gdwa", "ccdwa", "udwa", "udwa+"]))
def test_the_summary_agrees_with_the_trace(targets, controller):
    result = simulate(scenario(targets, controller))
    s, tr = result.summary(), result.trace
    gap = np.hypot(tr.x[:, 1:] - tr.x[:, :1], tr.y[:, 1:] - tr.y[:, :1])  # centre distances
    touched = (gap < (2.5 + 2.5) / 2).any()
    if touched:
        assert s["collision"] is not None and not s["arrived"]
    names = list(tr.ships[1:])
    for event in result.events["encounters"]:  # each over its own span: onset to release
        j = event["target"]
        if event["onset_s"] is None:
            span = np.ones(len(tr.t), bool)
        else:
            end = tr.t[-1] if event["released_s"] is None else event["released_s"]
            span = (tr.t >= event["onset_s"] - 1e-9) & (tr.t <= end + 1e-9)
        assert math.isclose(event["closest_distance_m"], gap[span, j].min(), abs_tol=1e-3)
    for j, entry in enumerate(s["per_target"]):  # per target: over the whole run
        assert entry["target"] == names[j]
        assert math.isclose(entry["closest_distance_m"], gap[:, j].min(), abs_tol=1e-3)
    assert math.isclose(s["closest_distance_m"], gap.min(), abs_tol=1e-3)
    end = math.hypot(tr.x[-1, 0] - GOAL[0], tr.y[-1, 0] - GOAL[1])
    assert s["arrived"] == (end <= TOLERANCE)
    assert s["time_s"] == round(float(tr.t[-1]), 3)


def test_the_same_seed_gives_the_same_trace_bytes():
    noisy = scenario([(10, 80, 180, 2.0), (-40, 60, 90, 2.5)], "udwa", noise=5.0)
    first = format_trace(simulate(noisy, SimOptions(seed=7)).trace)
    assert format_trace(simulate(noisy, SimOptions(seed=7)).trace) == first
    assert format_trace(simulate(noisy, SimOptions(seed=8)).trace) != first
