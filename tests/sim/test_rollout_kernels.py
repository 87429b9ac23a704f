"""The compiled rollout kernels (usvtool/sim/rollout_kernels.py) against the NumPy expressions
they stand for, bit for bit, on seeded random fans, grids and targets; and what their distance
bounds skip (far targets: no effect on any decision; what skipping saves, benchmarks/
bench_simulate.py measures)."""

import math
import tracemalloc

import numpy as np
import pytest
from affine import Affine

from usvtool.clearance import Clearance
from usvtool.encounter import domain_ellipse, domain_semi_axes
from usvtool.grid import Grid
from usvtool.sim import rollout_kernels as kernels
from usvtool.sim import vessel as vessel_model
from usvtool.sim.controllers import Own, Targets, World, make_controller

UDWA = vessel_model.preset("udwa-usv")


def fan(rng, ramped: bool):
    """A random fan of 4-9 speeds x 3-12 yaw rates over 5-40 steps, by arcs or by ramps."""
    speeds = np.sort(rng.uniform(0, 7, int(rng.integers(4, 10))))
    rates = np.sort(rng.uniform(-0.35, 0.35, int(rng.integers(3, 13))))
    steps, dt = int(rng.integers(5, 41)), float(rng.choice([0.1, 0.2, 0.5]))
    x0, y0, psi0 = rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-4, 4)
    if ramped:
        made = vessel_model.ramps(x0, y0, psi0, rng.uniform(0, 7), rng.uniform(-0.3, 0.3),
                                  speeds, rates, UDWA, dt, steps)  # fmt: skip
    else:
        made = vessel_model.arcs(x0, y0, psi0, speeds, rates, dt, steps)
    return made, (x0, y0), dt * np.arange(1, steps + 1)


def numpy_arcs(x0, y0, psi0, speeds, rates, dt, steps):
    """vessel.arcs as NumPy broadcasts (the positions before the kernel)."""
    turn = rates * dt
    u = np.empty((steps, rates.size), complex)
    u[0] = np.exp(1j * (psi0 + turn / 2))
    u[1:] = np.exp(1j * turn)
    np.cumprod(u, axis=0, out=u)
    summed = np.cumsum(u, axis=0)
    chord = speeds[:, None] * dt * np.sinc(turn / (2 * np.pi))
    x = (chord * summed.real[:, None, :]).reshape(steps, -1) + x0
    y = (chord * summed.imag[:, None, :]).reshape(steps, -1) + y0
    return x, y


def numpy_ramps(x0, y0, psi0, v0, omega0, speeds, rates, vessel, dt, steps):
    """vessel.ramps as NumPy broadcasts and cumulative sums."""
    t_mid = dt * (np.arange(steps) + 0.5)[:, None]
    chord = dt * vessel_model.toward(v0, speeds, vessel.max_decel, vessel.max_accel, t_mid)
    turned = vessel_model.travelled(omega0, rates, vessel.max_yaw_accel, vessel.max_yaw_accel,
                                    t_mid)  # fmt: skip
    u = np.exp(1j * (psi0 + turned))
    x = np.cumsum(chord[:, :, None] * u.real[:, None, :], axis=0).reshape(steps, -1) + x0
    y = np.cumsum(chord[:, :, None] * u.imag[:, None, :], axis=0).reshape(steps, -1) + y0
    return x, y


@pytest.mark.parametrize("seed", range(20))
def test_the_fans_positions_are_numpys_and_within_their_bound(seed):
    rng = np.random.default_rng(seed)
    speeds = np.sort(rng.uniform(0, 7, int(rng.integers(2, 10))))
    rates = np.sort(rng.uniform(-0.35, 0.35, int(rng.integers(1, 13))))
    steps, dt = int(rng.integers(1, 41)), float(rng.choice([0.1, 0.2, 0.5]))
    x0, y0, psi0 = rng.uniform(-1e5, 1e5, 3)
    v0, omega0 = rng.uniform(0, 7), rng.uniform(-0.3, 0.3)
    for made, (x, y), tight in (
        (vessel_model.arcs(x0, y0, psi0, speeds, rates, dt, steps),
         numpy_arcs(x0, y0, psi0, speeds, rates, dt, steps), True),
        (vessel_model.ramps(x0, y0, psi0, v0, omega0, speeds, rates, UDWA, dt, steps),
         numpy_ramps(x0, y0, psi0, v0, omega0, speeds, rates, UDWA, dt, steps), False),
    ):  # fmt: skip
        np.testing.assert_array_equal(made.x, x)
        np.testing.assert_array_equal(made.y, y)
        spread = np.hypot(made.x - x0, made.y - y0).max(axis=1)
        assert (spread <= made.radius * (1 + 1e-12) + 1e-9).all()  # a bound on every point
        if tight:  # the arcs' is the fastest sample's distance; the ramps', the distance run
            assert (made.radius <= spread * (1 + 1e-12) + 1e-9).all()


def numpy_checks(x, y, times, field, pos, vel, length, own_length, every, u, cap):
    """The rollouts' checks as the NumPy core made them: (contact, static_first, clearance,
    intrudes), every target and every point looked at."""
    t, n = x.shape
    radius = own_length / 2
    hit = np.zeros((t, n), bool)
    static = np.zeros((t, n), bool)
    clearance = np.full(n, np.inf)
    if field is not None:
        gap = field.at(x, y) - radius
        clearance = gap.min(axis=0)
        static = gap <= 0
        hit |= static
    along = domain_semi_axes(own_length)[0]
    intrudes = np.zeros(n, bool)
    rates = u.shape[1]
    for j in range(len(length)):
        ahead = pos[j] + vel[j] * times[:, None]
        dx, dy = ahead[:, 0, None] - x, ahead[:, 1, None] - y
        d2 = np.square(dx) + np.square(dy)
        reach = (own_length + length[j]) / 2
        hit |= d2 <= reach * reach
        clearance = np.minimum(clearance, np.sqrt(d2.min(axis=0)) - reach)
        if every and d2.min() <= along * along * (1 + 1e-9):
            rows = slice(None, None, every)
            ux, uy = np.tile(u.real[rows], n // rates), np.tile(u.imag[rows], n // rates)
            intrudes |= (domain_ellipse(dx[rows], dy[rows], ux, uy, own_length) <= 1).any(axis=0)
    first = np.where(hit.any(axis=0), hit.argmax(axis=0), t)
    at = np.minimum(first, t - 1)
    contact = np.where(first < t, times[at], np.inf)
    static_first = (first < t) & static[at, np.arange(n)]
    return contact, static_first, clearance, intrudes


def kernel_checks(made, start, times, field, pos, vel, length, own_length, every, cap):
    if field is not None:
        grid = field.grid
        left, _, _, top = grid.bounds
        table = (field.padded, grid.width, left, top, 1 / grid.cell_size, grid.cell_size)
    else:
        table = (np.zeros(0), 0, 0.0, 0.0, 1.0, 1.0)
    along, across = domain_semi_axes(own_length)
    return kernels.contacts(made.x, made.y, made.radius, made.u, times, *start, pos, vel, length,
                            *table, own_length, every, along, across,
                            along * along * (1 + 1e-9), cap)  # fmt: skip


def random_field(rng):
    """A grid of random islands and a solid block, cells of 1-4 m, around the fans."""
    cells = (rng.random((60, 70)) < 0.03).astype(np.uint8)
    cells[20:30, 40:55] = 1
    size = float(rng.choice([1.0, 2.5, 4.0]))
    return Clearance(Grid(cells, Affine(size, 0, -35 * size, 0, -size, 30 * size)))


@pytest.mark.parametrize("seed", range(40))
def test_the_checks_are_numpys(seed):
    """Contacts, which comes first, the domain and the clearance (capped at ``cap``, what the
    controllers use of it: beyond it the kernel may skip) are the NumPy core's, bit for bit."""
    rng = np.random.default_rng(seed)
    made, start, times = fan(rng, ramped=bool(seed % 2))
    field = random_field(rng) if seed % 3 else None
    k = int(rng.integers(0, 7))
    pos = rng.uniform(-60, 60, (k, 2))
    vel = rng.uniform(-6, 6, (k, 2))
    length = rng.uniform(2, 30, k)
    own_length, every, cap = float(rng.uniform(2, 20)), int(rng.integers(0, 4)), 30.0
    got = kernel_checks(made, start, times, field, pos, vel, length, own_length, every, cap)
    want = numpy_checks(made.x, made.y, times, field, pos, vel, length, own_length, every,
                        made.u, cap)  # fmt: skip
    for name, a, b in zip(("contact", "static_first", "clearance", "intrudes"), got, want,
                          strict=True):  # fmt: skip
        if name == "clearance":
            a, b = np.minimum(a, cap), np.minimum(b, cap)
        np.testing.assert_array_equal(a, b, err_msg=name)


def test_the_premises_of_the_comparison_hold():
    """The random cases above have contacts with the grid and with targets, some first with
    either, intrusions and clearances below the cap (else the comparison proves little)."""
    seen = {"grid first": 0, "target first": 0, "intrudes": 0, "below cap": 0}
    for seed in range(40):
        rng = np.random.default_rng(seed)
        made, start, times = fan(rng, ramped=bool(seed % 2))
        field = random_field(rng) if seed % 3 else None
        k = int(rng.integers(0, 7))
        pos, vel = rng.uniform(-60, 60, (k, 2)), rng.uniform(-6, 6, (k, 2))
        length = rng.uniform(2, 30, k)
        contact, static_first, clearance, intrudes = kernel_checks(
            made, start, times, field, pos, vel, length, float(rng.uniform(2, 20)),
            int(rng.integers(0, 4)), 30.0)  # fmt: skip
        seen["grid first"] += static_first.sum()
        seen["target first"] += (np.isfinite(contact) & ~static_first).sum()
        seen["intrudes"] += intrudes.sum()
        seen["below cap"] += (clearance < 30.0).sum()
    assert min(seen.values()) > 50, seen


def test_closest_and_crosses_ahead_are_numpys():
    crossing = []
    for seed in range(12):
        rng = np.random.default_rng(seed)
        made, _, times = fan(rng, ramped=bool(seed % 2))
        x, y = made.x, made.y
        columns = np.arange(x.shape[1])
        px, py = rng.uniform(-80, 80, 2)
        row, d2, point = kernels.closest(x, y, px, py)
        to = np.square(x - px) + np.square(y - py)
        want = to.argmin(axis=0)
        np.testing.assert_array_equal(row, want)
        np.testing.assert_array_equal(d2, to[want, columns])
        np.testing.assert_array_equal(point, x[want, columns] + 1j * y[want, columns])
        vx, vy = rng.uniform(-5, 5, 2)  # a target through the fan's middle at mid-horizon
        mid = times.size // 2
        px, py = x[mid].mean() - vx * times[mid], y[mid].mean() - vy * times[mid]
        hx, hy = np.array([vx, vy]) / math.hypot(vx, vy)
        now = hx * (made.y[0, 0] - py) - hy * (made.x[0, 0] - px)
        rx, ry = x - (px + vx * times)[:, None], y - (py + vy * times)[:, None]
        want = ((np.sign(hx * ry - hy * rx) != np.sign(now)) & (hx * rx + hy * ry > 0)).any(0)
        got = kernels.crosses_ahead(x, y, times, px, py, vx, vy, hx, hy, now)
        np.testing.assert_array_equal(got, want)
        crossing.append(want.mean())
    assert 0 < np.mean(crossing) < 1 and max(crossing) > 0  # both kinds are there


def open_water(name="udwa", **params):
    c = make_controller(name, **params)
    c.reset(World(UDWA, np.array([0.0, 800.0]), None, None, None, 0.1, 5.0))
    return c


def scattered(rng, k, near: int = 0):
    """``k`` targets 400-2000 m off (beyond reach of a 10 s horizon), ``near`` of them close."""
    bearing, rng_m = rng.uniform(0, 2 * np.pi, k), rng.uniform(400, 2000, k)
    pos = np.column_stack([rng_m * np.cos(bearing), rng_m * np.sin(bearing)])
    pos[:near] = rng.uniform(-60, 60, (near, 2)) + (0, 80)
    return Targets(pos, rng.uniform(-5, 5, (k, 2)), np.full(k, 15.0))


def test_far_targets_change_no_decision():
    """300 targets beyond reach of the horizon, and 3 close: the step decides as with the 3
    alone, with the same contacts, domain and clearance below the cap."""
    rng = np.random.default_rng(7)
    own = Own(0.0, 0.0, math.pi / 2, 6.0, 0.0)
    crowd = scattered(rng, 303, near=3)
    close = Targets(crowd.pos[:3], crowd.vel[:3], crowd.length[:3])
    c = open_water()
    a, b = c.rollouts(own, crowd), c.rollouts(own, close)
    assert np.isfinite(b.contact).any() and (b.clearance < 30).any()  # the close ones matter
    for name in ("contact", "static_hit", "intrudes"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    np.testing.assert_array_equal(np.minimum(a.clearance, 30), np.minimum(b.clearance, 30))
    crowded, alone = c.decide(own, crowd), c.decide(own, close)
    assert (crowded.v, crowded.omega) == (alone.v, alone.omega)


def test_a_step_holds_no_horizon_by_samples_array_but_the_positions():
    """tracemalloc's peak of one step (NumPy's allocations): the positions, 16 bytes per
    rollout point, and a few hundred bytes per sample (the NumPy core held some 100 bytes per
    point: distances, gaps, contact tables)."""
    c = open_water("gdwa", v_samples=101, omega_samples=101)
    own = Own(0.0, 0.0, math.pi / 2, 5.0, 0.0)
    targets = Targets(np.array([[0.0, 40.0], [20.0, 30.0]]), np.array([[0.0, -3.0], [-3.0, 0]]),
                      np.array([15.0, 15.0]))  # fmt: skip
    c.decide(own, targets)
    r = c.rollouts(own, targets)
    n, t = r.v.size, r.x.shape[0]
    del r
    tracemalloc.start()
    try:
        c.decide(own, targets)
        used = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert 16 * n * t < used < 16 * n * t + 320 * n, (used / (n * t), n, t)
