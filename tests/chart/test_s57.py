"""S-57 reading and obstacles, checked against hand-read facts of the NOAA cell US5MA12M."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

from usvtool.chart import s57
from usvtool.chart.s57 import DEFAULT_MIN_DEPTH, obstacles, read_cell
from usvtool.errors import UsvError

CHARTS = Path(__file__).resolve().parents[2] / "charts" / "noaa"
CELL = CHARTS / "US5MA12M.000"

THOMPSON_ISLAND = (-71.0106, 42.3148)
LONG_ISLAND = (-70.9665, 42.3193)
NANTASKET_ROADS = (-70.9219, 42.3122)  # DRGARE "35-Foot Nantasket Roads Reach", DRVAL1 11.0
MASS_BAY_DEEP = (-70.7419, 42.3153)  # DEPARE 36.5-45.7 m
BETWEEN_STRIPS = (-70.9, 42.26)  # inside M_COVR CATCOV=2 (no coverage) only


@pytest.fixture(scope="module")
def cell():
    return read_cell(CELL)


def in_any(geoms, lon, lat) -> bool:
    return bool(shapely.intersects(geoms, shapely.Point(lon, lat)).any())


def test_cell_identity_and_counts(cell):
    assert (cell.name, cell.edition, cell.update, cell.scale) == ("US5MA12M.000", "32", "0", 25000)
    assert len(cell.land) == 27 + 2  # 27 LNDARE polygons (of 285 features) + 2 BUAARE polygons
    assert len(cell.depth_areas) == 291 + 27  # DEPARE + DRGARE
    assert cell.drval1.min() == pytest.approx(-2.9) and cell.drval1.max() == pytest.approx(36.5)
    layers, counts = np.unique(cell.hazard_layers, return_counts=True)
    assert dict(zip(layers, counts, strict=True)) == {
        "OBSTRN": 42, "PILPNT": 30, "SLCONS": 228, "UWTROC": 516, "WRECKS": 9
    }  # fmt: skip
    assert len(cell.coastline) == 76 and len(cell.contours) == 423
    assert len(cell.soundings) == len(cell.sounding_depths) == 1698
    assert cell.sounding_depths.min() == pytest.approx(0.3)
    assert cell.utm.to_epsg() == 32619


def test_coverage_is_catcov_1_only(cell):
    left, bottom, right, top = cell.coverage.bounds
    assert -71.08 <= left < right <= -70.73 and 42.21 <= bottom < top <= 42.33
    assert (left, bottom, right, top) == pytest.approx(
        (-71.072828, 42.219129, -70.737819, 42.327875)
    )
    assert not cell.coverage.contains(shapely.Point(*BETWEEN_STRIPS))
    assert cell.coverage.contains(shapely.Point(*NANTASKET_ROADS))


def test_land_and_water_points(cell):
    assert in_any(cell.land, *THOMPSON_ISLAND) and in_any(cell.land, *LONG_ISLAND)
    assert not in_any(cell.land, *NANTASKET_ROADS)
    assert in_any(cell.depth_areas[cell.drval1 == 11.0], *NANTASKET_ROADS)


def test_obstacles_shallow_in_deep_out(cell):
    found = obstacles(cell)
    ids = {id(g) for g in found}
    shallow = cell.drval1 < DEFAULT_MIN_DEPTH
    assert set(np.unique(cell.drval1[shallow])) == {-2.9, 0.0}
    assert all(id(g) in ids for g in cell.depth_areas[shallow])
    assert not any(id(g) in ids for g in cell.depth_areas[~shallow])
    assert all(id(g) in ids for g in cell.land)
    assert not in_any(found, *NANTASKET_ROADS) and not in_any(found, *MASS_BAY_DEEP)
    assert in_any(found, *THOMPSON_ISLAND)
    # a deeper draft makes the 1.8 m band an obstacle too
    assert len(obstacles(cell, min_depth=2.0)) > len(found)
    assert 1.2 == DEFAULT_MIN_DEPTH


def test_hazards_buffered_in_metres_and_deep_ones_skipped(cell):
    from usvtool.geodesy import WGS84, reproject_geometries

    found = obstacles(cell, hazard_radius=25.0)
    kept = ~(cell.valsou >= DEFAULT_MIN_DEPTH)  # unknown VALSOU (NaN) is kept
    assert 0 < kept.sum() < len(cell.hazards)
    first_hazard = len(cell.land) + (cell.drval1 < DEFAULT_MIN_DEPTH).sum()
    assert len(found) == first_hazard + kept.sum()

    rock = np.flatnonzero((cell.hazard_layers == "UWTROC") & np.isnan(cell.valsou))[0]
    utm = cell.utm
    centre = reproject_geometries([cell.hazards[rock]], WGS84, utm)[0]
    disc = reproject_geometries([found[first_hazard + kept[:rock].sum()]], WGS84, utm)[0]
    assert disc.area == pytest.approx(np.pi * 25**2, rel=0.02)
    assert disc.contains(shapely.Point(centre.x + 24, centre.y))
    assert not disc.contains(shapely.Point(centre.x, centre.y + 26))

    raw = obstacles(cell, hazard_radius=0)
    assert set(shapely.get_type_id(raw[first_hazard:])) >= {0, 1}  # points and lines as they are


def test_obstacle_arguments_checked(cell):
    with pytest.raises(UsvError, match="hazard_radius"):
        obstacles(cell, hazard_radius=-1)
    with pytest.raises(UsvError, match="min_depth"):
        obstacles(cell, min_depth=float("nan"))


@pytest.mark.parametrize("kind", ["missing", "empty", "text", "raster-chart", "no-features"])
def test_bad_cells(bad_cell, kind):
    path, words = bad_cell(kind)
    with pytest.raises(UsvError, match=words) as err:
        read_cell(path)
    assert str(err.value).startswith(str(path)) and "\n" not in str(err.value)


def test_no_catcov_1_coverage(monkeypatch):
    original = s57._Reader.read

    def no_coverage(self, layer, columns=None):
        geoms, attrs = original(self, layer, columns)
        if layer == "M_COVR":
            attrs["CATCOV"] = np.full(len(geoms), 2.0)
        return geoms, attrs

    monkeypatch.setattr(s57._Reader, "read", no_coverage)
    with pytest.raises(
        UsvError, match=r"US5MA12M.000: no coverage polygon \(M_COVR with CATCOV=1\)"
    ):
        read_cell(CELL)
