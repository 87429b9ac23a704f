"""A Voyage built with usvtool.sim.run.start_voyage and stepped by hand is the run simulate
makes: the same trace, bit for bit, when it is steered by the same controller."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from usvtool.sim.controllers import make_controller
from usvtool.sim.run import SimOptions, simulate, start_voyage
from usvtool.sim.scenario import read_scenario

SCENARIOS = Path(__file__).resolve().parents[2] / "charts" / "scenarios"


def test_a_voyage_stepped_by_hand_is_simulates_run():
    scenario = read_scenario(SCENARIOS / "emergency-crossing.yaml")
    voyage = start_voyage(scenario, seed=3)
    controller = make_controller("udwa")
    controller.reset(voyage.world)
    while not voyage.over:
        decision = controller.decide(*voyage.observe())
        voyage.advance(decision.v, decision.omega, decision.events)
    mine = voyage.trace()
    theirs = simulate(scenario, SimOptions(seed=3)).trace
    assert mine.ships == theirs.ships and voyage.step == len(theirs.t) - 1
    for name in ("t", "x", "y", "heading", "speed", "yaw_rate"):
        assert np.array_equal(getattr(mine, name), getattr(theirs, name)), name
