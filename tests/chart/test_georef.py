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
from usvtool.errors import UsvError
from usvtool.grid import NAVIGABLE, OBSTACLE, read_grid


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


# ---- rotated and sheared geotransforms: warped north-up over the whole footprint -------------

WATER, LAND = (212, 234, 238), (201, 185, 122)
ROWS, COLS = 120, 160  # the test chart's size in pixels
SQUARE = (slice(40, 60), slice(70, 90))  # the land square's rows and columns: centre (80, 50)
X0, Y0 = 300000.0, 3300000.0  # UTM 16N, near Head of Passes


def affine_chart(path, transform, crs="EPSG:32616"):
    """A ROWS x COLS RGB GeoTIFF of water with the land square at SQUARE, georeferenced by
    ``transform`` (any affine: rotated, sheared, flipped)."""
    img = np.empty((3, ROWS, COLS), np.uint8)
    img[:] = np.array(WATER, np.uint8)[:, None, None]
    img[(slice(None), *SQUARE)] = np.array(LAND, np.uint8)[:, None, None]
    with rasterio.open(path, "w", driver="GTiff", width=COLS, height=ROWS, count=3,
                       dtype="uint8", crs=crs, transform=transform) as ds:
        ds.write(img)
    return path


def geo(gt, col, row):
    """GDAL's geotransform formula written out: Xp = GT0 + col GT1 + row GT2, Yp = GT3 + col GT4
    + row GT5."""
    x0, a, b, y0, d, e = gt
    return x0 + col * a + row * b, y0 + col * d + row * e


def corners_bbox(points):
    xs, ys = zip(*points, strict=True)
    return min(xs), min(ys), max(xs), max(ys)


def land_centroid(chart):
    """Map position of the centre of the warped chart's land pixels, and their area (m^2)."""
    rows, cols = np.nonzero((chart.rgb == LAND).all(axis=2) & chart.valid)
    t = chart.frame.transform
    return t @ (cols.mean() + 0.5, rows.mean() + 0.5), rows.size * t.a * t.a


def check_warped(chart, bbox, centre, area, land_area):
    """The warped chart is north-up with square pixels, its frame covers ``bbox`` (the
    footprint's, by hand) to within a millimetre, its valid pixels hold ``area`` m^2 and its
    land square ``land_area`` m^2 (nearest-neighbour: to a few per cent), centred at ``centre``
    within a pixel."""
    t = chart.frame.transform
    assert t.b == t.d == 0 and t.e == -t.a
    left, bottom, right, top = chart.frame.bounds
    assert left <= bbox[0] + 1e-3 and bottom <= bbox[1] + 1e-3
    assert right >= bbox[2] - 1e-3 and top >= bbox[3] - 1e-3
    assert right - left <= bbox[2] - bbox[0] + 2 * t.a  # and not much more
    assert top - bottom <= bbox[3] - bbox[1] + 2 * t.a
    assert chart.valid.sum() * t.a**2 == pytest.approx(area, rel=0.03)
    (x, y), found = land_centroid(chart)
    assert found == pytest.approx(land_area, rel=0.1)
    assert np.hypot(x - centre[0], y - centre[1]) < t.a


def test_a_30_degree_rotated_geotiff_gives_a_grid_over_its_whole_footprint(tmp_path, usv):
    # Affine.rotation(30) * scale(2, -2): a = 2 cos 30 = 1.7320508, b = d = 2 sin 30 = 1,
    # e = -1.7320508 (2 m pixels, 30 deg anticlockwise). Corners (col, row) -> (x, y) - (X0, Y0):
    # (0, 0) -> (0, 0); (160, 0) -> (277.128, 160); (0, 120) -> (120, -207.846);
    # (160, 120) -> (397.128, -47.846). Footprint bbox: x X0 .. X0 + 397.128, y Y0 - 207.846 ..
    # Y0 + 160; area 160 x 120 x 4 = 76 800 m^2. The land square's centre (80, 50) ->
    # (80 x 1.7320508 + 50, 80 - 50 x 1.7320508) = (188.564, -6.603); area 40 x 40 m.
    t = Affine.translation(X0, Y0) @ Affine.rotation(30) @ Affine.scale(2, -2)
    gt = (X0, 1.7320508, 1.0, Y0, 1.0, -1.7320508)
    assert np.allclose(t.to_gdal(), gt)
    path = affine_chart(tmp_path / "rotated.tif", t)
    bbox = (X0, Y0 - 207.846, X0 + 397.128, Y0 + 160)
    centre = (X0 + 188.564, Y0 - 6.603)

    chart = read_raster(path)
    check_warped(chart, bbox, centre, 76800, 1600)
    assert chart.frame.transform.a == pytest.approx(2.0)  # GDAL's suggestion: the pixel's size
    assert chart.frame.crs.to_epsg() == 32616

    out = tmp_path / "grid.tif"
    r = usv("preprocess", path, "-o", out, "--cell-size", 4, "--no-swell")
    assert r.exit_code == 0, r.stderr
    grid = read_grid(out)
    left, bottom, right, top = grid.bounds
    assert left <= bbox[0] + 1e-3 and bottom <= bbox[1] + 1e-3  # before: y 3 299 951 .. 3 300 003
    assert right >= bbox[2] - 1e-3 and top >= bbox[3] - 1e-3
    assert grid.cells[grid.cell_of(*centre)] == OBSTACLE  # the land square
    assert grid.cells[grid.cell_of(*geo(gt, 20, 100))] == NAVIGABLE  # water, lower left
    assert grid.cells[grid.cell_of(*geo(gt, 140, 15))] == NAVIGABLE  # water, upper right
    # inside the bbox, outside the footprint (its left edge is at x X0 + 115.5 at y Y0 - 200)
    assert grid.cells[grid.cell_of(X0 + 5, Y0 - 200)] == OBSTACLE


def test_a_sheared_geotiff_is_warped_over_its_footprint(tmp_path):
    # x = X0 + 2 col + 0.8 row, y = Y0 + 0.3 col - 2 row: corners (0, 0), (320, 48), (96, -240),
    # (416, -192); bbox x 0 .. 416, y -240 .. 48; pixel area |2 x -2 - 0.8 x 0.3| = 4.24 m^2,
    # chart 160 x 120 x 4.24 = 81 408 m^2, land 400 x 4.24 = 1696 m^2; the land centre (80, 50)
    # -> (160 + 40, 24 - 100) = (200, -76).
    gt = (X0, 2.0, 0.8, Y0, 0.3, -2.0)
    chart = read_raster(affine_chart(tmp_path / "sheared.tif", Affine.from_gdal(*gt)))
    check_warped(chart, (X0, Y0 - 240, X0 + 416, Y0 + 48), (X0 + 200, Y0 - 76), 81408, 1696)


def random_transforms(seed=22, n=6):
    """Seeded affines: a rotation anywhere in the circle, pixels of 1 to 3 m (not always square),
    a shear of up to 20 degrees, and now and then a mirror (a south-up raster)."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        sx, sy = rng.uniform(1, 3, 2)
        mirror = rng.random() < 0.3
        yield (Affine.translation(X0, Y0) @ Affine.rotation(rng.uniform(-180, 180))
               @ Affine.shear(rng.uniform(-20, 20), 0) @ Affine.scale(sx, sy if mirror else -sy))


@pytest.mark.parametrize("k", range(6))
def test_seeded_random_affine_geotiffs_are_warped_over_their_footprints(tmp_path, k):
    t = list(random_transforms())[k]
    gt = t.to_gdal()
    corners = [geo(gt, c, r) for c in (0, COLS) for r in (0, ROWS)]
    pixel_area = abs(gt[1] * gt[5] - gt[2] * gt[4])
    chart = read_raster(affine_chart(tmp_path / "affine.tif", t))
    check_warped(chart, corners_bbox(corners), geo(gt, 80, 50), ROWS * COLS * pixel_area,
                 400 * pixel_area)


def test_a_rotated_lon_lat_geotiff_is_warped_to_utm_over_its_footprint(tmp_path):
    # 2e-5 deg pixels (2.2 m north, 1.9 m east) at Head of Passes, rotated 25 deg; positions
    # projected to UTM 16N by pyproj, point by point
    t = Affine.translation(*HOP) @ Affine.rotation(25) @ Affine.scale(2e-5, -2e-5)
    gt = t.to_gdal()
    to_utm = Transformer.from_crs(4326, 32616, always_xy=True)
    corners = [to_utm.transform(*geo(gt, c, r)) for c in (0, COLS) for r in (0, ROWS)]
    xs, ys = np.array(corners).T
    quad = xs[[0, 1, 3, 2]], ys[[0, 1, 3, 2]]  # (0, 0), (0, ROWS), (COLS, ROWS), (COLS, 0)
    area = 0.5 * abs(np.dot(quad[0], np.roll(quad[1], 1)) - np.dot(quad[1], np.roll(quad[0], 1)))
    chart = read_raster(affine_chart(tmp_path / "lonlat.tif", t, crs="EPSG:4326"))
    assert chart.frame.crs.to_epsg() == 32616
    check_warped(chart, corners_bbox(corners), to_utm.transform(*geo(gt, 80, 50)), area,
                 area * 400 / (ROWS * COLS))


def test_a_degenerate_geotransform_is_refused(tmp_path):
    path = affine_chart(tmp_path / "flat.tif", Affine(2, 4, X0, 1, 2, Y0))  # determinant 0
    with pytest.raises(UsvError, match=r"flat.tif: .*geotransform .*degenerate"):
        read_raster(path)
