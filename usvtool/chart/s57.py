"""Read S-57 ENC cells (IHO S-57 edition 3.1) and derive the non-navigable areas.

The cell is read with the GDAL S57 driver bundled in pyogrio, with update files beside the base
cell (``.001``, ``.002``, ...) applied by the driver (``UPDATES=APPLY``) and multipoint soundings
split into one point each (``SPLIT_MULTIPOINT=ON``). All geometries are lon/lat (EPSG:4326).

Layers read (see ``docs/s57.md``):

- coverage: ``M_COVR`` polygons with ``CATCOV=1`` (``CATCOV=2`` means "no coverage");
- land: polygons of ``LNDARE`` and of the other objects that are dry or solid at the surface:
  ``BUAARE`` (built-up area), ``PONTON``, ``HULKES``, ``FLODOC``, ``DRYDOC``;
- depth areas: ``DEPARE`` and ``DRGARE`` polygons with ``DRVAL1``/``DRVAL2``; a missing ``DRVAL1``
  is taken as -1 m (drying), as in S-52's DEPARE03 procedure;
- hazards: ``UWTROC``, ``WRECKS``, ``OBSTRN`` (with ``VALSOU`` where given), plus ``SLCONS``
  (piers, breakwaters, sea walls) and ``PILPNT`` (piles), which are solid obstructions too;
- coastline ``COALNE``, depth contours ``DEPCNT`` (``VALDCO``), soundings ``SOUNDG`` (depth = Z).

:func:`update_status` tells which edition and update were applied and which update files lie
beside the cell, for the commands' summaries.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely

from usvtool.companions import s57_updates
from usvtool.errors import UsvError, check_input_file
from usvtool.geodesy import WGS84, reproject_geometries, utm_crs

LAND_LAYERS = ("LNDARE", "BUAARE", "PONTON", "HULKES", "FLODOC", "DRYDOC")
DEPTH_LAYERS = ("DEPARE", "DRGARE")
HAZARD_LAYERS = ("UWTROC", "WRECKS", "OBSTRN", "SLCONS", "PILPNT")

#: Shallowest navigable depth below chart datum, metres: the YL-2500 USV's 0.6 m draft (ISSA
#: paper) plus 0.5 m under-keel clearance, rounded up by 0.1 m for squat and for chart depths
#: being quoted to the decimetre.
DEFAULT_MIN_DEPTH = 1.2
#: Radius in metres of the circle kept clear around point hazards (and of the band around line
#: and area hazards): a few hull lengths, and the order of a 1:25 000 chart's plotting accuracy.
DEFAULT_HAZARD_RADIUS = 10.0

_POLYGONAL = (3, 6)  # shapely type ids: Polygon, MultiPolygon

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Cell:
    """The navigation-relevant content of one S-57 cell, in lon/lat.

    Geometry fields are numpy object arrays of shapely geometries; attribute arrays run
    parallel to them (NaN where the attribute is not given).
    """

    path: Path
    name: str
    edition: str
    update: str
    scale: int  # compilation scale denominator (DSPM_CSCL), 0 if unknown
    coverage: shapely.Geometry
    land: np.ndarray
    depth_areas: np.ndarray
    drval1: np.ndarray
    drval2: np.ndarray
    hazards: np.ndarray
    hazard_layers: np.ndarray
    valsou: np.ndarray
    coastline: np.ndarray
    contours: np.ndarray
    valdco: np.ndarray
    soundings: np.ndarray
    sounding_depths: np.ndarray

    @property
    def utm(self):
        """The UTM zone CRS of the coverage's centre."""
        return coverage_utm(self.coverage)


def coverage_utm(coverage: shapely.Geometry):
    """The UTM zone CRS of the centre of a coverage's bounding box (lon/lat)."""
    left, bottom, right, top = coverage.bounds
    return utm_crs((left + right) / 2, (bottom + top) / 2)


def read_cell(path, updates: bool = True) -> Cell:
    """Read an S-57 cell (``.000``); with ``updates``, apply the update files beside it."""
    path = Path(path)
    check_input_file(path)
    reader = _Reader(path, updates)

    land = np.concatenate([_polygons(reader.read(name)[0]) for name in LAND_LAYERS])
    depth, drval1, drval2 = [], [], []
    for name in DEPTH_LAYERS:
        geoms, attrs = reader.read(name, ["DRVAL1", "DRVAL2"])
        keep = np.isin(shapely.get_type_id(geoms), _POLYGONAL)
        depth.append(geoms[keep])
        drval1.append(attrs["DRVAL1"][keep])
        drval2.append(attrs["DRVAL2"][keep])
    depth_areas = np.concatenate(depth)
    if not len(land) and not len(depth_areas):
        raise UsvError(f"{path}: no land (LNDARE) or depth areas (DEPARE): not a navigational cell")
    drval1 = np.concatenate(drval1)
    drval1 = np.where(np.isnan(drval1), -1.0, drval1)

    hazards, layers, valsou = [], [], []
    for name in HAZARD_LAYERS:
        geoms, attrs = reader.read(name, ["VALSOU"])
        hazards.append(geoms)
        layers.append(np.full(len(geoms), name))
        valsou.append(attrs["VALSOU"])

    contours, contour_attrs = reader.read("DEPCNT", ["VALDCO"])
    soundings = reader.read("SOUNDG")[0]
    soundings = soundings[shapely.get_type_id(soundings) == 0]
    depths = shapely.get_coordinates(soundings, include_z=True)[:, 2]
    soundings, depths = soundings[~np.isnan(depths)], depths[~np.isnan(depths)]
    return Cell(
        path=path,
        **reader.identity(),
        coverage=reader.coverage(),
        land=land,
        depth_areas=depth_areas,
        drval1=drval1,
        drval2=np.concatenate(drval2),
        hazards=np.concatenate(hazards),
        hazard_layers=np.concatenate(layers),
        valsou=np.concatenate(valsou),
        coastline=reader.read("COALNE")[0],
        contours=contours,
        valdco=contour_attrs["VALDCO"],
        soundings=soundings,
        sounding_depths=depths,
    )


def read_coverage(path, updates: bool = True) -> shapely.Geometry:
    """The cell's coverage (lon/lat) alone: a quick read for checks made before the real work."""
    path = Path(path)
    check_input_file(path)
    return _Reader(path, updates).coverage()


def update_status(path) -> dict:
    """Edition and update number applied (``DSID_EDTN``, ``DSID_UPDN``, with the update files
    applied) and the names of the update files beside the cell.

    Warns when the update files are not a contiguous run from .001: GDAL's driver applies
    .001, .002, ... in turn and stops at the first one missing, so later files are ignored.
    """
    path = Path(path)
    check_input_file(path)
    identity = _Reader(path, True).identity()
    files = s57_updates(path)  # the files GDAL's driver applies (usvtool.companions)
    numbers = [int(p.suffix[1:]) for p in files]
    missing = sorted(set(range(1, max(numbers, default=0) + 1)) - set(numbers))
    if missing:
        log.warning(
            "%s: update files %s are not a contiguous run from .001 (missing %s): "
            "update %s applied, the later files ignored",
            path, ", ".join(p.suffix for p in files), ", ".join(f".{n:03d}" for n in missing),
            identity["update"],
        )  # fmt: skip
    return {
        "edition": identity["edition"],
        "update": identity["update"],
        "update_files": [p.name for p in files],
    }


def obstacles(
    cell: Cell,
    min_depth: float = DEFAULT_MIN_DEPTH,
    hazard_radius: float = DEFAULT_HAZARD_RADIUS,
) -> np.ndarray:
    """Lon/lat geometries of everything a vessel needing ``min_depth`` metres must avoid.

    - all land polygons;
    - depth areas whose shallow bound ``DRVAL1`` is below ``min_depth``;
    - hazards, buffered by ``hazard_radius`` metres in the cell's UTM zone (a radius of 0
      keeps them as points and lines); a hazard whose ``VALSOU`` is known to be at least
      ``min_depth`` is skipped, one without ``VALSOU`` is kept.
    """
    if not math.isfinite(min_depth):
        raise UsvError(f"min_depth {min_depth}: must be a finite number")
    if not math.isfinite(hazard_radius) or hazard_radius < 0:
        raise UsvError(f"hazard_radius {hazard_radius}: must be a finite number >= 0")
    shallow = cell.depth_areas[cell.drval1 < min_depth]
    hazards = cell.hazards[~(cell.valsou >= min_depth)]
    if hazard_radius > 0 and len(hazards):
        utm = cell.utm
        metric = reproject_geometries(hazards, WGS84, utm)
        hazards = reproject_geometries(shapely.buffer(metric, hazard_radius), utm, WGS84)
    return np.concatenate([cell.land, shallow, hazards])


class _Reader:
    """Layer reads from one cell, with the driver options and the checks done once."""

    def __init__(self, path: Path, updates: bool):
        import pyogrio

        self.path = path
        self.options = {"UPDATES": "APPLY" if updates else "IGNORE", "SPLIT_MULTIPOINT": "ON"}
        try:
            self.layers = set(pyogrio.list_layers(path)[:, 0])
            s57 = "DSID" in self.layers and pyogrio.read_info(path, layer="DSID")["driver"] == "S57"
        except pyogrio.errors.DataSourceError:
            s57 = False
        if not s57:
            raise UsvError(f"{path}: not an S-57 cell (GDAL's S57 driver cannot read it)")

    def read(self, layer: str, columns: list[str] | None = None):
        """Geometries (non-null) and the requested attributes (float arrays) of one layer."""
        from pyogrio.raw import read

        columns = columns or []
        if layer not in self.layers:
            return np.empty(0, dtype=object), {c: np.empty(0) for c in columns}
        meta, fids, wkb, values = read(self.path, layer=layer, columns=columns, **self.options)
        if wkb is None:
            wkb = np.full(len(fids), None, dtype=object)
        present = np.array([g is not None for g in wkb], dtype=bool)
        geoms = shapely.from_wkb(wkb[present])
        found = dict(zip(meta["fields"], values, strict=True))
        nan = np.full(len(wkb), np.nan)
        attrs = {c: np.asarray(found.get(c, nan), dtype=float)[present] for c in columns}
        return geoms, attrs

    def identity(self) -> dict:
        """Cell name, edition, update number and compilation scale from the DSID record (the
        update number is the last update applied: 0 when updates are ignored)."""
        from pyogrio.raw import read

        fields = ["DSID_DSNM", "DSID_EDTN", "DSID_UPDN", "DSPM_CSCL"]
        meta, _, _, values = read(
            self.path, layer="DSID", columns=fields, read_geometry=False, **self.options
        )
        found = {f: v[0] for f, v in zip(meta["fields"], values, strict=True) if len(v)}
        scale = found.get("DSPM_CSCL")
        return {
            "name": str(found.get("DSID_DSNM") or self.path.name),
            "edition": _text(found.get("DSID_EDTN")),
            "update": _text(found.get("DSID_UPDN")),
            "scale": int(scale) if scale else 0,
        }

    def coverage(self) -> shapely.Geometry:
        """Union of the ``M_COVR`` polygons with ``CATCOV=1``."""
        geoms, attrs = self.read("M_COVR", ["CATCOV"])
        coverage = _polygons(geoms[attrs["CATCOV"] == 1])
        if not len(coverage):
            raise UsvError(f"{self.path}: no coverage polygon (M_COVR with CATCOV=1)")
        return shapely.union_all(coverage)


def _text(value) -> str:
    """A DSID field as text ('' when not given; a 0 stays '0')."""
    return "" if value is None else str(value)


def _polygons(geoms: np.ndarray) -> np.ndarray:
    """The polygonal members of ``geoms``."""
    return geoms[np.isin(shapely.get_type_id(geoms), _POLYGONAL)]
