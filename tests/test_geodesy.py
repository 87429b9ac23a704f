"""Geodesy: UTM zones, geodesic lengths, lon/lat <-> map."""

import numpy as np
import pytest
from pyproj import Geod, Transformer

from usvtool.geodesy import geodesic_length, lonlat_to_map, map_to_lonlat, utm_crs


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
