"""The compiled weather lookup (usvtool/sim/weather_kernels.py) against the NumPy expressions it
stands for (FieldWeather.at, then eq. 5), bit for bit where NumPy's math is the C library's (else
within a few ulps: tests/sim/libm.py), on seeded random fields and points inside and outside the
raster; and one speed by hand."""

import math

import numpy as np
import pytest
from affine import Affine

from usvtool.sim.weather import KNOT, FieldWeather, Weather

from . import libm


def numpy_speeds(w: FieldWeather, *args):
    """The NumPy path: :meth:`Weather.attainable_speed` (conditions from ``at``, then eq. 5)."""
    return Weather.attainable_speed(w, *args)


def random_field(rng, wave_height: bool, wave_from: bool, outside: str) -> FieldWeather:
    """A random (k, rows, cols) field of 1-7 x 1-9 cells, wind components -8..8 m/s, on a
    north-up raster of 5-20 m cells."""
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
def test_same_bits_as_numpy(outside, wave_height, wave_from):
    rng = np.random.default_rng([7, wave_height, wave_from, outside == "calm"])
    for _ in range(20):
        w = random_field(rng, wave_height, wave_from, outside)
        n = 300
        v = rng.uniform(-1, 8, n)
        v[:5] = 0.0
        heading = rng.uniform(-7, 7, n)
        x, y = rng.uniform(-80, 200, n), rng.uniform(-80, 200, n)
        for dwt in (None, 20.0, 5e5):
            got = w.attainable_speed(v, heading, x, y, dwt)
            want = numpy_speeds(w, v, heading, x, y, dwt)
            libm.assert_close_bits(got, want)


def test_broadcast_strided_and_scalar_arguments():
    rng = np.random.default_rng(3)
    w = random_field(rng, False, False, "nearest")
    end = rng.uniform(0, 60, 40) + 1j * rng.uniform(0, 60, 40)  # .real, .imag are strided
    heading = rng.uniform(-3, 3, (3, 1))
    got = w.attainable_speed(4.0, heading, end.real, end.imag, 20.0)
    want = numpy_speeds(w, 4.0, heading, end.real, end.imag, 20.0)
    assert got.shape == (3, 40)
    libm.assert_close_bits(got, want)
    one = w.attainable_speed(3.0, 0.5, 10.0, 20.0)
    assert one.shape == ()
    libm.assert_close_bits(one, numpy_speeds(w, 3.0, 0.5, 10.0, 20.0))


def test_hand_case_head_wind():
    """A uniform 6 m/s wind from the east (u = -6, force 4, Table 2's 1.0 m waves) on a ship
    heading east at 5 m/s: eq. 5 costs 1.08 + 2.77e-3·6 knots (Δ = 0)."""
    layers = np.stack([np.full((2, 2), -6.0), np.zeros((2, 2))])
    w = FieldWeather(layers, Affine(10.0, 0.0, 0.0, 0.0, -10.0, 20.0), False, False)
    want = (5.0 / KNOT - (1.08 + 2.77e-3 * 6.0)) * KNOT
    assert float(w.attainable_speed(5.0, 0.0, 7.0, 13.0)) == pytest.approx(want, abs=1e-12)
