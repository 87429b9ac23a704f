"""The compiled glue of a DWA step (usvtool/sim/rollout_kernels.py: window_axes, weighted_shares,
heading_reward) against the Python and NumPy expressions they stand for, bit for bit (the sign
of zero included), on seeded random windows, rewards and angles."""

import math

import numpy as np
import pytest

from usvtool.angles import wrap_pi
from usvtool.sim import rollout_kernels as kernels
from usvtool.sim import vessel as vessel_model
from usvtool.sim.controllers import Own, Targets, World, make_controller
from usvtool.sim.controllers.base import normalise


def same_bits(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def limits(vessel) -> np.ndarray:
    return np.array([vessel.min_speed, vessel.max_speed, vessel.max_decel, vessel.max_accel,
                     vessel.max_yaw_rate, vessel.max_yaw_accel], float)  # fmt: skip


def random_vessel(rng) -> vessel_model.Vessel:
    low = float(rng.choice([0.0, rng.uniform(0, 2)]))
    return vessel_model.Vessel(5.0, 2.0, None, low, low + rng.uniform(0.5, 8), rng.uniform(0.1, 3),
                               rng.uniform(0.1, 3), rng.uniform(0.05, 1.2),
                               rng.uniform(0.01, 1.5))  # fmt: skip


@pytest.mark.parametrize("seed", range(30))
def test_window_axes_are_the_window_its_samples_and_their_pairs(seed):
    rng = np.random.default_rng(seed)
    vessels = (vessel_model.preset("udwa-usv"), vessel_model.preset("iwso-dwa-usv"))
    for trial in range(40):
        ship = vessels[trial % 2] if trial < 20 else random_vessel(rng)
        v = float(rng.choice([0.0, ship.min_speed, ship.max_speed,
                              rng.uniform(0, ship.max_speed * 1.2)]))  # fmt: skip
        omega = float(rng.choice([0.0, ship.max_yaw_rate, -ship.max_yaw_rate, 1e-18,
                                  rng.uniform(-1.2, 1.2) * ship.max_yaw_rate]))  # fmt: skip
        span = float(rng.choice([0.1, 0.2, 0.05, 10.0, rng.uniform(0.01, 20)]))
        n_v, n_omega = int(rng.integers(2, 26)), int(rng.integers(2, 26))
        win = vessel_model.window(ship, v, omega, span)
        speeds, rates = vessel_model.samples(win, n_v, n_omega, current=(v, omega))
        got = kernels.window_axes(v, omega, limits(ship), span, n_v, n_omega)
        want = (speeds, rates, np.repeat(speeds, rates.size), np.tile(rates, speeds.size))
        for a, b in zip(got, want, strict=True):
            assert same_bits(a, b), (seed, trial)


def test_a_period_windows_samples_are_the_axes_and_fan_of_the_step():
    """PeriodWindow.sample (one compiled call for the window) gives what axes and fan give."""
    rng = np.random.default_rng(3)
    ship = vessel_model.preset("udwa-usv")
    for name in ("udwa", "udwa+"):
        c = make_controller(name)
        c.reset(World(ship, np.array([0.0, 800.0])))
        for _ in range(20):
            own = Own(*rng.uniform(-50, 50, 2), rng.uniform(-4, 4), rng.uniform(0, 7),
                      rng.uniform(-0.3, 0.3))  # fmt: skip
            v, omega, fan = c.generator.sample(own, 21, 21)
            speeds, rates = c.generator.axes(own, 21, 21)
            want = c.generator.fan(own, speeds, rates)
            assert same_bits(v, np.repeat(speeds, rates.size))
            assert same_bits(omega, np.tile(rates, speeds.size))
            for a, b in zip(fan, want, strict=True):
                assert same_bits(a, b)


def numpy_score(rewards, scales, candidates):
    """The core's score as the loop over the critics made it."""
    total = np.zeros(rewards.shape[1])
    for values, scale in zip(rewards, scales, strict=True):
        total += scale * normalise(values, candidates)
    return total


@pytest.mark.parametrize("seed", range(30))
def test_weighted_shares_are_the_sum_of_the_normalised_rewards(seed):
    rng = np.random.default_rng(seed)
    for trial in range(30):
        critics, n = int(rng.integers(1, 6)), int(rng.choice([1, 7, 8, 9, 130, 274, 441, 462,
                                                              int(rng.integers(1, 2000))]))
        rewards = rng.uniform(0, 1, (critics, n)) * 10.0 ** rng.uniform(-4, 4, (critics, 1))
        rewards[rng.random((critics, n)) < 0.2] = 0.0
        if critics > 1:
            rewards[0] = 0.0  # a critic whose sum is zero: no share
            rewards[-1] -= rng.uniform(0, 2) * rewards[-1].mean()  # some negative rewards
        candidates = rng.random(n) < rng.choice([0.0, 0.3, 0.9, 1.0])
        scales = rng.choice([0.0, 0.06, 0.2, 0.3, 0.4, 0.5, 1.0, -0.5], critics)
        shares = np.where(candidates, rewards, 0.0)
        sums = shares.sum(axis=1)
        for row, total in zip(shares, sums, strict=True):  # the premise: a row's sum is its own
            assert same_bits(total, row.copy().sum())
        got = kernels.weighted_shares(shares, sums, scales)
        assert same_bits(got, numpy_score(rewards, scales, candidates)), (seed, trial)


@pytest.mark.parametrize("seed", range(10))
def test_heading_reward_is_the_wrapped_angle(seed):
    rng = np.random.default_rng(seed)
    n = 2000
    off = rng.uniform(-4 * math.pi, 4 * math.pi, n)
    off[:16] = [0.0, -0.0, math.pi, -math.pi, 2 * math.pi, -2 * math.pi, 3 * math.pi,
                -3 * math.pi, 1e-300, -1e-300, math.nextafter(math.pi, 0),
                math.nextafter(-math.pi, 0), 7.0, -7.0, 1e3, -1e3]  # fmt: skip
    reached = rng.random(n) < 0.1
    want = np.where(reached, np.pi, np.pi - np.abs(wrap_pi(off)))
    assert same_bits(kernels.heading_reward(off, reached), want)


@pytest.mark.parametrize("seed", range(20))
def test_candidates_are_the_free_samples_less_the_removed_and_the_domains(seed):
    rng = np.random.default_rng(seed)
    for _ in range(50):
        n = int(rng.integers(1, 500))
        contact = np.where(rng.random(n) < rng.uniform(0, 1), np.inf, rng.uniform(0.2, 10, n))
        removed = rng.random(n) < rng.choice([0.0, 0.5, 1.0])
        intrudes = rng.random(n) < rng.choice([0.0, 0.3, 0.95, 1.0])
        free = ~np.isfinite(contact)
        want = free & ~removed
        if (want & ~intrudes).any():
            want &= ~intrudes
        got_free, got = kernels.candidates(contact, removed, intrudes)
        assert same_bits(got_free, free) and same_bits(got, want)


@pytest.mark.parametrize("seed", range(10))
def test_track_urgent_is_track_then_most_urgent(seed):
    from usvtool.sim import tracking_kernels as tk

    rng = np.random.default_rng(seed)
    k = int(rng.integers(1, 7))
    limits = [rng.uniform(5, 60, k), rng.uniform(5, 60, k), np.full(k, np.inf)]
    states = [[np.zeros(k, np.int8), np.full(k, np.nan), np.full(k, np.nan), np.full(k, np.nan)]
              for _ in range(2)]  # fmt: skip
    xy = rng.uniform(-300, 300, (k, 2))
    vel = rng.uniform(-5, 5, (k, 2))
    heading = rng.uniform(0, 360, k)
    for step in range(300):
        t = 0.1 * step
        at = xy + vel * t
        speed = np.hypot(vel[:, 0], vel[:, 1])
        own = (float(rng.uniform(-5, 5)), float(t * 3), float(rng.uniform(0, 360)),
               float(rng.uniform(0, 6)))  # fmt: skip
        scratch = [(np.empty(k, np.int8), np.empty((5, k))) for _ in range(2)]
        tk.track(t, *own, at, heading, speed, *limits, 120.0, *states[0], *scratch[0])
        want = tk.most_urgent(states[0][0], states[0][2])
        got = tk.track_urgent(t, *own, at, heading, speed, *limits, 120.0, *states[1],
                              *scratch[1])  # fmt: skip
        assert got == want
        for a, b in zip(states[0] + list(scratch[0]), states[1] + list(scratch[1]), strict=True):
            assert same_bits(a, b)


def numpy_vo_candidates(psi, v, offsets, off, turn, lo, hi, n):
    """vo's candidates as NumPy made them (before the kernel)."""
    speeds = np.linspace(lo, hi, n)
    extra = [0.0, off] if abs(off) <= turn else [0.0]
    heads = psi + np.concatenate((offsets, extra))
    h = heads.size
    speed = np.empty(speeds.size * h + 1)
    speed[:-1] = np.repeat(speeds, h)
    speed[-1] = v
    index = np.empty(speed.size, np.intp)
    index[:-1] = np.tile(np.arange(h), speeds.size)
    index[-1] = offsets.size
    return speed, heads, index, heads[index]


@pytest.mark.parametrize("seed", range(20))
def test_vo_candidates_are_numpys(seed):
    rng = np.random.default_rng(seed)
    for _ in range(40):
        turn = float(rng.choice([math.pi, rng.uniform(0.05, math.pi)]))
        h = int(rng.integers(3, 50))
        offsets = np.linspace(-turn, turn, h + 1 if turn >= math.pi else h)[:h].copy()
        psi, v = float(rng.uniform(-4, 4)), float(rng.uniform(0, 7))
        off = math.remainder(float(rng.uniform(-7, 7)), 2 * math.pi)
        lo = float(rng.choice([0.0, v, rng.uniform(0, 7)]))
        hi = float(rng.choice([lo, lo + rng.uniform(0, 7), lo + 1e-320, lo * (1 + 1e-16)]))
        n = int(rng.integers(2, 12))
        got = kernels.vo_candidates(psi, v, offsets, off, abs(off) <= turn, lo, hi, n)
        want = numpy_vo_candidates(psi, v, offsets, off, turn, lo, hi, n)
        for a, b in zip(got, want, strict=True):
            assert same_bits(a, b)


@pytest.mark.parametrize("seed", range(20))
def test_vo_contacts_are_first_contacts_minimum(seed):
    from usvtool.sim.controllers.vo import first_contact

    rng = np.random.default_rng(seed)
    kinds = set()
    for _ in range(30):
        n, k = int(rng.integers(1, 300)), int(rng.integers(1, 6))
        vx, vy = rng.uniform(-7, 7, n), rng.uniform(-7, 7, n)
        pos = rng.uniform(-200, 200, (k, 2))
        pos[rng.random(k) < 0.2] *= 0.01  # some already inside
        vel = rng.uniform(-6, 6, (k, 2))
        vel[rng.random(k) < 0.2] = 0.0
        radius = rng.uniform(5, 40, k)
        spread = float(rng.choice([0.0, 0.25, rng.uniform(0, 8)]))  # a < 0 for some
        horizon = float(rng.choice([30.0, 5.0, 300.0]))
        w = np.stack([vx[:, None] - vel[:, 0], vy[:, None] - vel[:, 1]], axis=-1)
        want = first_contact(pos, w, radius, spread, horizon).min(axis=1)
        got = kernels.vo_contacts(vx, vy, pos[:, 0].copy(), pos[:, 1].copy(), vel, radius, spread,
                                  horizon)  # fmt: skip
        assert same_bits(got, want)
        kinds |= {"inside" if t == 0 else "contact" if np.isfinite(t) else "none" for t in want}
    assert kinds == {"inside", "contact", "none"}


@pytest.mark.parametrize("seed", range(20))
def test_vo_near_is_numpys_cpa_test(seed):
    from usvtool.encounter import VEL_EPS

    rng = np.random.default_rng(seed)
    seen = set()
    for _ in range(60):
        k = int(rng.integers(1, 8))
        pos = rng.uniform(-150, 150, (k, 2))
        vel = rng.uniform(-5, 5, (k, 2))
        x, y, psi, v = *rng.uniform(-20, 20, 2), rng.uniform(-4, 4), rng.uniform(0, 6)
        own_vx, own_vy = v * math.cos(psi), v * math.sin(psi)
        vel[rng.random(k) < 0.2] = (own_vx, own_vy)  # no relative motion
        time, distance = float(rng.choice([60.0, 20.0])), float(rng.choice([10.0, 60.0]))
        rel = pos - (x, y)
        wx, wy = vel[:, 0] - own_vx, vel[:, 1] - own_vy
        ww = wx * wx + wy * wy
        moving = ww > VEL_EPS * VEL_EPS
        tcpa = np.where(moving, -(rel[:, 0] * wx + rel[:, 1] * wy) / np.where(moving, ww, 1.0),
                        0.0)  # fmt: skip
        dcpa = np.hypot(rel[:, 0] + tcpa * wx, rel[:, 1] + tcpa * wy)
        want = (tcpa > 0) & (tcpa <= time) & (dcpa <= distance)
        got = kernels.vo_near(pos, vel, x, y, own_vx, own_vy, time, distance)
        assert same_bits(got, want)
        seen |= set(want.tolist())
    assert seen == {True, False}


@pytest.mark.parametrize("seed", range(10))
def test_favour_is_numpys_side_bonus(seed):
    rng = np.random.default_rng(seed)
    for _ in range(50):
        n = int(rng.integers(1, 500))
        score = rng.uniform(-1, 1, n)
        omega = rng.choice([0.0, -0.0, 0.1, -0.1, np.nan, 1e-300, -1e-300], n)
        omega[rng.random(n) < 0.5] = rng.uniform(-0.3, 0.3)
        clearance = rng.choice([np.inf, 30.0, 29.999, 0.0, 45.0], n)
        side, priority = int(rng.choice([-1, 1])), float(rng.choice([0.5, 1.0, 0.1]))
        for safe in (False, True):
            bonus = np.sign(omega) == side
            if safe:
                bonus &= clearance >= 30.0
            want = np.where(bonus, score * (1 + priority), score)
            got = kernels.favour(score, omega, side, 1 + priority, clearance, 30.0, safe)
            assert same_bits(got, want)


def test_first_touching_is_numpys_first_contact():
    from usvtool.sim import tracking_kernels as tk

    rng = np.random.default_rng(5)
    found = set()
    for _ in range(2000):
        k = int(rng.integers(1, 6))
        xy = rng.uniform(-40, 40, (k, 2))
        x, y = rng.uniform(-10, 10, 2)
        reach = rng.uniform(5, 30, k)
        near = rng.random(k) < 0.1  # exactly at the reach: not touching
        xy[near, 0], xy[near, 1] = x + reach[near], y
        hit = np.flatnonzero(np.hypot(xy[:, 0] - x, xy[:, 1] - y) < reach)
        want = int(hit[0]) if hit.size else -1
        assert tk.first_touching(xy, float(x), float(y), reach) == want
        found.add(want >= 0)
    assert found == {True, False}


def test_offsets_are_numpys_differences():
    rng = np.random.default_rng(2)
    for _ in range(100):
        n = int(rng.integers(1, 500))
        points = rng.uniform(-1e4, 1e4, n) + 1j * rng.uniform(-1e4, 1e4, n)
        px, py = (float(v) for v in rng.uniform(-1e4, 1e4, 2))
        north, east = kernels.offsets(points, px, py)
        assert same_bits(north, py - points.imag) and same_bits(east, px - points.real)


def test_a_route_progress_gives_the_same_subgoal_for_the_same_state():
    from usvtool.sim.controllers.critics import RouteProgress

    ship = vessel_model.preset("iwso-dwa-usv")
    route = np.array([[0.0, 0.0], [0.0, 60.0], [40.0, 100.0], [40.0, 200.0]])
    cached, fresh = RouteProgress(None, 10.0), RouteProgress(None, 10.0)
    world = World(ship, np.array([40.0, 260.0]), route=route)
    cached.reset(world)
    fresh.reset(world)
    for y in np.linspace(0, 260, 200):
        own = Own(float(y) / 7, float(y), 1.0, 4.0, 0.0)
        first = cached.subgoal(own)
        assert same_bits(cached.subgoal(own), first)  # asked again by another critic
        fresh._last = None  # no memory: worked out afresh
        assert same_bits(fresh.subgoal(own), first)


def test_the_path_critic_at_the_goal_takes_the_rollouts_distances_to_it():
    """gdwa's path critic, its sub-goal the goal (no route), reuses the rollouts' closest
    approach to the goal: the same reward as a pass of its own."""
    rng = np.random.default_rng(4)
    ship = vessel_model.preset("iwso-dwa-usv")
    goal = np.array([30.0, 200.0])
    c = make_controller("gdwa")
    c.reset(World(ship, goal))
    path = next(critic for critic in c.objective if critic.name == "path")
    for _ in range(20):
        own = Own(*rng.uniform(-40, 40, 2), rng.uniform(-4, 4), rng.uniform(1, 5),
                  rng.uniform(-0.5, 0.5))  # fmt: skip
        r = c.rollouts(own, Targets.none())
        afresh = np.sqrt(kernels.closest(r.x, r.y, float(goal[0]), float(goal[1]))[1])
        assert same_bits(path.reward(own, r), afresh.max() - afresh)


def island_field(rng):
    """A grid of random islands and a solid block, cells of 1-4 m, around the fans."""
    from affine import Affine

    from usvtool.clearance import Clearance
    from usvtool.grid import Grid

    cells = (rng.random((60, 70)) < 0.03).astype(np.uint8)
    cells[20:30, 40:55] = 1
    size = float(rng.choice([1.0, 2.5, 4.0]))
    return Clearance(Grid(cells, Affine(size, 0, -35 * size, 0, -size, 30 * size)))


def step_targets(rng) -> tuple:
    """0-4 targets, some within reach of the rollouts, as the sweep takes them."""
    k = int(rng.integers(0, 5))
    pos = rng.uniform(-60, 60, (k, 2)) + (0, 40)
    pos[rng.random(k) < 0.3] *= 20  # some far off
    return pos, rng.uniform(-5, 5, (k, 2)), rng.uniform(2, 20, k)


def separate_sweep(c, own, targets):
    """A step's rollouts as the separate kernels made them (the generator's sample, contacts,
    closest): ``(v, omega, x, y, contact, static_first, clearance, intrudes, row, to_goal,
    near)``."""
    v, omega, fan = c.generator.sample(own, c._n_v, c._n_omega)
    found = kernels.contacts(fan.x, fan.y, fan.radius, fan.u, c.times, float(own.x),
                             float(own.y), *targets, *c._checks)  # fmt: skip
    return (v, omega, fan.x, fan.y, *found, *kernels.closest(fan.x, fan.y, *c._goal))


@pytest.mark.parametrize("name", ["udwa", "udwa+", "gdwa"])
@pytest.mark.parametrize("seed", range(4))
def test_a_sweep_is_the_sample_its_contacts_and_the_closest_points(name, seed):
    """The generators' sweep (one compiled call for the period window: period_sweep, its
    closest points taken as the fan is made, arc_points_closest; sweep for the ramps) gives
    what window_axes, arc_fan or the ramps, contacts and closest give apart."""
    rng = np.random.default_rng([seed, len(name)])
    ship = vessel_model.preset("udwa-usv" if name != "gdwa" else "iwso-dwa-usv")
    for field in (None, island_field(rng)):
        c = make_controller(name, **({"step": 0.1, "horizon": 3.0} if seed % 2 else {}))
        c.reset(World(ship, np.array([float(rng.uniform(-30, 30)), 120.0]), field))
        for _ in range(10):
            own = Own(*rng.uniform(-20, 20, 2), rng.uniform(-4, 4), rng.uniform(0, 7),
                      rng.uniform(-0.3, 0.3))  # fmt: skip
            targets = step_targets(rng)
            got = c.generator.sweep(own, c._n_v, c._n_omega, targets, c._checks, c._goal)
            want = separate_sweep(c, own, targets)
            for a, b in zip(got, want, strict=True):
                assert same_bits(a, b), (name, seed)


def test_arc_points_closest_is_arc_points_then_closest():
    rng = np.random.default_rng(11)
    for _ in range(60):
        speeds = np.sort(rng.uniform(0, 7, int(rng.integers(1, 23))))
        rates = np.sort(rng.uniform(-0.4, 0.4, int(rng.integers(1, 24))))
        rates[rng.random(rates.size) < 0.1] = 0.0
        steps, dt = int(rng.integers(1, 60)), float(rng.choice([0.1, 0.2, 0.5]))
        x0, y0, psi0 = (float(a) for a in rng.uniform(-100, 100, 3))
        u = np.empty((steps, rates.size), complex)
        chord, summed = kernels.arc_chords(psi0, speeds, rates, dt, u)
        x, y = np.empty((2, steps, speeds.size * rates.size))
        radius = kernels.arc_points(x0, y0, chord, summed, x, y)
        goal = (float(rng.uniform(-200, 200)), float(rng.uniform(-200, 200)))
        if rng.random() < 0.2:  # the goal on a point: equal distances, the first row kept
            goal = (float(x[steps // 2, 0]), float(y[steps // 2, 0]))
        want = (radius, *kernels.closest(x, y, *goal))
        x2, y2 = np.empty((2, steps, speeds.size * rates.size))
        got = kernels.arc_points_closest(x0, y0, chord, summed, x2, y2, *goal)
        assert same_bits(x2, x) and same_bits(y2, y)
        for a, b in zip(got, want, strict=True):
            assert same_bits(a, b)
        u2, x3, y3 = np.empty_like(u), np.empty_like(x), np.empty_like(y)
        assert same_bits(kernels.arc_fan(x0, y0, psi0, speeds, rates, dt, u2, x3, y3), radius)
        assert same_bits(u2, u) and same_bits(x3, x) and same_bits(y3, y)


def weather_field(rng, wave_height: bool, wave_from: bool, outside: str):
    """A random field of 1-7 x 1-9 cells (tests/sim/test_weather_kernels.py's)."""
    from affine import Affine

    from usvtool.sim.weather import FieldWeather

    rows, cols = int(rng.integers(1, 8)), int(rng.integers(1, 10))
    layers = [rng.uniform(-8, 8, (rows, cols)), rng.uniform(-8, 8, (rows, cols))]
    if wave_height:
        layers.append(rng.uniform(0, 3, (rows, cols)))
    if wave_from:
        angle = rng.uniform(-math.pi, math.pi, (rows, cols))
        layers += [np.cos(angle), np.sin(angle)]
    cell = float(rng.uniform(5, 20))
    transform = Affine(cell, 0.0, -30.0, 0.0, -cell, rows * cell - 30.0)
    return FieldWeather(np.array(layers), transform, wave_height, wave_from, outside)


@pytest.mark.parametrize("outside", ["nearest", "calm"])
@pytest.mark.parametrize("wave_height, wave_from", [(False, False), (True, False), (True, True)])
def test_a_fields_speed_of_floats_and_of_vectors_is_the_general_paths(outside, wave_height,
                                                                      wave_from):  # fmt: skip
    """FieldWeather.attainable_speed of four floats (field_attainable_speed_one) and of four
    contiguous vectors (the kernel without broadcasting) gives the bits of its general path
    (broadcast, ravelled copies) and of the kernel of one point."""
    from usvtool.sim import weather_kernels

    rng = np.random.default_rng([3, wave_height, wave_from, outside == "calm"])
    for _ in range(10):
        w = weather_field(rng, wave_height, wave_from, outside)
        n = 200
        v, heading = rng.uniform(-1, 8, n), rng.uniform(-7, 7, n)
        x, y = rng.uniform(-80, 250, n), rng.uniform(-80, 250, n)
        v[:5] = 0.0
        dwt = float(rng.choice([0.0, 20.0]))
        general = w.attainable_speed(v[:, None], heading[:, None], x[:, None], y[:, None],
                                     dwt)[:, 0]  # fmt: skip
        assert same_bits(w.attainable_speed(v, heading, x, y, dwt), general)
        for i in range(0, n, 7):
            a = (float(v[i]), float(heading[i]), float(x[i]), float(y[i]))
            one = w.attainable_speed(*a, dwt)
            assert type(one) is np.float64 and one.shape == ()
            assert same_bits(one, general[i])
            assert same_bits(w.attainable_speed(*(np.float64(b) for b in a), dwt), general[i])
            assert weather_kernels.field_attainable_speed_one(
                *w._compiled, a[2], a[3], a[0], a[1], *w._flags, dwt, 1852.0 / 3600.0
            ) == general[i] or math.isnan(general[i])  # fmt: skip


def test_the_velocity_critic_in_a_field_takes_the_final_positions():
    """The weather's speed critic reads the final positions as the rollouts' last rows: the
    bits of the final positions' parts (Rollouts.end) it read before."""
    rng = np.random.default_rng(8)
    ship = vessel_model.preset("udwa-usv")
    for name in ("udwa", "udwa+"):
        w = weather_field(rng, True, True, "nearest")
        c = make_controller(name)
        c.reset(World(ship, np.array([0.0, 400.0]), weather=w))
        velocity = next(critic for critic in c.objective if critic.name == "velocity")
        for _ in range(10):
            own = Own(*rng.uniform(-20, 60, 2), rng.uniform(-4, 4), rng.uniform(0, 7),
                      rng.uniform(-0.3, 0.3))  # fmt: skip
            r = c.rollouts(own, Targets.none())
            want = w.attainable_speed(r.v, r.psi_end, r.end.real, r.end.imag, ship.deadweight)
            assert same_bits(velocity.reward(own, r), want)


def test_the_transformers_are_made_once_per_pair_and_give_a_fresh_ones_bits():
    from pyproj import Transformer

    from usvtool import geodesy

    rng = np.random.default_rng(1)
    lon, lat = rng.uniform(2.5, 3.5, 50), rng.uniform(-1, 1, 50)
    for crs in ("EPSG:32631", 32631):
        fresh = Transformer.from_crs(geodesy.WGS84, crs, always_xy=True)
        assert geodesy.transformer(geodesy.WGS84, crs) is geodesy.transformer(geodesy.WGS84, crs)
        for a, b in zip(geodesy.lonlat_to_map(crs, lon, lat), fresh.transform(lon, lat),
                        strict=True):  # fmt: skip
            assert same_bits(a, b)
        assert geodesy.lonlat_to_map(crs, 3.0, 0.5) == tuple(
            float(a) for a in fresh.transform(3.0, 0.5))


def test_the_ramps_ufuncs_called_as_numpys_are_numbas_and_the_midpoints_the_expression():
    """vessel.toward and travelled call the NumPy ufuncs under numba's frozen ones (no Python
    wrapper): the same bits, broadcasting and casting as the numba call; ramps' cached period
    middles are the expression it computed every step."""
    rng = np.random.default_rng(6)
    for _ in range(30):
        now = float(rng.uniform(-1, 7))
        target = rng.uniform(-1, 7, int(rng.integers(1, 30)))
        target[rng.random(target.size) < 0.2] = now
        t = rng.choice([0.05, 0.1, 0.2]) * (np.arange(int(rng.integers(1, 60))) + 0.5)[:, None]
        down, up = (float(a) for a in rng.uniform(0.01, 3, 2))
        assert same_bits(vessel_model.toward(now, target, down, up, t),
                         kernels.toward(now, target, down, up, t))  # fmt: skip
        assert same_bits(vessel_model.travelled(now, target, down, down, t),
                         kernels.travelled(now, target, down, down, t))  # fmt: skip
        assert same_bits(vessel_model.travelled(now, target[:, None], down, up, t[:, 0]),
                         kernels.travelled(now, target[:, None], down, up, t[:, 0]))  # fmt: skip
    assert same_bits(vessel_model.toward(2, np.array([7, 0]), 1, 2, 1), np.array([4.0, 1.0]))
    for dt, steps in ((0.2, 50), (0.1, 30), (0.5, 1)):
        assert same_bits(vessel_model._midpoints(dt, steps), dt * (np.arange(steps) + 0.5)[:, None])


@pytest.mark.parametrize("seed", range(6))
def test_crosses_ahead_is_numpys_change_of_side_ahead_of_the_bow(seed):
    """The Rule 15 test's kernel against the NumPy expression it stands for, with zeros, signed
    zeros and NaNs among the sides."""
    rng = np.random.default_rng(seed)
    for _ in range(40):
        steps, n = int(rng.integers(1, 40)), int(rng.integers(1, 300))
        x, y = rng.uniform(-50, 50, (2, steps, n))
        x[rng.random((steps, n)) < 0.05] = np.nan
        times = 0.2 * np.arange(1, steps + 1)
        px, py, vx, vy = (float(a) for a in rng.uniform(-30, 30, 4))
        if rng.random() < 0.3:  # on the course line: zero sides
            x[:, : n // 2] = px + vx * times[:, None]
            y[:, : n // 2] = py + vy * times[:, None]
        speed = math.hypot(vx, vy)
        hx, hy = vx / speed, vy / speed
        now = float(rng.choice([1.5, -2.0, 0.0, -0.0, np.nan, float(rng.uniform(-5, 5))]))
        tx, ty = px + vx * times[:, None], py + vy * times[:, None]
        rx, ry = x - tx, y - ty
        want = ((np.sign(hx * ry - hy * rx) != np.sign(now)) & (hx * rx + hy * ry > 0)).any(0)
        got = kernels.crosses_ahead(x, y, times, px, py, vx, vy, hx, hy, now)
        assert same_bits(got, want)


def test_heading_reward_at_the_modulos_borders():
    """heading_reward's vectorised pass (no modulo inside (-2 pi, 2 pi)) and its modulo pass
    meet where ``off + pi`` is 0 or +-2 pi: the bits of wrap_pi on either side of each border,
    with every sample beyond them, none, or a few."""
    borders = [-3 * np.pi, -np.pi, np.pi, 3 * np.pi, -5 * np.pi, 5 * np.pi]
    near = [np.nextafter(b, d) for b in borders for d in (-np.inf, np.inf)] + borders
    rng = np.random.default_rng(12)
    for values in (np.array(near), rng.uniform(-3, 3, 300), rng.uniform(-9, 9, 300),
                   np.concatenate([rng.uniform(-3, 3, 300), near])):  # fmt: skip
        reached = rng.random(values.size) < 0.2
        want = np.where(reached, np.pi, np.pi - np.abs(wrap_pi(values)))
        assert same_bits(kernels.heading_reward(values, reached), want)
    odd = np.array([np.nan, np.inf, -np.inf, 1.0])
    got = kernels.heading_reward(odd, np.zeros(4, bool))
    assert np.isnan(got[:3]).all() and got[3] == np.pi - 1.0


def test_wrap_angles_is_wrap_pi():
    borders = [-3 * np.pi, -np.pi, np.pi, 3 * np.pi, -5 * np.pi, 5 * np.pi]
    near = [np.nextafter(b, d) for b in borders for d in (-np.inf, np.inf)] + borders
    rng = np.random.default_rng(13)
    for values in (np.array(near + [0.0, -0.0, 1e-300, -1e-300]), rng.uniform(-3, 3, 300),
                   rng.uniform(-9, 9, 300), rng.uniform(-1e3, 1e3, 300),
                   np.concatenate([rng.uniform(-3, 3, 300), near])):  # fmt: skip
        assert same_bits(kernels.wrap_angles(values), wrap_pi(values))
    assert np.isnan(kernels.wrap_angles(np.array([np.nan, np.inf, -np.inf]))).all()


def test_the_weathers_off_bow_is_numpys_at_the_modulos_borders():
    from usvtool.sim import weather_kernels
    from usvtool.sim.weather import off_bow

    borders = [-3 * np.pi, -np.pi, np.pi, 3 * np.pi, -5 * np.pi, 5 * np.pi]
    near = [np.nextafter(b, d) for b in borders for d in (-np.inf, np.inf)] + borders
    rng = np.random.default_rng(14)
    for delta in [*near, 0.0, -0.0, 1e-300, *rng.uniform(-20, 20, 400)]:
        assert same_bits(weather_kernels._off_bow(float(delta)), off_bow(float(delta), 0.0))


def test_the_runs_grid_collision_is_the_grids_own_test():
    """run._collision's grid test in floats (the bounds taken once) against Grid.contains and
    Grid.cell_of, on points inside, outside and on the cells' edges."""
    from types import SimpleNamespace

    from affine import Affine

    from usvtool.grid import OBSTACLE, Grid
    from usvtool.sim import run as sim_run

    rng = np.random.default_rng(15)
    for _ in range(20):
        size = float(rng.choice([1.0, 2.5, 4.0, 0.3]))
        cells = (rng.random((30, 40)) < 0.2).astype(np.uint8) * OBSTACLE
        left, top = (float(a) for a in rng.uniform(-500, 500, 2))
        grid = Grid(cells, Affine(size, 0, left, 0, -size, top))
        g_left, bottom, right, g_top = grid.bounds
        setup = SimpleNamespace(grid=grid, box=(*grid.bounds, grid.cell_size, grid.cells,
                                                OBSTACLE))  # fmt: skip
        xs = [*rng.uniform(g_left - 20, right + 20, 300), g_left, right,
              *(g_left + size * np.arange(40))]  # fmt: skip
        ys = [*rng.uniform(bottom - 20, g_top + 20, 300), bottom, g_top,
              *(g_top - size * np.arange(40))]  # fmt: skip
        for x, y in zip(xs, rng.permutation(ys), strict=True):
            x, y = float(x), float(y)
            if not grid.contains(x, y):
                want = -1
            else:
                row, col = grid.cell_of(x, y)
                want = -1 if grid.cells[row, col] == OBSTACLE else None
            assert sim_run._collision(setup, x, y, np.zeros((0, 2)), np.zeros(0)) == want
