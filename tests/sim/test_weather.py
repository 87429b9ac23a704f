"""Wind and waves: Beaufort and UDWA Table 2, the speed loss of UDWA eq. 5, field rasters."""

import math

import numpy as np
import pytest
from affine import Affine

from usvtool.errors import UsvError
from usvtool.sim.weather import (
    CALM,
    KNOT,
    attainable_speed,
    beaufort,
    off_bow,
    read_weather,
    uniform,
    wave_height,
)


def _math(compass_deg):
    return math.pi / 2 - math.radians(compass_deg)


# -- Beaufort and Table 2 ---------------------------------------------------------------------


@pytest.mark.parametrize(
    "speed, force",
    [
        (0.0, 0),
        (0.2, 0),
        (0.24, 0),
        (0.25, 1),
        (0.3, 1),
        (1.5, 1),
        (1.6, 2),
        (3.3, 2),
        (3.4, 3),
        (5.4, 3),
        (5.5, 4),
        (7.0, 4),
        (7.9, 4),
        (8.0, 5),
        (10.8, 6),
        (32.6, 11),
        (32.7, 12),
    ],
)
def test_beaufort_wmo_limits(speed, force):
    assert int(beaufort(speed)) == force


@pytest.mark.parametrize(
    "speed, height",
    [
        (0.1, 0.0),
        (0.3, 0.1),
        (1.5, 0.1),
        (1.6, 0.2),
        (3.3, 0.2),
        (3.4, 0.6),
        (5.4, 0.6),
        (5.5, 1.0),
        (7.0, 1.0),
        (8.0, 2.0),
    ],
)
def test_wave_height_table_2(speed, height):
    assert float(wave_height(speed)) == height


def test_wave_height_is_vectorised():
    assert wave_height(np.array([[0.0, 2.0], [4.0, 6.0]])).tolist() == [[0.0, 0.2], [0.6, 1.0]]


# -- eq. 5 ------------------------------------------------------------------------------------


def test_eq5_hand_case():
    # V = 6 m/s = 6 * 3600 / 1852 = 11.6630670 kn; h = 0.6 m, F = 4 m/s, D = 20 t;
    # the waves 60 deg on the starboard bow, the wind 60 deg on the port bow: q = eps = pi/3
    # 1.08 h = 0.648;  0.126 q h = 0.126 * 1.0471976 * 0.6 = 0.0791681;
    # 2.77e-3 F cos eps = 2.77e-3 * 4 * 0.5 = 0.00554;  sum = 0.5743719
    # 1 - 2.33e-7 * 20 * 11.6630670 = 0.99994565;  loss = 0.5743406 kn
    # V_a = 11.6630670 - 0.5743406 = 11.0887264 kn = 5.7045336 m/s
    heading = _math(0.0)  # north
    va = attainable_speed(6.0, heading, 4.0, _math(300.0), 0.6, _math(60.0), 20.0)
    assert float(va) == pytest.approx(11.0887264 * KNOT, abs=1e-6)
    assert float(va) == pytest.approx(5.7045336, abs=1e-6)


def test_head_seas_lose_more_than_beam_and_following():
    # 7 m/s in force 4 (7 m/s wind, 1 m waves): head 1.099 kn, beam 0.882 kn, following 0.665 kn
    off = np.radians([0.0, 90.0, 180.0])
    va = attainable_speed(7.0, 0.0, 7.0, off, 1.0, off, 20.0)
    loss_kn = (7.0 - va) / KNOT
    assert loss_kn == pytest.approx([1.0993, 0.8820, 0.6647], abs=1e-4)


def test_eq5_vectorised_over_headings():
    headings = np.linspace(-np.pi, np.pi, 361)
    va = attainable_speed(5.0, headings, 6.0, 0.0, None, None, 20.0)  # Table 2: h = 1.0 m
    assert va.shape == (361,)
    assert headings[np.argmin(va)] == pytest.approx(0.0)  # into the wind
    assert abs(headings[np.argmax(va)]) == pytest.approx(np.pi)  # before it
    assert np.allclose(va, va[::-1])  # port and starboard alike


def test_eq5_calm_slow_and_stopped():
    assert float(attainable_speed(5.0, 1.0, 0.0, 0.0, 0.0, 0.0, 20.0)) == 5.0
    assert float(attainable_speed(0.2, 0.0, 7.0, 0.0, 1.0, 0.0, 20.0)) == 0.0  # clipped at 0
    assert float(attainable_speed(0.0, 0.0, 7.0, np.pi, 1.0, np.pi, 20.0)) == 0.0


def test_off_bow():
    assert off_bow([0.1, -3.0, 3.0], [0.1, 3.0, -3.0]) == pytest.approx(
        [0.0, 2 * np.pi - 6, 2 * np.pi - 6]
    )


# -- uniform weather --------------------------------------------------------------------------


def test_uniform_weather():
    w = uniform(6.0, 90.0)  # from the east, force 4
    c = w.at(np.zeros((2, 3)), 5.0)
    assert c.wind_speed.shape == (2, 3) and (c.wind_speed == 6.0).all()
    assert np.allclose(c.wind_from, 0.0) and np.allclose(c.wave_from, 0.0)
    assert (c.wave_height == 1.0).all()
    # a ship heading east meets it head on
    assert w.attainable_speed(5.0, 0.0, 0.0, 0.0, 20.0) == attainable_speed(
        5.0, 0.0, 6.0, 0.0, 1.0, 0.0, 20.0
    )
    assert uniform(6.0, 90.0, 0.3, 180.0).at(0, 0).wave_from == pytest.approx(_math(180.0))
    assert float(CALM.attainable_speed(4.0, 2.0, 0.0, 0.0)) == 4.0


@pytest.mark.parametrize(
    "args, text",
    [
        ((-1.0, 0.0), "wind_speed must be >= 0, not -1.0"),
        ((float("nan"), 0.0), "wind_speed must be finite, not nan"),
        ((3.0, "N"), "wind_from must be a number, not 'N'"),
        ((3.0, 0.0, -0.5), "wave_height must be >= 0, not -0.5"),
    ],
)
def test_uniform_refuses_bad_values(args, text):
    with pytest.raises(UsvError, match=rf"^s\.yaml: weather: {text}$"):
        uniform(*args, where="s.yaml: weather")


# -- field rasters ----------------------------------------------------------------------------

# A 2 x 2 field of 100 m cells over (0, 0)-(200, 200); cell centres x = 50, 150, y = 150, 50.
# NW: 2 m/s from the north (u, v = 0, -2)   NE: 4 m/s from the west (4, 0)
# SW: 6 m/s from the east (-6, 0)           SE: 8 m/s from the south (0, 8)
TRANSFORM = Affine(100, 0, 0, 0, -100, 200)
SPEED = np.array([[2.0, 4.0], [6.0, 8.0]])
FROM = np.array([[0.0, 270.0], [90.0, 180.0]])
U = np.array([[0.0, 4.0], [-6.0, 0.0]])
V = np.array([[-2.0, 0.0], [0.0, 8.0]])
# Hand values: (x, y) -> (speed, compass from)
# NW centre: 2 from 0; midway NW-NE (u, v = 2, -1): sqrt(5) from WNW, atan2(-2, 1) = 296.565 deg;
# the middle (u, v = -0.5, 1.5): sqrt(2.5) from atan2(0.5, -1.5) = 161.565 deg
POINTS = ([50.0, 100.0, 100.0], [150.0, 150.0, 100.0])
EXPECTED_SPEED = [2.0, math.sqrt(5.0), math.sqrt(2.5)]
EXPECTED_FROM = [0.0, 360 + math.degrees(math.atan2(-2, 1)), math.degrees(math.atan2(0.5, -1.5))]


def _write_tif(path, bands, descriptions=None, crs=None, nodata=None):
    import rasterio

    bands = np.asarray(bands, "float32")
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        width=bands.shape[2],
        height=bands.shape[1],
        count=bands.shape[0],
        dtype="float32",
        transform=TRANSFORM,
        crs=crs,
        nodata=nodata,
    ) as ds:
        ds.write(bands)
        if descriptions:
            ds.descriptions = descriptions
    return path


@pytest.fixture
def uv_tif(tmp_path):
    return _write_tif(tmp_path / "uv.tif", [U, V], ("u", "v"), crs="EPSG:32619")


@pytest.fixture
def speed_tif(tmp_path):
    return _write_tif(tmp_path / "speed.tif", [FROM, SPEED], ("wind_from", "wind_speed"))


def _check_hand_values(weather):
    c = weather.at(*POINTS)
    assert c.wind_speed == pytest.approx(EXPECTED_SPEED, abs=1e-9)
    expected = [_math(d) for d in EXPECTED_FROM]
    assert off_bow(c.wind_from, expected) == pytest.approx([0, 0, 0], abs=1e-9)
    # no wave band: Table 2 of the wind (2 m/s and 1.58 m/s are both force 2)
    assert c.wave_height.tolist() == [0.2, 0.2, 0.2]
    assert np.allclose(c.wave_from, c.wind_from)


def test_uv_geotiff(uv_tif):
    _check_hand_values(read_weather(uv_tif))


def test_speed_direction_geotiff(speed_tif):
    _check_hand_values(read_weather(speed_tif))


def test_both_forms_agree_everywhere(uv_tif, speed_tif):
    x, y = np.meshgrid(np.linspace(-50, 250, 13), np.linspace(-50, 250, 11))
    a, b = read_weather(uv_tif).at(x, y), read_weather(speed_tif).at(x, y)
    assert a.wind_speed.shape == (11, 13)
    assert np.allclose(a.wind_speed, b.wind_speed, atol=1e-9)
    moving = a.wind_speed > 1e-6
    assert np.allclose(off_bow(a.wind_from, b.wind_from)[moving], 0, atol=1e-6)


def test_outside_nearest_or_calm(uv_tif):
    far = ([-1000.0, 1000.0], [-1000.0, 100.0])  # beyond the SW corner; east of the field
    c = read_weather(uv_tif).at(*far)
    # SW cell (6 from the east); east edge midway between NE and SE: (u, v) = (2, 4)
    assert c.wind_speed == pytest.approx([6.0, math.sqrt(20.0)])
    assert c.wind_from[0] == pytest.approx(0.0)
    calm = read_weather(uv_tif, outside="calm").at(*far)
    assert calm.wind_speed.tolist() == [0.0, 0.0] and calm.wave_height.tolist() == [0.0, 0.0]
    assert read_weather(uv_tif, outside="calm").at(199.0, 1.0).wind_speed == pytest.approx(8.0)


def test_wave_bands(tmp_path):
    heights = np.array([[0.5, 1.5], [1.0, 2.0]])
    wave_from = np.full((2, 2), 45.0)
    path = _write_tif(
        tmp_path / "w.tif",
        [SPEED, FROM, heights, wave_from],
        ("wind_speed", "wind_from", "wave_height", "wave_from"),
    )
    c = read_weather(path).at([100.0, 150.0], [100.0, 50.0])
    assert c.wave_height == pytest.approx([1.25, 2.0])
    assert c.wave_from == pytest.approx([_math(45.0)] * 2)


def test_bands_option_and_unnamed_bands(tmp_path):
    path = _write_tif(tmp_path / "plain.tif", [U, V])
    with pytest.raises(UsvError, match="no wind bands among 2"):
        read_weather(path)
    _check_hand_values(read_weather(path, bands=("u", "v")))
    with pytest.raises(UsvError, match="bands names 1 band"):
        read_weather(path, bands=("u",))


def test_nodata_cells_are_calm(tmp_path):
    u = U.copy()
    u[1, 0] = -9999.0  # SW
    path = _write_tif(tmp_path / "nd.tif", [u, V], ("u", "v"), nodata=-9999.0)
    assert float(read_weather(path).at(50.0, 50.0).wind_speed) == 0.0


def test_negative_speed_refused(tmp_path):
    path = _write_tif(tmp_path / "neg.tif", [SPEED - 3, FROM], ("wind_speed", "wind_from"))
    with pytest.raises(UsvError, match=r"neg\.tif: wind_speed must be >= 0, the raster has -1"):
        read_weather(path)


def test_crs_mismatch_refused(uv_tif, speed_tif):
    read_weather(uv_tif, crs="EPSG:32619")
    with pytest.raises(UsvError, match=r"CRS EPSG:32619 is not the chart's EPSG:32618"):
        read_weather(uv_tif, crs="EPSG:32618")
    read_weather(speed_tif, crs="EPSG:32618")  # no CRS: taken to be in the chart's frame


def test_a_rotated_field_is_refused(tmp_path):
    path = _write_tif(tmp_path / "r.tif", [U, V], ("u", "v"))
    import rasterio

    with rasterio.open(path, "r+") as ds:
        ds.transform = TRANSFORM @ Affine.rotation(30)
    with pytest.raises(UsvError, match=r"r\.tif: a rotated or sheared geotransform; warp"):
        read_weather(path)


def test_unreadable_file(tmp_path):
    path = tmp_path / "junk.tif"
    path.write_bytes(b"this is not a raster\n" * 10)
    with pytest.raises(UsvError) as e:
        read_weather(path)
    assert str(e.value).startswith(f"{path}: not a readable raster") and "\n" not in str(e.value)
    with pytest.raises(UsvError, match="no such file"):
        read_weather(tmp_path / "missing.tif")


def test_netcdf_field(tmp_path):
    from rasterio.env import Env

    with Env() as env:
        if "netCDF" not in env.drivers():
            pytest.skip("rasterio's GDAL has no netCDF driver")
    # rasterio will not create NetCDF ("w" mode is blacklisted): write a CF file with scipy
    from scipy.io import netcdf_file

    path = tmp_path / "wind.nc"
    f = netcdf_file(path, "w")
    f.createDimension("y", 2)
    f.createDimension("x", 2)
    for name, values in (("x", [50.0, 150.0]), ("y", [150.0, 50.0])):
        var = f.createVariable(name, "f8", (name,))
        var[:] = values
        var.standard_name = f"projection_{name}_coordinate"
        var.units = "m"
    for name, values in (("u10", U), ("v10", V)):
        var = f.createVariable(name, "f4", ("y", "x"))
        var[:] = values
        var.units = "m s-1"
    f.close()
    weather = read_weather(path)
    assert weather.transform == TRANSFORM
    _check_hand_values(weather)
