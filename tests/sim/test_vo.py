"""The ``vo`` controller (Kuwata et al. 2014) against hand-computed velocity obstacles, COLREGs
constraints, hysteresis and grounding, and in short closed-loop encounters."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from affine import Affine

from usvtool.clearance import Clearance
from usvtool.encounter import CROSSING_GIVE_WAY, HEAD_ON, OVERTAKING, assess
from usvtool.grid import Grid
from usvtool.sim.controllers import Own, Targets, World, make_controller
from usvtool.sim.controllers.vo import first_contact, passes_to_port
from usvtool.sim.families import make_scene
from usvtool.sim.run import SimOptions, simulate
from usvtool.sim.scenario import parse, read_scenario
from usvtool.sim.vessel import preset

SHIP = preset("udwa-usv")  # 15 m, 7 m/s, 20 deg/s, 5 deg/s²
NORTH = math.pi / 2


def controller(world: World | None = None, **params):
    c = make_controller("vo", **params)
    c.reset(world or World(SHIP, np.array([0.0, 2000.0])))
    return c


def targets(*ships) -> Targets:
    """Targets from (x, y, vx, vy) rows, 15 m long."""
    rows = np.array(ships, float).reshape(-1, 4)
    return Targets(rows[:, :2].copy(), rows[:, 2:].copy(), np.full(len(rows), 15.0))


def at(speed: float, deg: float) -> np.ndarray:
    return speed * np.array([math.cos(math.radians(deg)), math.sin(math.radians(deg))])


# -- the velocity obstacle (eqs. 1-2), by hand ----------------------------------------------


def test_a_velocity_inside_the_cone_is_refused_and_one_outside_allowed():
    """A still target 100 m east, a combined radius of 10 m: the cone's half angle is
    asin(10 / 100) = 5.739 deg. At 5 m/s, 5 deg is inside (the ray meets the disc), 7 deg
    outside; dead ahead the contact is at (100 - 10) / 5 = 18 s."""
    p = np.array([[100.0, 0.0]])
    w = np.stack([at(5, 0), at(5, 5), at(5, 7), at(5, -5), at(5, -7)])[:, None, :]
    t = first_contact(p, w, np.array([10.0]), 0.0, 60.0)[:, 0]
    assert t[0] == pytest.approx(18.0)
    assert np.isfinite(t).tolist() == [True, True, False, True, False]


def test_the_cone_is_shifted_by_the_targets_velocity():
    """The same target moving north at 3 m/s: own (5, 3) is relative (5, 0), inside; own (5, 0)
    is relative (5, -3), 31 deg off the line of sight, outside."""
    c = controller(margin=0.0, uncertainty=0.0)
    own = Own(0.0, 0.0, 0.0, 5.0, 0.0)
    tg = Targets(np.array([[100.0, 0.0]]), np.array([[0.0, 3.0]]), np.array([5.0]))  # 10 m radius
    contact, _ = c.obstacles(own, tg, np.array([5.0, 5.0]), np.array([3.0, 0.0]))
    assert contact[0] == pytest.approx(18.0) and contact[1] == np.inf


def test_the_horizon_cuts_the_cone():
    """Dead ahead at 0.5 m/s the contact is at 180 s, beyond a 30 s horizon: not barred."""
    p = np.array([[100.0, 0.0]])
    w = np.array([[at(0.5, 0)], [at(5.0, 0)]])
    t = first_contact(p, w, np.array([10.0]), 0.0, 30.0)[:, 0]
    assert t[0] == np.inf and t[1] == pytest.approx(18.0)


def test_the_worst_case_cone_grows_by_the_velocity_uncertainty():
    """5 m/s at 7 deg lies |v| sin(7 - 5.739 deg) = 0.110 m/s outside the cone's edge: a target
    speed known to 0.2 m/s puts it inside, to 0.05 m/s not."""
    p = np.array([[100.0, 0.0]])
    w = at(5, 7)[None, None, :]
    gap = 5 * math.sin(math.radians(7) - math.asin(0.1))
    assert gap == pytest.approx(0.110, abs=1e-3)
    assert np.isfinite(first_contact(p, w, np.array([10.0]), 0.2, 600.0)[0, 0])
    assert not np.isfinite(first_contact(p, w, np.array([10.0]), 0.05, 600.0)[0, 0])


def test_region_v3_is_passing_with_the_target_to_starboard():
    """A target dead ahead (north): a relative velocity to the right of the line of sight
    passes her on the own ship's port side (allowed), one to the left on her starboard side (V3,
    refused in a COLREGs mode); one moving away (V2) is never V3."""
    p = np.array([[0.0, 100.0]])
    w = np.array([[[2.0, 10.0]], [[-2.0, 10.0]], [[-2.0, -10.0]], [[2.0, -1.0]]])
    assert passes_to_port(p, w)[:, 0].tolist() == [False, True, False, False]


# -- the COLREGs modes and the hysteresis ---------------------------------------------------


def test_head_on_turns_to_starboard():
    """Reciprocal courses 250 m apart at 5 m/s each (a contact at (250 - 30) / 10 = 22 s,
    within the 30 s horizon): the VO bars the course ahead and V3 the port side of it; the
    command turns to starboard (a negative yaw rate)."""
    c = controller()
    own = Own(0.0, 0.0, NORTH, 5.0, 0.0)
    d = c.decide(own, targets((0.0, 250.0, 0.0, -5.0)))
    assert d.omega < 0
    assert c.mode(0) == 1  # head-on held


def closed_loop(c: make_controller, own: Own, ships: Targets, seconds: float, dt: float = 0.1):
    """The own ship's positions and every target's along a run of ``seconds`` (the controller's
    (v, omega) integrated exactly enough at ``dt``; the targets on straight lines)."""
    x, y, psi, v, omega = own.x, own.y, own.psi, own.v, own.omega
    pos, vel = ships.pos.copy(), ships.vel
    track, others = [], []
    for _ in range(int(round(seconds / dt))):
        d = c.decide(Own(x, y, psi, v, omega), Targets(pos.copy(), vel, ships.length))
        v, omega = d.v, d.omega
        psi += omega * dt
        x += v * math.cos(psi) * dt
        y += v * math.sin(psi) * dt
        pos = pos + vel * dt
        track.append((x, y))
        others.append(pos.copy())
    return np.array(track), np.array(others)


def test_a_crossing_from_starboard_passes_astern():
    """Give-way: a target 200 m east and 200 m north heading west at 5 m/s, both at the
    crossing point (0, 200) at 40 s. The own ship crosses the target's track (y = 200) only once
    the target is west of her (astern of it), and keeps clear of the 15 m + 15 m margin."""
    c = controller(World(SHIP, np.array([0.0, 600.0]), period=0.1))
    own = Own(0.0, 0.0, NORTH, 5.0, 0.0)
    track, others = closed_loop(c, own, targets((200.0, 200.0, -5.0, 0.0)), 90.0)
    cross = int(np.argmax(track[:, 1] >= 200.0))
    assert track[cross, 1] >= 200.0
    assert others[cross, 0, 0] < track[cross, 0]  # the target is already past, to the west
    gap = np.hypot(*(track - others[:, 0]).T).min()
    assert gap > 15.0 + 15.0


def test_overtaking_passes_with_clearance():
    """A slower target 150 m ahead on the same course (2 m/s against 6): the own ship passes
    her without coming within the two half lengths plus the margin less 10 %."""
    c = controller(World(SHIP, np.array([0.0, 900.0]), period=0.1))
    own = Own(0.0, 0.0, NORTH, 6.0, 0.0)
    track, others = closed_loop(c, own, targets((0.0, 150.0, 0.0, 2.0)), 100.0)
    gap = np.hypot(*(track - others[:, 0]).T)
    assert gap.min() > 0.9 * 30.0
    assert track[-1, 1] > others[-1, 0, 1] + 30.0  # she is past


def test_the_hysteresis_holds_the_mode_for_its_time():
    """A head-on enters its mode at t = 0; once the target no longer meets the entry conditions
    (a d_CPA of 200 m, far beyond 4 lengths) the mode is held for ``hold`` = 10 s and then
    dropped."""
    c = controller(hold=10.0)
    own = Own(0.0, 0.0, NORTH, 5.0, 0.0)
    assert c.colregs(own, targets((0.0, 250.0, 0.0, -5.0))).tolist() == [True]
    clear = targets((200.0, 250.0, 0.0, -5.0))
    c.time = 9.9
    assert c.colregs(own, clear).tolist() == [True] and c.mode(0) == 1
    c.time = 10.1
    assert c.colregs(own, clear).tolist() == [False] and c.mode(0) is None


def test_the_modes_classes_are_those_of_usvtool_encounter():
    """The controller's own bearings (radians, the components) give the classes of
    :func:`usvtool.encounter.assess` for targets all round on near-collision courses."""
    rng = np.random.default_rng(5)
    own = Own(10.0, -20.0, 0.7, 5.0, 0.0)
    bearing = rng.uniform(-math.pi, math.pi, 200)
    pos = np.stack([own.x + 200 * np.cos(bearing), own.y + 200 * np.sin(bearing)], axis=1)
    course = rng.uniform(-math.pi, math.pi, 200)
    vel = 4.0 * np.stack([np.cos(course), np.sin(course)], axis=1)
    c = controller(colregs_distance=1e6, colregs_time=1e6, hold=0.0)
    tg = Targets(pos, vel, np.full(200, 15.0))
    c.colregs(own, tg)
    want = assess((own.x, own.y), (90 - math.degrees(own.psi)) % 360, own.v, pos,
                  (90 - np.degrees(course)) % 360, np.full(200, 4.0)).cls  # fmt: skip
    got = [c.mode(j) if c.mode(j) is not None else -1 for j in range(200)]
    constrained = np.isin(want, (HEAD_ON, CROSSING_GIVE_WAY, OVERTAKING))
    assert np.array_equal(np.where(constrained, want, -1), got)
    assert constrained.sum() > 30


def test_no_mode_for_the_stand_on_vessel():
    """A crossing from port (the own ship stands on): no COLREGs constraint, only the VO."""
    c = controller()
    own = Own(0.0, 0.0, NORTH, 5.0, 0.0)
    assert c.colregs(own, targets((-200.0, 200.0, 5.0, 0.0))).tolist() == [False]


# -- grounding --------------------------------------------------------------------------------


def test_on_a_grid_a_candidate_toward_land_is_refused():
    """Land from 40 m north of the own ship (a 1 m grid): at 5 m/s for 10 s the course north
    runs 50 m, into it (refused); 3 m/s runs 30 m, short of its 7.5 m clearance limit (37.5 m;
    allowed); south is open water (allowed)."""
    cells = np.zeros((200, 200), np.uint8)
    cells[:60, :] = 1  # rows from the north: y >= 140 is land
    field = Clearance(Grid(cells, Affine(1, 0, -100, 0, -1, 200)))
    c = controller(World(SHIP, np.array([0.0, -50.0]), field))
    own = Own(0.0, 100.0, NORTH, 5.0, 0.0)
    heads = np.array([NORTH, -NORTH])
    refused = c.grounds(own, np.array([5.0, 3.0, 5.0]), heads, np.array([0, 0, 1]))
    assert refused.tolist() == [True, False, False]


# -- every bundled scenario and the emergency and Imazu families ---------------------------

SCENARIOS = sorted((Path(__file__).resolve().parents[2] / "charts" / "scenarios").glob("*.yaml"))
FAMILY_SCENES = ([("emergency", kind, n) for kind in ("head-on", "crossing", "overtaking")
                  for n in range(3)]
                 + [("imazu", case, 0) for case in ("01", "02", "03", "05", "10", "15", "20")])


@pytest.mark.slow
@pytest.mark.parametrize("path", SCENARIOS, ids=lambda p: p.stem)
def test_every_bundled_scenario_arrives_without_a_contact(path):
    s = simulate(read_scenario(path), SimOptions(controller="vo", seed=1)).summary()
    assert s["collision"] is None and s["arrived"], s


@pytest.mark.slow
@pytest.mark.parametrize("fam, kind, n", FAMILY_SCENES)
def test_the_emergency_and_imazu_scenes_pass_without_a_contact(fam, kind, n):
    scenario = make_scene(fam, kind, n).draw.scenario
    s = simulate(parse({**scenario, "controller": {"name": "vo"}}, f"{fam} {kind} {n}")).summary()
    assert s["collision"] is None and s["arrived"], s
