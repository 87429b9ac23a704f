"""Georeferencing: UTM zones, a known pixel through a lon/lat GeoTIFF, geodesic lengths."""

import numpy as np
import pytest
import rasterio
from affine import Affine
from pyproj import Geod, Transformer

from usvtool.chart.georef import frame_for_bounds, geodesic_length, utm_crs
from usvtool.chart.sources import read_raster


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


def test_frame_covers_bounds_from_the_lower_left():
    f = frame_for_bounds((100, 200, 130.5, 210), 10)
    assert (f.width, f.height) == (4, 1)
    assert f.bounds == (100, 200, 140, 210)


def test_a_known_pixel_of_a_lon_lat_geotiff_lands_at_its_utm_position(tmp_path):
    # a 0.01 degree chart near Boston, 200 x 200 px, with one red pixel at a known lon/lat
    res = 0.00005
    west, north = -71.05, 42.32
    img = np.full((3, 200, 200), 230, np.uint8)
    img[:, 120, 70] = (255, 0, 0)
    path = tmp_path / "chart.tif"
    profile = dict(driver="GTiff", width=200, height=200, count=3, dtype="uint8",
                   crs="EPSG:4326", transform=Affine(res, 0, west, 0, -res, north))
    with rasterio.open(path, "w", **profile) as ds:
        ds.write(img)
    lon, lat = west + 70.5 * res, north - 120.5 * res  # the red pixel's centre

    chart = read_raster(path)
    assert chart.frame.crs.to_epsg() == 32619
    rows, cols = np.nonzero((chart.rgb == (255, 0, 0)).all(axis=2))
    t = chart.frame.transform
    x, y = t @ (cols.mean() + 0.5, rows.mean() + 0.5)
    ex, ey = Transformer.from_crs(4326, 32619, always_xy=True).transform(lon, lat)
    assert abs(x - ex) < 1.5 * t.a and abs(y - ey) < 1.5 * t.a  # within a pixel and a half
    assert t.a == pytest.approx(-t.e)  # square pixels
