"""Geodesy: CRSs, reprojection, geodesic lengths.

A contract below the stages: every stage that turns map metres into lon/lat (or back) or
measures a length on the ellipsoid does it here, with the same conventions.

- Coordinates: ``(x, y)`` = (east, north) in map metres of a projected CRS, and ``(lon, lat)``
  in degrees of WGS84 (:data:`WGS84`), always in that order (pyproj's ``always_xy``). A CRS is
  anything pyproj accepts (a rasterio ``CRS``, ``"EPSG:32619"``, a WKT or PROJ string).
- Angles (compass degrees, mathematical radians) are converted in :mod:`usvtool.angles`.

Thin glue over pyproj; nothing here re-implements projection maths.
"""

from __future__ import annotations

import functools
import math

import numpy as np

WGS84 = "EPSG:4326"


def utm_crs(lon: float, lat: float):
    """The WGS84 / UTM zone CRS (rasterio ``CRS``) holding the point (lon, lat).

    >>> utm_crs(-71.0, 42.3).to_epsg(), utm_crs(151.2, -33.9).to_epsg()
    (32619, 32756)
    """
    from rasterio.crs import CRS

    zone = int(math.floor((lon + 180.0) / 6.0)) % 60 + 1
    return CRS.from_epsg((32600 if lat >= 0 else 32700) + zone)


def transformer(src, dst):
    """A pyproj transformer taking (x, y) = (lon, lat) / (east, north) order on both sides,
    made once per pair of CRSs given as text or codes in a process (:func:`_transformer`:
    building one costs some 5 ms, and a scene converts its points one by one)."""
    src, dst = pyproj_crs(src), pyproj_crs(dst)
    if type(src) in (str, int) and type(dst) in (str, int):  # a CRS named by its text or code
        return _transformer(src, dst)
    from pyproj import Transformer  # another object (a pyproj CRS): made afresh

    return Transformer.from_crs(src, dst, always_xy=True)


@functools.lru_cache(maxsize=64)
def _transformer(src, dst):
    """:func:`transformer` of CRSs in pyproj's forms. A Transformer is reusable, and safe to
    share between threads since pyproj 3.1 (each thread gets its own PROJ object)."""
    from pyproj import Transformer

    return Transformer.from_crs(src, dst, always_xy=True)


def lonlat_to_map(crs, lon, lat):
    """Map coordinates ``(x, y)`` in ``crs`` of WGS84 ``(lon, lat)`` (scalars or arrays).

    >>> x, y = lonlat_to_map("EPSG:32631", 3.0, 0.0)  # UTM 31N's central meridian, equator
    >>> round(x, 6), round(y, 6)
    (500000.0, 0.0)
    """
    return _pair(transformer(WGS84, crs).transform(lon, lat))


def map_to_lonlat(crs, x, y):
    """WGS84 ``(lon, lat)`` of map coordinates ``(x, y)`` in ``crs`` (scalars or arrays).

    >>> lon, lat = map_to_lonlat("EPSG:32631", 500000.0, 0.0)
    >>> round(lon, 9), round(lat, 9)
    (3.0, 0.0)
    """
    return _pair(transformer(crs, WGS84).transform(x, y))


def reproject_geometries(geoms, src, dst):
    """Reproject an array of shapely geometries from CRS ``src`` to ``dst``."""
    import shapely

    t = transformer(src, dst)
    return shapely.transform(
        np.asarray(geoms, dtype=object), lambda xy: np.column_stack(t.transform(xy[:, 0], xy[:, 1]))
    )


def geodesic_length(lon, lat) -> float:
    """Length in metres of a polyline on the WGS84 ellipsoid (pyproj ``Geod``, Karney's method).

    The ISSA paper uses Vincenty's inverse formula; Karney's agrees with it to well under a
    millimetre on these distances and never fails to converge.
    """
    from pyproj import Geod

    lon = np.asarray(lon, float)
    lat = np.asarray(lat, float)
    if lon.size < 2:
        return 0.0
    return float(Geod(ellps="WGS84").line_length(lon, lat))


def pyproj_crs(crs):
    """``crs`` in a form pyproj takes (WKT for a rasterio ``CRS``); ValueError for None."""
    if crs is None:
        raise ValueError("no CRS")
    return crs.to_wkt() if hasattr(crs, "to_wkt") else crs


def _pair(xy):
    a, b = xy
    if np.ndim(a) == 0:
        return float(a), float(b)
    return np.asarray(a, float), np.asarray(b, float)
