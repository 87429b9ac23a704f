"""S-52 rendering of the NOAA cell US5MA12M and its land truth, at a coarse 40 m resolution."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from usvtool.chart.rendering import (
    COLOURS,
    chart_frame,
    render_cell,
    sounding_text,
    write_chart,
    write_truth,
)
from usvtool.chart.s57 import read_cell
from usvtool.errors import UsvError
from usvtool.geodesy import WGS84, transformer

CELL = Path(__file__).resolve().parents[2] / "charts" / "noaa" / "US5MA12M.000"
RESOLUTION = 40.0

THOMPSON_ISLAND = (-71.0106, 42.3148)
LONG_ISLAND = (-70.9665, 42.3193)
NANTASKET_ROADS = (-70.9219, 42.3122)  # dredged to 11.0 m
MASS_BAY_DEEP = (-70.7419, 42.3153)  # DEPARE 36.5-45.7 m
BETWEEN_STRIPS = (-70.9, 42.26)  # outside the CATCOV=1 coverage


@pytest.fixture(scope="module")
def cell():
    return read_cell(CELL)


@pytest.fixture(scope="module")
def plain(cell):
    return render_cell(cell, RESOLUTION, soundings=False)


@pytest.fixture(scope="module")
def cluttered(cell):
    return render_cell(cell, RESOLUTION)


def pixel(frame, lon, lat) -> tuple[int, int]:
    x, y = transformer(WGS84, frame.crs).transform(lon, lat)
    col, row = ~frame.transform @ (x, y)
    return int(row), int(col)


def colour_at(rgb, frame, point) -> tuple[int, ...]:
    return tuple(int(v) for v in rgb[(slice(None), *pixel(frame, *point))])


def is_colour(rgb, name) -> np.ndarray:
    return (rgb == np.array(COLOURS[name], dtype=np.uint8)[:, None, None]).all(axis=0)


def test_frame_is_utm_coverage_bounds(plain):
    rgb, truth, frame = plain
    assert frame.crs.to_epsg() == 32619 and frame.resolution == RESOLUTION
    assert (frame.width, frame.height) == (692, 315)  # 27.7 km x 12.6 km
    assert rgb.shape == (3, frame.height, frame.width) and rgb.dtype == np.uint8
    assert truth.shape == (frame.height, frame.width) and truth.dtype == np.uint8
    assert set(np.unique(truth)) == {0, 1, 255}


def test_known_points(plain):
    rgb, truth, frame = plain
    for point in (THOMPSON_ISLAND, LONG_ISLAND):
        assert truth[pixel(frame, *point)] == 1
        assert colour_at(rgb, frame, point) == COLOURS["LANDA"]
    assert truth[pixel(frame, *NANTASKET_ROADS)] == 0
    assert colour_at(rgb, frame, NANTASKET_ROADS) == COLOURS["DEPMD"]  # 10 <= 11.0 < 30
    assert colour_at(rgb, frame, MASS_BAY_DEEP) == COLOURS["DEPDW"]
    assert truth[pixel(frame, *BETWEEN_STRIPS)] == 255
    assert colour_at(rgb, frame, BETWEEN_STRIPS) == COLOURS["NODTA"]


def test_land_colour_is_the_truth(plain):
    rgb, truth, _ = plain
    land = is_colour(rgb, "LANDA")
    assert not (land & (truth != 1)).any()  # no land colour off the land polygons
    assert (land & (truth == 1)).sum() / (truth == 1).sum() > 0.95  # lines cover the rest
    assert is_colour(rgb, "NODTA")[truth == 255].all()
    assert 0.15 < (truth == 1).sum() / (truth != 255).sum() < 0.3


def test_only_palette_colours_no_antialiasing(cluttered):
    rgb = cluttered[0]
    found = {tuple(int(v) for v in c) for c in np.unique(rgb.reshape(3, -1), axis=1).T}
    assert found == set(COLOURS.values())


def test_contour_settings_change_shades(cell):
    rgb, _, frame = render_cell(cell, RESOLUTION, safety=12.0, soundings=False)
    assert colour_at(rgb, frame, NANTASKET_ROADS) == COLOURS["DEPMS"]  # 2 <= 11.0 < 12
    with pytest.raises(UsvError, match="not in order"):
        render_cell(cell, RESOLUTION, shallow=5.0, safety=3.0)


def test_soundings_are_clutter_over_water(plain, cluttered):
    ink = is_colour(cluttered[0], "SNDG2")
    assert not is_colour(plain[0], "SNDG2").any()
    assert ink.sum() > 1000
    assert (cluttered[1][ink] != 255).all()  # drawn inside the coverage
    assert (cluttered[1] == plain[1]).all()  # the truth ignores clutter


def test_sounding_text():
    assert [sounding_text(d) for d in (0.3, 2.4, 12.0, 30.96, 36.6)] == [
        "0.3",
        "2.4",
        "12",
        "31",
        "37",
    ]


def test_absurd_size_refused(cell):
    with pytest.raises(UsvError, match=r"--resolution 0.2 m: .* use --resolution [\d.]+ or more"):
        chart_frame(cell, 0.2)


def test_geotiffs_round_trip(tmp_path, plain):
    import rasterio
    from rasterio.enums import ColorInterp

    rgb, truth, frame = plain
    write_chart(tmp_path / "chart.tif", rgb, frame, {"source": "US5MA12M.000"})
    write_truth(tmp_path / "truth.tif", truth, frame)
    with rasterio.open(tmp_path / "chart.tif") as ds:
        assert ds.count == 3 and ds.crs.to_epsg() == 32619 and ds.transform == frame.transform
        assert ds.colorinterp == (ColorInterp.red, ColorInterp.green, ColorInterp.blue)
        assert ds.tags()["source"] == "US5MA12M.000"
        assert (ds.read() == rgb).all()
    with rasterio.open(tmp_path / "truth.tif") as ds:
        assert ds.count == 1 and ds.nodata == 255 and (ds.read(1) == truth).all()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["chart.tif", "truth.tif"]
