"""Raster frames: bounds, a known pixel through a lon/lat GeoTIFF, scale errors, kept frames.

UTM zones and geodesic lengths (:mod:`usvtool.geodesy`) are tested in tests/test_geodesy.py.
"""

import numpy as np
import pytest
import rasterio
from affine import Affine
from pyproj import Transformer

from usvtool.chart.georef import frame_for_bounds
from usvtool.chart.sources import read_raster


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



def frame_at(crs, lon, lat, res=10.0, size=500):
    """A ``size`` x ``size`` north-up frame of ``res`` m pixels centred on (lon, lat) in ``crs``."""
    from rasterio.crs import CRS

    from usvtool.chart.georef import Frame

    crs = CRS.from_user_input(crs)
    x, y = Transformer.from_crs(4326, crs, always_xy=True).transform(lon, lat)
    half = res * size / 2
    return Frame(Affine(res, 0, x - half, 0, -res, y + half), size, size, crs)


HOP = (-89.26, 29.15)  # Head of Passes, in UTM zone 16 (central meridian 87 W)


@pytest.mark.parametrize(
    ("crs", "expected", "tol"),
    [
        # transverse Mercator: k = k0 (1 + (1 + C) A^2 / 2 + ...), A = dlon cos(lat),
        # C = e'^2 cos^2(lat) = 0.00514, k0 = 0.9996
        ("EPSG:32616", 0.000196, 2e-6),  # dlon 2.26 deg: A = 0.03445, k = 1.000196
        ("EPSG:32617", 0.00760, 5e-5),  # dlon 8.26 deg: A = 0.1259, k = 1.00760 (A^4 term 4e-5)
        ("EPSG:3857", 1 / np.cos(np.radians(29.15)) - 1, 1e-4),  # sphere formula 1 / cos(lat)
        ("+proj=merc +lat_ts=29.15 +datum=WGS84", 0.0, 1e-6),  # true to scale at the point
    ],
)
def test_scale_error_against_the_projection_formulas(crs, expected, tol):
    from usvtool.chart.georef import scale_error

    assert scale_error(frame_at(crs, *HOP, res=1.0, size=10)) == pytest.approx(expected, abs=tol)


@pytest.mark.parametrize(
    ("crs", "kept"),
    [
        ("EPSG:32616", True),  # the chart's own UTM zone
        ("EPSG:32615", True),  # the next zone west: 3.74 deg from its meridian, k = 1.0012
        ("EPSG:32617", False),  # two zones east: k = 1.0076
        ("EPSG:3857", False),  # Web Mercator: 14.5 %
        ("EPSG:3395", False),  # World Mercator, true at the equator: 14.4 %
        ("+proj=merc +lat_ts=29.15 +datum=WGS84", True),  # a Mercator true at the chart
        ("+proj=poly +lon_0=-95 +lat_0=29 +datum=WGS84", False),  # polyconic 5.7 deg off: 0.39 %
        ("EPSG:3452", False),  # Louisiana South State Plane, in US survey feet
        ("EPSG:4326", False),  # not projected
    ],
)
def test_which_source_crs_is_kept_as_the_charts_frame(crs, kept):
    from usvtool.chart.sources import keeps_frame

    assert keeps_frame(frame_at(crs, *HOP, res=1.0, size=5000)) is kept  # a 5 km chart


def test_a_known_pixel_of_a_far_utm_zone_geotiff_lands_in_its_own_zone(tmp_path):
    # 5 m pixels in UTM 17N around Head of Passes (UTM 16N): scale 1.0076, so warped to 16N
    lon, lat = HOP
    frame = frame_at("EPSG:32617", lon, lat, res=5.0, size=200)
    img = np.full((3, 200, 200), 230, np.uint8)
    x17, y17 = Transformer.from_crs(4326, 32617, always_xy=True).transform(lon, lat)
    col, row = ~frame.transform @ (x17, y17)
    img[:, int(row), int(col)] = (255, 0, 0)
    centre = frame.transform @ (int(col) + 0.5, int(row) + 0.5)  # the red pixel's centre
    path = tmp_path / "utm17.tif"
    with rasterio.open(path, "w", driver="GTiff", width=200, height=200, count=3, dtype="uint8",
                       crs="EPSG:32617", transform=frame.transform) as ds:
        ds.write(img)

    chart = read_raster(path)
    assert chart.frame.crs.to_epsg() == 32616
    rows, cols = np.nonzero((chart.rgb == (255, 0, 0)).all(axis=2))
    t = chart.frame.transform
    x, y = t @ (cols.mean() + 0.5, rows.mean() + 0.5)
    ex, ey = Transformer.from_crs(32617, 32616, always_xy=True).transform(*centre)
    assert abs(x - ex) < 1.5 * t.a and abs(y - ey) < 1.5 * t.a
    assert t.a == pytest.approx(-t.e)
