"""Angles: compass degrees <-> mathematical radians, and the three wraps, by hand."""

import math

import numpy as np
import pytest

from usvtool.angles import compass_to_math, math_to_compass, wrap180, wrap360, wrap_pi


@pytest.mark.parametrize(
    ("compass", "radians"),
    [
        (0, math.pi / 2),
        (45, math.pi / 4),
        (90, 0.0),
        (135, -math.pi / 4),
        (180, -math.pi / 2),
        (225, -3 * math.pi / 4),
        (270, math.pi),
        (315, 3 * math.pi / 4),
        (360, math.pi / 2),
        (-90, math.pi),
        (450, 0.0),
    ],  # fmt: skip
)
def test_compass_to_math_by_hand(compass, radians):
    assert compass_to_math(compass) == pytest.approx(radians, abs=1e-15)
    assert math_to_compass(radians) == pytest.approx(compass % 360, abs=1e-12)


def test_compass_conversions_are_vectorised_and_inverse():
    deg = np.random.default_rng(1).uniform(0, 360, (7, 3))
    rad = compass_to_math(deg)
    assert rad.shape == (7, 3) and (rad > -math.pi).all() and (rad <= math.pi).all()
    np.testing.assert_allclose(math_to_compass(rad), deg, atol=1e-12)
    # a unit step along the heading: north is +y, east is +x
    step = np.column_stack([np.cos(compass_to_math([0, 90, 180, 270])),
                            np.sin(compass_to_math([0, 90, 180, 270]))])  # fmt: skip
    np.testing.assert_allclose(step, [[0, 1], [1, 0], [0, -1], [-1, 0]], atol=1e-15)


def test_math_to_compass_stays_in_0_360():
    north = math.pi / 2
    out = math_to_compass(np.array([np.nextafter(north, 4), np.nextafter(north, 0), -1e-300,
                                    5 * math.pi]))  # fmt: skip
    assert ((out >= 0) & (out < 360)).all()
    assert out[-1] == pytest.approx(270.0)


def test_wrap180():
    a = np.array([-540.0, -180.0, -179.5, 0.0, 180.0, 181.0, 359.0, 540.0])
    np.testing.assert_array_equal(wrap180(a), [180.0, 180.0, -179.5, 0.0, 180.0, -179.0, -1.0,
                                                180.0])  # fmt: skip
    assert wrap180(-0.0) == 0.0 and math.copysign(1, wrap180(-0.0)) == 1


def test_wrap360_is_half_open():
    assert wrap360([360.0, -360.0, 0.0, -1e-20, 359.5]).tolist() == [0.0, 0.0, 0.0, 0.0, 359.5]
    assert wrap360([-90.0, 725.0, 1e-300]).tolist() == [270.0, 5.0, 1e-300]


def test_wrap_pi_is_half_open_at_pi():
    rad = np.array([math.pi, -math.pi, 3 * math.pi, 0.0, -0.5, 7.0])
    out = wrap_pi(rad)
    assert ((out >= -math.pi) & (out < math.pi)).all()
    np.testing.assert_allclose(out, [-math.pi, -math.pi, -math.pi, 0.0, -0.5, 7.0 - 2 * math.pi],
                               atol=1e-15)  # fmt: skip
    # the same direction: the unit vectors agree
    np.testing.assert_allclose(np.exp(1j * out), np.exp(1j * rad), atol=1e-14)


def test_one_heading_in_floats_gives_the_bits_of_a_0d_array():
    """math_to_compass of a float takes the float path: the bits its NumPy path gives one heading
    (a 0-d array), on seeded angles and the edges (both zeros; a hair north of north, whose
    difference from 90 is -5.7e-14: its mod 360 is 359.99999999999994, where a 1-d array's
    loop rounds to 360, then 0)."""
    rng = np.random.default_rng(3)
    rad = np.concatenate([rng.uniform(-7, 7, 20_000), [0.0, -0.0, 1e-300, np.pi / 2 + 1e-15,
                                                       np.pi, -np.pi, 2 * np.pi, -2 * np.pi]])
    want = np.array([math_to_compass(np.asarray(r)) for r in rad])
    got = np.array([math_to_compass(float(r)) for r in rad])
    assert np.array_equal(got.view(np.int64), want.view(np.int64))
    assert type(math_to_compass(0.5)) is float
    assert math_to_compass(np.pi / 2 + 1e-15) == 359.99999999999994
