"""The own ship: presets, kinematics (IWSO eq. 16), dynamic window and braking (eqs. 18-20)."""

import math

import numpy as np
import pytest

from usvtool.errors import UsvError
from usvtool.sim.vessel import (
    PRESETS,
    Vessel,
    Window,
    admissible,
    arcs,
    preset,
    ramps,
    samples,
    step,
    step_one,
    travelled,
    vessel_from,
    window,
)

from . import libm

UDWA = preset("udwa-usv")
IWSO = preset("iwso-dwa-usv")


# -- presets ----------------------------------------------------------------------------------


def test_udwa_preset_is_table_3():
    assert UDWA.deadweight == 20.0
    assert (UDWA.min_speed, UDWA.max_speed, UDWA.max_accel) == (0.0, 7.0, 2.0)
    assert UDWA.max_yaw_rate == math.radians(20.0)
    assert UDWA.max_yaw_accel == math.radians(5.0)


def test_iwso_preset_is_section_5_2_in_degrees():
    assert (IWSO.min_speed, IWSO.max_speed, IWSO.max_accel, IWSO.max_decel) == (1, 5, 0.7, 0.8)
    assert IWSO.max_yaw_rate == math.radians(60.0)  # printed "60 rad/s"
    assert IWSO.max_yaw_accel == math.radians(75.0)  # printed "75 rad/s^2"
    assert IWSO.deadweight is None


def test_user_units_round_trip():
    assert vessel_from(None, UDWA.user_units()) == UDWA
    assert UDWA.user_units()["max_yaw_rate"] == pytest.approx(20.0)


def test_overrides_in_user_units():
    ship = vessel_from("udwa-usv", {"max_yaw_rate": 10, "beam": 3}, "s.yaml: own.vessel")
    assert ship.max_yaw_rate == pytest.approx(math.radians(10))
    assert ship.beam == 3.0 and ship.max_speed == 7.0


def _message(excinfo) -> str:
    text = str(excinfo.value)
    assert "\n" not in text
    return text


def test_unknown_preset_lists_the_known_ones():
    with pytest.raises(UsvError) as e:
        vessel_from("tanker", {}, "s.yaml: own.vessel")
    text = _message(e)
    assert text.startswith("s.yaml: own.vessel: unknown vessel preset 'tanker'")
    assert all(name in text for name in PRESETS)


@pytest.mark.parametrize(
    "field, value, expected",
    [
        ("max_speed", float("nan"), "max_speed must be > 0, not nan"),
        ("max_speed", 0, "max_speed must be > 0, not 0"),
        ("max_accel", -1.5, "max_accel must be > 0, not -1.5"),
        ("max_yaw_rate", float("inf"), "max_yaw_rate must be finite, not inf"),
        ("max_decel", "fast", "max_decel must be a number, not 'fast'"),
        ("max_yaw_accel", True, "max_yaw_accel must be a number, not True"),
        ("min_speed", -1, "min_speed must be >= 0, not -1"),
        ("min_speed", 8, "min_speed (8) must not exceed max_speed (7.0)"),
        ("deadweight", 0, "deadweight must be > 0, not 0"),
        ("speed", 3, "unknown vessel field(s) 'speed'"),
    ],
)
def test_bad_override_names_the_field(field, value, expected):
    with pytest.raises(UsvError) as e:
        vessel_from("udwa-usv", {field: value}, "s.yaml: own.vessel")
    assert _message(e).startswith("s.yaml: own.vessel: " + expected)


def test_no_preset_needs_every_field():
    with pytest.raises(UsvError) as e:
        vessel_from(None, {"max_speed": 3}, "own.vessel")
    assert "length, beam, min_speed, max_accel" in _message(e)


def test_direct_construction_is_validated():
    values = dict(UDWA.__dict__, max_speed=float("nan"))
    with pytest.raises(UsvError, match=r"^vessel: max_speed must be > 0, not nan$"):
        Vessel(**values)


# -- kinematics -------------------------------------------------------------------------------


def test_step_straight_line():
    assert np.allclose(step(1.0, 2.0, 0.0, 3.0, 0.0, 2.0), (7.0, 2.0, 0.0))
    assert np.allclose(step(1.0, 2.0, math.pi / 2, 3.0, 0.0, 2.0), (1.0, 8.0, math.pi / 2))


def test_step_quarter_circle_port_and_starboard():
    # v = 2 m/s, |omega| = pi/4 rad/s: radius 8/pi; 2 s turn through 90 degrees
    r = 8 / math.pi
    assert np.allclose(step(0.0, 0.0, 0.0, 2.0, math.pi / 4, 2.0), (r, r, math.pi / 2))
    assert np.allclose(step(0.0, 0.0, 0.0, 2.0, -math.pi / 4, 2.0), (r, -r, -math.pi / 2))


def test_step_heading_wraps():
    _, _, psi = step(0.0, 0.0, 3.0, 1.0, 1.0, 0.5)  # 3.5 rad -> 3.5 - 2 pi
    assert float(psi) == pytest.approx(3.5 - 2 * math.pi)
    x, y, psi = step(5.0, 5.0, 1.0, 2.0, 0.5, 4 * math.pi)  # a full circle
    assert np.allclose((x, y, psi), (5.0, 5.0, 1.0))


def test_step_broadcasts():
    x, y, psi = step(0.0, 0.0, np.zeros((3, 1)), np.ones(4), 0.1, 1.0)
    assert x.shape == y.shape == psi.shape == (3, 4)


def test_step_one_gives_the_bits_of_step():
    """The run's scalar step against the NumPy one of one pose (0-d arrays, as a run called it)
    on seeded poses: straight on (omega 0 and -0.0, np.sinc's epsilon), tiny and ordinary
    turns, headings past pi (the wrap), at rest."""
    rng = np.random.default_rng(16)
    n = 5_000
    x, y = rng.uniform(-1e4, 1e4, (2, n))
    psi = rng.uniform(-4, 4, n)
    psi[:20] = -math.pi  # the wrap's edge: psi + 0 + pi = 0
    v = np.where(rng.random(n) < 0.1, 0.0, rng.uniform(0, 12, n))
    omega = rng.choice([0.0, -0.0, 1e-12, -3e-10, 0.05, -0.3, 0.5], n) * rng.uniform(0.5, 1, n)
    omega[:50] = [0.0, -0.0] * 25
    dt = rng.choice([0.05, 0.1, 0.2], n)
    poses = list(zip(x, y, psi, v, omega, dt, strict=True))
    want = np.array([[float(c) for c in step(*map(float, p))] for p in poses])
    got = np.array([step_one(*map(float, p)) for p in poses])
    for column in range(3):  # bit for bit where NumPy's sin and cos are the C library's
        libm.assert_close_bits(got[:, column], want[:, column], "x y psi".split()[column])
    assert all(isinstance(c, float) for c in step_one(1.0, 2.0, 3.0, 4.0, 0.0, 0.1))


def _euler(x0, y0, psi0, v, omega, dt, steps, sub=100_000):
    """Fine forward-Euler integration of x' = v cos psi, y' = v sin psi, psi' = omega."""
    h = dt * steps / sub
    k = np.arange(sub)
    psi = psi0 + omega[:, None] * h * k
    x = x0 + np.cumsum(v[:, None] * h * np.cos(psi), axis=1)
    y = y0 + np.cumsum(v[:, None] * h * np.sin(psi), axis=1)
    at = np.arange(1, steps + 1) * (sub // steps) - 1
    return np.stack([x[:, at], y[:, at]], -1)


def _positions(fan) -> np.ndarray:
    """A fan's rollouts as positions (N, steps, 2)."""
    return np.stack([fan.x.T, fan.y.T], -1)


def test_arcs_match_fine_euler():
    speeds = np.array([0.0, 1.0, 3.0, 5.0])
    rates = np.array([0.3, 0.0, 1e-9, -0.3, 0.6, -math.radians(20)])
    fan = arcs(10.0, -4.0, 0.7, speeds, rates, 0.5, 20)
    assert fan.x.shape == fan.y.shape == (20, 24) and fan.u.shape == (20, 6)
    v, omega = np.repeat(speeds, 6), np.tile(rates, 4)  # pair i·R + k: speed i, rate k
    assert np.abs(_positions(fan) - _euler(10.0, -4.0, 0.7, v, omega, 0.5, 20)).max() < 2e-3
    # each period's chord direction: the heading at the middle of the period
    mid = 0.7 + rates * 0.5 * (np.arange(20)[:, None] + 0.5)
    np.testing.assert_allclose(fan.u, np.exp(1j * mid), rtol=0, atol=1e-12)


def test_arcs_near_zero_yaw_rate_keep_their_first_order_term():
    # omega = 1e-8: x = v t cos psi0 - v omega t^2/2 sin psi0 (+ v omega^2 t^3/6 ~ 1e-14)
    v, omega, psi0 = 5.0, 1e-8, 0.7
    t = 0.5 * np.arange(1, 21)
    pos = _positions(arcs(0.0, 0.0, psi0, [v], [omega, 0.0], 0.5, 20))
    x = v * t * math.cos(psi0) - v * omega * t**2 / 2 * math.sin(psi0)
    y = v * t * math.sin(psi0) + v * omega * t**2 / 2 * math.cos(psi0)
    assert np.abs(pos[0] - np.stack([x, y], -1)).max() < 1e-11
    np.testing.assert_allclose(
        pos[1], np.stack([v * t * math.cos(psi0), v * t * math.sin(psi0)], -1), atol=1e-12, rtol=0
    )


def test_arcs_equal_repeated_steps():
    speeds, rates = np.array([1.0, 4.0]), np.array([0.2, -0.5])
    pos = _positions(arcs(1.0, 2.0, 3.0, speeds, rates, 0.25, 7))
    v, omega = np.repeat(speeds, 2), np.tile(rates, 2)
    x, y, psi = np.full(4, 1.0), np.full(4, 2.0), np.full(4, 3.0)
    for k in range(7):
        x, y, psi = step(x, y, psi, v, omega, 0.25)
        assert np.allclose(pos[:, k], np.stack([x, y], -1))


def test_window_hand_case():
    # eq. 19: 3 m/s -+ 2 m/s^2 * 0.5 s; 19 deg/s -+ 5 deg/s^2 * 0.5 s, cut at 20 deg/s (eq. 18)
    w = window(UDWA, 3.0, math.radians(19), 0.5)
    assert w == pytest.approx((2.0, 4.0, math.radians(16.5), math.radians(20)))


def test_window_at_the_limits():
    assert window(UDWA, 7.0, 0.0, 0.25)[:2] == (6.5, 7.0)  # no faster than max_speed
    assert window(UDWA, 0.0, 0.0, 0.25)[:2] == (0.0, 0.5)  # no slower than min_speed = 0
    assert window(IWSO, 1.0, 0.0, 0.25)[:2] == (1.0, 1.175)  # min_speed = 1
    w = window(UDWA, 3.0, -math.radians(20), 0.5)
    assert w[2:] == pytest.approx((-math.radians(20), -math.radians(17.5)))


def test_window_out_of_reach_collapses_to_nearest():
    assert window(IWSO, 0.0, 0.0, 0.5)[:2] == (0.35, 0.35)  # accelerating toward min_speed 1
    assert window(UDWA, 8.0, 0.0, 0.25)[:2] == (7.5, 7.5)  # slowing toward max_speed 7


def test_window_broadcasts():
    w = window(UDWA, np.array([0.0, 7.0]), 0.0, 0.5)
    assert w.v_lo.tolist() == [0.0, 6.0] and w.v_hi.tolist() == [1.0, 7.0]


def test_admissible_hand_case():
    # dist 4 m: v <= sqrt(2 * 4 * 2) = 4 m/s; |omega| * v <= 2 * 4 * radians(5) = 0.69813,
    # so at 3 m/s |omega| <= 0.23271 rad/s = 13.33 deg/s
    v = [4.0, 4.1, 3.0, 3.0, 3.0, 0.0]
    omega = np.radians([0.0, 0.0, 13.0, 14.0, -14.0, 20.0])
    assert admissible(v, omega, 4.0, UDWA).tolist() == [True, False, True, False, False, True]
    assert admissible(v, omega, np.inf, UDWA).all()
    assert admissible([0.0, 0.1], 0.0, 0.0, UDWA).tolist() == [True, False]
    assert admissible([0.0, 0.1], 0.3, np.nan, UDWA).tolist() == [True, False]  # NaN: 0 m


def test_samples_grid_edges_current_and_straight():
    w = Window(1.0, 2.0, -0.3, 0.1)
    speeds, rates = samples(w, 3, 3)
    assert speeds.tolist() == [1.0, 1.5, 2.0]
    assert rates.tolist() == pytest.approx([-0.3, -0.1, 0.0, 0.1])
    speeds, rates = samples(w, 3, 3, current=(1.2, -0.25))
    assert speeds.tolist() == [1.0, 1.2, 1.5, 2.0]
    assert rates.tolist() == pytest.approx([-0.3, -0.25, -0.1, 0.0, 0.1])
    speeds, rates = samples(w, 3, 3, current=(5.0, 1.0))  # outside: not added
    assert speeds.size == 3 and rates.size == 4


def test_samples_degenerate_window_and_bad_counts():
    speeds, rates = samples(window(IWSO, 0.0, 0.0, 0.5), 5, 4)
    assert speeds.tolist() == [0.35] and 0.0 in rates
    with pytest.raises(ValueError):
        samples(Window(0, 1, 0, 1), 1, 3)


def test_samples_straight_on_is_exactly_zero():
    """Where the yaw axis crosses zero linspace gives 5.6e-17 rad/s, and a sample there would
    count as a turn (the side rules go by the sign): it is zero, once, and so is a current yaw
    rate within round-off of it."""
    assert np.linspace(-0.3, 0.2, 6)[3] != 0.0  # the premise
    _, rates = samples(Window(1.0, 2.0, -0.3, 0.2), 2, 6, current=(1.0, -2.8e-17))
    assert rates.tolist() == pytest.approx([-0.3, -0.2, -0.1, 0.0, 0.1, 0.2])
    assert 0.0 in rates.tolist() and not ((rates != 0) & (np.abs(rates) < 1e-9)).any()


def test_ramps_reach_the_sample_at_the_limits_then_hold_it():
    """From 3 m/s and no turn toward 7 m/s and 10 deg/s on the UDWA boat (2 m/s², 5 deg/s²):
    both ramps take 2 s. By hand: heading 5 t²/2 deg up to 2 s, then 10 + 10 (t - 2); distance
    3 t + t² up to 2 s, then 10 + 7 (t - 2). The positions against a fine Euler march of the same
    ramps (and a second sample slowing to 1 m/s, turning to starboard): the midpoint rule's
    error at the 0.2 s rollout step is millimetres."""
    v, omega = [7.0, 1.0], np.radians([10.0, -10.0])
    t = np.arange(1, 7) * 0.5
    yaw = UDWA.max_yaw_accel
    turned = travelled(0.0, omega[0], yaw, yaw, t)
    np.testing.assert_allclose(np.degrees(turned), [0.625, 2.5, 5.625, 10, 15, 20])
    run = travelled(3.0, v[0], UDWA.max_decel, UDWA.max_accel, t)
    np.testing.assert_allclose(run, [1.75, 4, 6.75, 10, 13.5, 17])
    # slowing from 3 to 1 m/s at 2 m/s² takes 1 s: 3 t - t² up to 1 s, then 2 + (t - 1)
    run = travelled(3.0, v[1], UDWA.max_decel, UDWA.max_accel, t)
    np.testing.assert_allclose(run, [1.25, 2, 2.5, 3, 3.5, 4])
    fan = ramps(0.0, 0.0, 0.0, 3.0, 0.0, v, omega, UDWA, 0.5, 6)  # pairs (7, 10), (1, -10)
    np.testing.assert_allclose(fan.x[:4, 0], [1.75, 4, 6.75, 10], atol=0.25)  # turning a bit
    np.testing.assert_allclose(np.abs(fan.u), 1.0)
    fan = ramps(0.0, 0.0, 0.0, 3.0, 0.0, v, omega, UDWA, 0.2, 15)
    z = (fan.x + 1j * fan.y).T[[0, 3]]  # the pairs (7 m/s, 10 deg/s) and (1 m/s, -10 deg/s)
    dt = 1e-4
    for i in range(2):
        x = y = h = 0.0
        speed, rate, marks = 3.0, 0.0, []
        for n in range(1, 30001):
            speed += min(max(v[i] - speed, -UDWA.max_decel * dt), UDWA.max_accel * dt)
            turn = float(omega[i]) - rate
            rate += min(max(turn, -UDWA.max_yaw_accel * dt), UDWA.max_yaw_accel * dt)
            h += rate * dt
            x += speed * dt * math.cos(h)
            y += speed * dt * math.sin(h)
            if n % 2000 == 0:
                marks.append(complex(x, y))
        np.testing.assert_allclose(z[i], marks, atol=0.005)
