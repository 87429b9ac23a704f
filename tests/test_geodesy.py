"""Geodesy and compass angles: UTM zones, geodesic lengths, lon/lat <-> map, compass <-> radians."""

import math

import numpy as np
import pytest
from pyproj import Geod, Transformer

from usvtool.geodesy import (
    compass_to_math,
    geodesic_length,
    lonlat_to_map,
    map_to_lonlat,
    math_to_compass,
    utm_crs,
    wrap_deg,
)


def test_utm_zone_of_boston_and_head_of_passes():
    assert utm_crs(-71.0, 42.3).to_epsg() == 32619
    assert utm_crs(-89.26, 29.15).to_epsg() == 32616
    assert utm_crs(18.4, -33.9).to_epsg() == 32734


def test_geodesic_lengths_against_known_wgs84_arcs():
    # one degree of latitude from the equator: 110 574.389 m; of longitude on it: 111 319.491 m
    assert geodesic_length([0, 0], [0, 1]) == pytest.approx(110574.389, abs=0.01)
    assert geodesic_length([0, 1], [0, 0]) == pytest.approx(111319.491, abs=0.01)
    # a polyline is the sum of its legs, as pyproj's Geod.inv gives them
    lon, lat = [-71.05, -71.0, -70.95], [42.30, 42.32, 42.28]
    legs = Geod(ellps="WGS84").inv(lon[:-1], lat[:-1], lon[1:], lat[1:])[2]
    assert geodesic_length(lon, lat) == pytest.approx(sum(legs), rel=1e-12)



def test_lonlat_to_map_and_back_agree_with_pyproj():
    crs = utm_crs(-70.93, 42.32)
    lon, lat = np.array([-70.93391, -70.79426]), np.array([42.32119, 42.31806])
    x, y = lonlat_to_map(crs, lon, lat)
    ex, ey = Transformer.from_crs(4326, 32619, always_xy=True).transform(lon, lat)
    np.testing.assert_allclose(x, ex, atol=1e-6)
    np.testing.assert_allclose(y, ey, atol=1e-6)
    back = map_to_lonlat(crs, x, y)
    np.testing.assert_allclose(back, (lon, lat), atol=1e-10)
    point = lonlat_to_map("EPSG:32619", -70.93391, 42.32119)  # scalars give floats
    assert type(point[0]) is float and point == pytest.approx((ex[0], ey[0]), abs=1e-6)


@pytest.mark.parametrize(
    ("compass", "radians"),
    [(0, math.pi / 2), (45, math.pi / 4), (90, 0.0), (135, -math.pi / 4), (180, -math.pi / 2),
     (225, -3 * math.pi / 4), (270, math.pi), (315, 3 * math.pi / 4), (360, math.pi / 2),
     (-90, math.pi), (450, 0.0)],  # fmt: skip
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


def test_wrap_deg():
    a = np.array([-540.0, -180.0, -179.5, 0.0, 180.0, 181.0, 359.0, 540.0])
    np.testing.assert_array_equal(wrap_deg(a), [180.0, 180.0, -179.5, 0.0, 180.0, -179.0, -1.0,
                                                180.0])  # fmt: skip
    assert wrap_deg(-0.0) == 0.0 and math.copysign(1, wrap_deg(-0.0)) == 1
