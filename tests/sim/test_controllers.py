"""The DWA core and its controllers, on hand-built situations and against the plain per-sample
loop of tests/sim/plain_dwa.py."""

import math

import numpy as np
import pytest
from affine import Affine

from usvtool.clearance import Clearance
from usvtool.errors import UsvError
from usvtool.grid import Grid
from usvtool.sim import vessel as vessel_model
from usvtool.sim.controllers import CONTROLLERS, Encounter, Own, Targets, World, make_controller
from usvtool.sim.weather import uniform

from . import plain_dwa

SHIP = vessel_model.preset("iwso-dwa-usv")  # 2.5 m, 1-5 m/s
NORTH = math.pi / 2


def ships(*rows):
    """Targets from (x, y, vx, vy, length) rows."""
    a = np.array(rows, float).reshape(-1, 5)
    return Targets(a[:, :2], a[:, 2:4], a[:, 4])


#: The hand-built situations below are sized for a short horizon, and the plain loop knows no
#: ship domain: both set here, whatever the controllers' defaults.
SHORT = {"horizon": 3.0, "step": 0.1, "domain": False}


def controller(name="dwa", goal=(0.0, 300.0), clearance=None, weather=None, **params):
    c = make_controller(name, **{**SHORT, **params})
    c.reset(World(SHIP, np.array(goal), clearance, None, weather, 0.1))
    return c


def replay(v, omega, own, targets, times, length=SHIP.length, field=None):
    """The smallest gap over the horizon of one sample, stepped independently with
    vessel.step (the exact arc) and plain distances."""
    x, y, psi = own.x, own.y, own.psi
    gap = math.inf
    for t in times:
        x, y, psi = (float(a) for a in vessel_model.step(x, y, psi, v, omega, times[0]))
        for p, u, other in zip(targets.pos, targets.vel, targets.length, strict=True):
            d = math.hypot(x - p[0] - u[0] * t, y - p[1] - u[1] * t)
            gap = min(gap, d - (length + other) / 2)
        if field is not None:
            gap = min(gap, float(field.at(np.array([x]), np.array([y]))[0]) - length / 2)
    return gap


def test_the_registry_names_every_controller():
    assert all(cls.name == name for name, cls in CONTROLLERS.items()) and "udwa+" in CONTROLLERS
    with pytest.raises(UsvError, match="unknown controller 'apf'.*dwa"):
        make_controller("apf")
    with pytest.raises(UsvError, match=r"^alpha is not a parameter of dwa \(known: horizon, "):
        make_controller("dwa", alpha=1)
    # the core's checks are its declarations' (usvtool/params.py), one line each
    for bad, words in (({"horizon": 0}, "horizon must be > 0 for udwa, not 0"),
                       ({"v_samples": 1}, "v_samples must be >= 2 for udwa, not 1"),
                       ({"v_samples": 2.5}, "v_samples must be an integer, not 2.5"),
                       ({"sides": "left"}, "sides must be one of none, paper, colregs, iwso "
                                           "for udwa, not 'left'"),
                       ({"priority": -1}, "priority must be >= 0 for udwa, not -1"),
                       ({"window": "step"}, "window must be one of period, horizon for udwa, "
                                            "not 'step'"),
                       ({"weather": 1}, "weather must be true or false, not 1")):  # fmt: skip
        with pytest.raises(UsvError) as info:
            make_controller("udwa", **bad)
        assert str(info.value) == words
    with pytest.raises(UsvError, match=r"^reach must be > 0 for gdwa, not 0$"):
        make_controller("gdwa", reach=0)
    assert make_controller("gdwa", reach=None).params["reach"] is None
    # a horizon shorter than half a rollout step rolls nothing out (was an internal IndexError)
    with pytest.raises(UsvError, match=r"horizon \(0.05\) must be at least half a step \(0.2\)"):
        make_controller("udwa", horizon=0.05)


def test_open_water_heads_for_the_goal_at_full_speed():
    """Nothing around, goal dead ahead: straight on, accelerating."""
    c = controller()
    d = c.decide(Own(0, 0, NORTH, 4.0, 0.0), Targets.none())
    assert d.omega == 0.0
    assert d.v == pytest.approx(4.0 + SHIP.max_accel * 0.1)


@pytest.mark.parametrize("seed", range(12))
def test_the_core_chooses_what_the_plain_loop_chooses(seed):
    """Random situations with 1-3 targets close by: the vectorised core's best score equals the
    per-sample loop's, and so do the contact times of every sample."""
    rng = np.random.default_rng(seed)
    k = int(rng.integers(1, 4))
    rows = [(*rng.uniform(-15, 15, 2) + (0, 15), *rng.uniform(-3, 3, 2), 2.5) for _ in range(k)]
    targets = ships(*rows)
    own = Own(0.0, 0.0, NORTH + rng.uniform(-0.5, 0.5), rng.uniform(1.5, 4.5), 0.0)
    c = controller(goal=tuple(rng.uniform(-100, 100, 2) + (0, 150)))
    r = c.rollouts(own, targets)
    samples = list(zip(r.v, r.omega, strict=True))
    best, score, contact = plain_dwa.choose(
        own, targets, samples, goal=c.world.goal, length=SHIP.length, times=c.times,
        weights=c.params,
    )  # fmt: skip
    np.testing.assert_allclose(r.contact, contact)
    d = c.decide(own, targets)
    if score is None:  # every sample meets a contact: the fallback's order
        assert d.events and d.events[0]["kind"] == "all-samples-collide"
    else:
        core = c.score(own, r, ~np.isfinite(r.contact))
        assert core[~np.isfinite(r.contact)].max() == pytest.approx(score, rel=1e-12)
        chosen = int(np.flatnonzero((r.v == d.v) & (r.omega == d.omega))[0])
        assert core[chosen] == pytest.approx(score, rel=1e-12)  # the same best (or a tie)
        assert d.omega == pytest.approx(samples[best][1]) or core[best] == pytest.approx(score)


def test_never_a_colliding_sample_while_a_free_one_exists():
    """A ship crossing close ahead from port and land 3 m to starboard: about half the samples
    meet one of them; the choice, replayed independently, meets neither."""
    cells = np.zeros((60, 60), np.uint8)
    cells[:, 33:] = 1  # land from x = 3 m east of the own ship
    field = Clearance(Grid(cells, Affine(1, 0, -30, 0, -1, 40)))
    targets = ships((-8, 10, 2.0, 0.0, 2.5))
    own = Own(0, 0, NORTH, 4.0, 0.0)
    c = controller(clearance=field)
    r = c.rollouts(own, targets)
    assert 0.3 < np.isfinite(r.contact).mean() < 0.8 and r.static_hit.any()  # the premise
    d = c.decide(own, targets)
    assert not d.events
    assert replay(d.v, d.omega, own, targets, c.times, field=field) > 0


def test_when_every_sample_collides_it_takes_the_longest_time_to_contact():
    """Boxed in by four ships: the fallback picks the sample whose contact comes last (by the
    plain loop), starboard and slow among equals, and logs which check rejected how many."""
    targets = ships((0, 6, 0, -1, 2.5), (5, 2, -1, 0, 2.5), (-5, 2, 1, 0, 2.5), (0, -4, 0, 1, 2.5))
    own = Own(0, 0, NORTH, 4.0, 0.0)
    c = controller()
    r = c.rollouts(own, targets)
    assert np.isfinite(r.contact).all()
    _, _, contact = plain_dwa.choose(own, targets, list(zip(r.v, r.omega, strict=True)),
                                     goal=c.world.goal, length=SHIP.length, times=c.times,
                                     weights=c.params)  # fmt: skip
    d = c.decide(own, targets)
    (event,) = d.events
    assert event["kind"] == "all-samples-collide"
    assert event["rejected"] == {"grid": 0, "targets": r.v.size, "side": 0}
    chosen = int(np.flatnonzero((r.v == d.v) & (r.omega == d.omega))[0])
    admissible = vessel_model.admissible(r.v, r.omega, r.v * r.contact, SHIP)
    if not admissible.any():  # none can stop in time: all are equal on that count
        admissible[:] = True
    assert contact[chosen] == max(c for c, a in zip(contact, admissible, strict=True) if a)
    ties = [i for i, a in enumerate(admissible) if a and contact[i] == contact[chosen]]
    assert d.omega == min(r.omega[ties])  # the most starboard (negative yaw rate) of the ties


def head_on_with_goal_to_port():
    """A head-on target and a goal off to port: the plain objective turns to port."""
    return ships((0, 40, 0, -3, 2.5)), Own(0, 0, NORTH, 4.0, 0.0), (-200.0, 200.0)


def test_ccdwa_removes_the_port_half_in_a_head_on():
    targets, own, goal = head_on_with_goal_to_port()
    assert controller(goal=goal).decide(own, targets).omega > 0  # dwa: to port
    ccdwa = controller("ccdwa", goal=goal)
    d = ccdwa.decide(own, targets, Encounter("head-on", 0))
    assert d.omega <= 0 and not d.events


def test_udwa_prefers_starboard_and_departs_under_rule_2_when_it_is_blocked():
    targets, own, goal = head_on_with_goal_to_port()
    udwa = controller("udwa", goal=goal, priority=10.0)
    assert udwa.decide(own, targets, Encounter("head-on", 0)).omega < 0  # preferred side wins
    blocker = ships((0, 40, 0, -3, 2.5), (2.0, 8.0, 0, 0, 2.5))  # a ship fine on the bow
    d = udwa.decide(own, blocker, Encounter("head-on", 0))
    assert d.omega > 0
    (event,) = d.events
    assert event["kind"] == "rule2-departure" and event["preferred"] == "starboard"
    assert "starboard" in event["reason"]
    ccdwa = controller("ccdwa", goal=goal)  # removal, but never into a contact: overridden
    d = ccdwa.decide(own, blocker, Encounter("head-on", 0))
    assert d.omega > 0 and [e["kind"] for e in d.events] == ["side-rule-overridden"]


def test_the_side_tables_read_the_papers():
    """Crossing from port: the UDWA paper turns to port, the COLREGs (Rule 17(c)) never."""
    udwa = make_controller("udwa").side_rule
    assert udwa.side(Encounter("crossing-stand-on", 0)) == 1
    colregs = make_controller("udwa", sides="colregs").side_rule
    assert colregs.side(Encounter("crossing-stand-on", 0)) == -1
    assert udwa.side(Encounter("overtaken", 0)) == 0 and udwa.side(None) == 0
    assert make_controller("dwa").side_rule.side(Encounter("head-on", 0)) == 0


def test_the_weather_term_favours_the_heading_that_makes_more_speed():
    """Wind 7 m/s from the north: with the weather term a southern heading scores a higher
    speed than a northern one at the same calm-water speed (eq. 5)."""
    c = controller("udwa", weather=uniform(7.0, 0.0))
    r = c.rollouts(Own(0, 0, 0.0, 4.0, 0.0), Targets.none())  # heading east
    r.psi_end[:] = np.where(r.omega > 0, NORTH, -NORTH)  # pretend: port samples end north
    (velocity,) = [critic for critic in c.objective if critic.name == "velocity"]
    speed = velocity.reward(None, r)
    same_v = r.v == r.v[0]
    assert speed[same_v & (r.omega > 0)].max() < speed[same_v & (r.omega < 0)].min()
    assert (speed[r.omega > 0] < r.v[r.omega > 0]).all()  # a head wind costs speed


def test_gdwa_follows_the_route_vertex_by_vertex():
    route = np.array([[0.0, 0.0], [0.0, 50.0], [50.0, 50.0]])
    c = make_controller("gdwa", reach=5.0)
    c.reset(World(SHIP, np.array([50.0, 100.0]), None, route, None, 0.1))
    assert c.progress.subgoal(Own(0, 0, NORTH, 4, 0)).tolist() == [0.0, 50.0]
    assert c.progress.subgoal(Own(0, 46, NORTH, 4, 0)).tolist() == [50.0, 50.0]  # within reach
    assert c.progress.subgoal(Own(60, 52, 0, 4, 0)).tolist() == [50.0, 100.0]  # passed: the goal


def test_the_domain_is_kept_clear_when_some_sample_can():
    """A ship lying 12 m ahead, 3 m to starboard: out of reach of every hull, but the straight
    samples bring her inside the own ship's domain (7 L x 3 L, semi-axes 8.75 m and 3.75 m).
    With the domain rule the choice keeps her outside it over the horizon, replayed by hand."""
    targets = ships((3.0, 12.0, 0.0, 0.0, 2.5))
    own = Own(0, 0, NORTH, 4.0, 0.0)
    kept = controller(domain=True)
    r = kept.rollouts(own, targets)
    assert r.intrudes.any() and not r.intrudes.all()  # the premise
    d = kept.decide(own, targets)
    x, y, psi = own.x, own.y, own.psi
    for _ in kept.times:  # the target inside the ellipse along and across the heading?
        x, y, psi = (float(a) for a in vessel_model.step(x, y, psi, d.v, d.omega, 0.1))
        mid = psi - d.omega * 0.05
        along = (3.0 - x) * math.cos(mid) + (12.0 - y) * math.sin(mid)
        across = (12.0 - y) * math.cos(mid) - (3.0 - x) * math.sin(mid)
        assert (along / 8.75) ** 2 + (across / 3.75) ** 2 > 1
    assert r.intrudes[r.omega == 0].all()  # holding course would bring her inside


def test_a_rollout_through_the_goal_scores_the_full_heading():
    """Close to the goal a fast rollout ends beyond it looking away; it reaches it all the same
    and gets the heading term's maximum (a ship would circle the goal otherwise)."""
    c = make_controller("dwa", **SHORT)
    c.reset(World(SHIP, np.array([0.0, 6.0]), None, None, None, 0.1, 1.0))
    r = c.rollouts(Own(0, 0, NORTH, 4.0, 0.0), Targets.none())
    straight = r.omega == 0.0
    assert r.reached[straight].all() and np.abs(r.end[straight] - 6j).min() > 5  # ends beyond
    (heading,) = [critic for critic in c.objective if critic.name == "heading"]
    assert (heading.reward(None, r)[straight] == math.pi).all()


def test_safe_priority_gives_the_bonus_only_where_nothing_comes_near():
    """The head-on with the goal to port: the plain objective turns to port, a large starboard
    bonus to starboard. With ``safe_priority`` the bonus goes only to samples whose clearance
    reaches ``dist_max``: none here (the target comes within 30 m of every rollout), so the
    choice is the unbiased one; with a 10 m cap every rollout reaches it, and starboard wins."""
    targets, own, goal = head_on_with_goal_to_port()
    enc = Encounter("head-on", 0)
    plain = controller("udwa", goal=goal, priority=0.0).decide(own, targets, enc)
    assert plain.omega > 0  # the premise
    assert controller("udwa", goal=goal, priority=10.0).decide(own, targets, enc).omega < 0
    safe = controller("udwa", goal=goal, priority=10.0, safe_priority=True)
    r = safe.rollouts(own, targets)
    assert (r.clearance < safe.params["dist_max"]).all()
    assert safe.decide(own, targets, enc).omega == plain.omega
    capped = controller("udwa", goal=goal, priority=10.0, safe_priority=True, dist_max=10.0)
    assert (capped.rollouts(own, targets).clearance >= 10.0).all()
    assert capped.decide(own, targets, enc).omega < 0


def test_the_horizon_window_turns_in_its_rollouts_and_commands_one_periods_step():
    """The UDWA boat at 7 m/s, not turning (5 deg/s² of yaw acceleration, 2 m/s²): one period's
    window holds 0.5 deg/s either way, the horizon's the whole +-20 deg/s. The rollouts of the
    horizon window turn (a sample at 20 deg/s ends 160 deg round after 10 s: 4 s of ramp at
    5 deg/s², 40 deg, then 6 s at 20 deg/s, 120 deg); the command is one period's step toward
    the chosen sample."""
    boat = vessel_model.preset("udwa-usv")
    own = Own(0.0, 0.0, NORTH, 7.0, 0.0)
    targets = ships((0.0, 60.0, 0.0, -5.0, 15.0))  # head-on, 60 m
    made = {}
    for window in ("period", "horizon"):
        c = make_controller("udwa", window=window)
        c.reset(World(boat, np.array([0.0, 400.0]), None, None, None, 0.1))
        made[window] = c, c.rollouts(own, targets)
    period, horizon = made["period"][1], made["horizon"][1]
    assert np.degrees(np.abs(period.omega).max()) == pytest.approx(0.5)
    assert np.degrees(np.abs(horizon.omega).max()) == pytest.approx(20.0)
    hardest = np.argmax(horizon.omega)
    assert np.degrees(horizon.psi_end[hardest] - NORTH) % 360 == pytest.approx(160.0)
    c = made["horizon"][0]
    d = c.decide(own, targets, Encounter("head-on", 0))
    assert abs(d.omega) <= math.radians(0.5) + 1e-12 and 6.8 - 1e-12 <= d.v <= 7.0
    assert d.omega != 0.0  # it turns: somewhere toward a sample of the wide window
