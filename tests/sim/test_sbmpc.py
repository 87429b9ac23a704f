"""``sbmpc`` (Johansen, Perez and Cristofaro 2016): its behaviour set, a hazard computed by
hand, its choices in the COLREGS encounters, the grounding term on a grid, and runs of the
bundled scenarios and a few scenes of the emergency and imazu families."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from affine import Affine

from usvtool.clearance import Clearance
from usvtool.grid import Grid
from usvtool.sim import vessel as vessel_model
from usvtool.sim.controllers import CONTROLLERS, Own, Targets, World
from usvtool.sim.controllers.sbmpc import SBMPC, behaviours

NORTH = math.pi / 2
EAST = 0.0
SCENARIOS = Path(__file__).resolve().parents[2] / "charts" / "scenarios"


def controller(clearance=None, goal=(0.0, 2000.0), **params) -> SBMPC:
    c = SBMPC(**params)
    c.reset(World(vessel_model.preset("udwa-usv"), np.array(goal, float), clearance,
                  period=0.1))  # fmt: skip
    return c


def ships(*rows) -> Targets:
    """Targets from (x, y, course in math rad, speed, length) rows."""
    a = np.array(rows, float).reshape(-1, 5)
    vel = np.c_[np.cos(a[:, 2]), np.sin(a[:, 2])] * a[:, 3:4]
    return Targets(a[:, :2].copy(), vel, a[:, 4].copy())


def index(chi_deg: float, prop: float) -> int:
    chi, p = behaviours()
    return int(np.flatnonzero((np.isclose(np.degrees(chi), chi_deg)) & (p == prop))[0])


def chosen(c: SBMPC) -> tuple[float, float]:
    return float(np.degrees(c.chi[c.held])), float(c.prop[c.held])


def test_the_behaviour_set_is_the_papers():
    """13 course offsets, -90 to +90 deg in steps of 15, times the four propulsion commands
    nominal, slow forward (1/2), stop (0) and full reverse (-1): 52 behaviours."""
    chi, prop = behaviours()
    assert chi.size == prop.size == 52
    assert sorted(set(np.round(np.degrees(chi)).astype(int))) == list(range(-90, 91, 15))
    assert sorted(set(prop)) == [-1.0, 0.0, 0.5, 1.0]
    pairs = {(round(math.degrees(a)), b) for a, b in zip(chi, prop, strict=True)}
    assert len(pairs) == 52
    assert "sbmpc" in CONTROLLERS


def test_hazard_of_two_behaviours_by_hand():
    """Own ship east at her nominal 7 m/s... here 2 m/s (speed=2), a ship at rest 20 m ahead.
    Holding course (0 deg, P = 1) meets it at t = 10 s: the collision term at the contact,
    with the distance floor, dominates (> 1e20). Stopping (0 deg, P = 0, deceleration 2
    m/s^2): the speed falls to 1 m/s at 0.5 s and to 0 at 1 s, the positions (mid-step speeds
    1.5 and 0.5 m/s over 0.5 s) 0.75 m and 1.0 m. Only t = 0.5 s has a relative speed:
    C = 1 * 1^2, R = 0.5^-0.5 (30 / 19.25)^4 = 8.342...; then f = 2.5 (1 - 0), g = 0.5 |0 - 1|
    from the held (0 deg, nominal): H = 8.3424 + 2.5 + 0.5."""
    c = controller(goal=(1000.0, 0.0), speed=2.0, d_safe=30.0, step=0.5)
    own = Own(0.0, 0.0, EAST, 2.0, 0.0)
    targets = ships((20.0, 0.0, 0.0, 0.0, 15.0))
    h = c.hazard(own, targets, 0.0)
    by_hand = 1.0 * 0.5 ** -0.5 * (30 / 19.25) ** 4 + 2.5 + 0.5
    assert h[index(0, 0.0)] == pytest.approx(by_hand, rel=1e-9)
    assert h[index(0, 1.0)] > 1e20
    assert h.argmin() != index(0, 1.0)


def test_head_on_turns_to_starboard():
    """A ship 300 m dead ahead on the reciprocal course: a starboard offset, at full speed."""
    c = controller()
    c.decide(Own(0.0, 0.0, NORTH, 7.0, 0.0), ships((0.0, 300.0, -NORTH, 5.0, 15.0)))
    chi, prop = chosen(c)
    assert chi > 0, (chi, prop)
    # the mirror image, a port offset, carries the COLREGS violation cost kappa
    h = c.last_hazard
    assert h[index(-chi, prop)] >= h[index(chi, prop)] + c.params["kappa"] - 0.5


def test_give_way_crossing_goes_to_starboard_or_slows():
    """A ship from starboard on a collision course (both reach (0, 140) after 20 s): the
    give-way ship turns to starboard or slows, never to port."""
    c = controller()
    c.decide(Own(0.0, 0.0, NORTH, 7.0, 0.0), ships((100.0, 140.0, math.pi, 5.0, 15.0)))
    chi, prop = chosen(c)
    assert chi >= 0 and (chi > 0 or prop < 1), (chi, prop)


def test_stand_on_keeps_course_and_speed_while_safe():
    """A ship from port that passes 100 m ahead (beyond d_safe, 60 m): hold course and speed."""
    c = controller()
    own = Own(0.0, 0.0, NORTH, 7.0, 0.0)
    # she is at (-60, 240) heading east at 5 m/s: at x = 0 after 12 s, when the own ship is
    # at y = 84, 156 m astern of her
    for _ in range(30):
        c.decide(own, ships((-60.0, 240.0, EAST, 5.0, 15.0)))
        assert chosen(c) == (0.0, 1.0)


def test_stand_on_close_crossing_from_port_does_not_turn_to_port():
    """The same ship close and on a collision course: whatever she does, not a port turn
    (Rule 17(c), the transitional cost)."""
    c = controller()
    c.decide(Own(0.0, 0.0, NORTH, 7.0, 0.0), ships((-100.0, 140.0, EAST, 5.0, 15.0)))
    chi, _ = chosen(c)
    assert chi >= 0


def test_grounding_refuses_a_turn_toward_land():
    """Land from 25 m to starboard, a ship head-on: every starboard offset of 45 deg or more
    reaches the land within the grounding horizon and carries the hull cost; the choice is
    not one of them (in open water the same encounter turns to starboard)."""
    cells = np.zeros((400, 200), np.uint8)
    cells[:, 125:] = 1  # land from x = 25 m
    field = Clearance(Grid(cells, Affine(1, 0, -100, 0, -1, 350)))
    c = controller(clearance=field)
    own = Own(0.0, 0.0, NORTH, 7.0, 0.0)
    targets = ships((0.0, 300.0, -NORTH, 5.0, 15.0))
    c.decide(own, targets)
    h = c.last_hazard
    for chi in (45, 60, 75, 90):
        assert h[index(chi, 1.0)] >= c.params["hull_cost"]
    x, y, _, _, v = c.predict(own, NORTH)
    assert c.grounding(x, y, v)[index(0, 0.0)] == 0.0  # stopping, she stays clear of it
    assert h[c.held] < c.params["hull_cost"]
    chi, prop = chosen(c)
    assert not (chi >= 45 and prop > 0)


def test_a_behaviour_is_held_until_the_next_evaluation():
    """update 1 s at a 0.1 s period: evaluated at the 1st and 11th calls, held between."""
    c = controller()
    own = Own(0.0, 0.0, NORTH, 7.0, 0.0)
    seen = []
    for _ in range(21):
        c.decide(own, ships((0.0, 300.0, -NORTH, 5.0, 15.0)))
        seen.append(id(c.last_hazard))
    assert len(set(seen)) == 3
    assert seen[:10] == [seen[0]] * 10 and seen[10:20] == [seen[10]] * 10


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(p.stem for p in SCENARIOS.glob("*.yaml")))
def test_every_bundled_scenario_runs_without_collision(name):
    """Every bundled scenario to its end: no collision; those it does not arrive in are named
    (docs/controllers.md, "sbmpc": emergency-crossing, out of its 90 s)."""
    from usvtool.sim.run import SimOptions, simulate
    from usvtool.sim.scenario import read_scenario

    s = simulate(read_scenario(SCENARIOS / f"{name}.yaml"), SimOptions(controller="sbmpc"))
    figures = s.summary()
    assert not figures["collision"]
    assert figures["arrived"] == (name != "emergency-crossing")


def family_runs(name: str, scenes, tmp_path) -> dict[str, tuple[bool, bool, float]]:
    """(collided, arrived, closest distance) of sbmpc on each (kind, scene) of a family."""
    from usvtool.sim.families import make_scene, write_scene
    from usvtool.sim.run import SimOptions, simulate
    from usvtool.sim.scenario import read_scenario

    out = {}
    for kind, n in scenes:
        scene = make_scene(name, kind, n)
        path = write_scene(scene, tmp_path / f"{name}-{kind}-{n}.yaml")[0]
        figures = simulate(read_scenario(path), SimOptions(controller="sbmpc")).summary()
        out[f"{kind}/{n}"] = (bool(figures["collision"]), bool(figures["arrived"]),
                              figures["closest_distance_m"])  # fmt: skip
    return out


@pytest.mark.slow
def test_emergency_family_scenes(tmp_path):
    """Two seeded scenes of each emergency kind (docs/controllers.md, "sbmpc", records the
    outcomes): none collides."""
    runs = family_runs("emergency", [(k, n) for k in ("head-on", "crossing", "overtaking")
                                     for n in range(2)], tmp_path)  # fmt: skip
    assert not [k for k, (hit, _, _) in runs.items() if hit], runs


@pytest.mark.slow
def test_imazu_cases(tmp_path):
    """The 22 Imazu cases (docs/controllers.md, "sbmpc", records the outcomes)."""
    from usvtool.sim.families import FAMILIES

    runs = family_runs("imazu", [(k, 0) for k in FAMILIES["imazu"].kinds], tmp_path)
    collided = sorted(k for k, (hit, _, _) in runs.items() if hit)
    assert collided == IMAZU_COLLISIONS, runs


#: The Imazu cases where sbmpc collides (docs/controllers.md, "sbmpc").
IMAZU_COLLISIONS: list[str] = []
