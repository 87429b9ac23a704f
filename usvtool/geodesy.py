"""Geodesy and compass angles: CRSs, reprojection, geodesic lengths, compass <-> radians.

A contract below the stages: every stage that turns map metres into lon/lat (or back), measures
a length on the ellipsoid or converts an angle does it here, with the same conventions.

- Coordinates: ``(x, y)`` = (east, north) in map metres of a projected CRS, and ``(lon, lat)``
  in degrees of WGS84 (:data:`WGS84`), always in that order (pyproj's ``always_xy``). A CRS is
  anything pyproj accepts (a rasterio ``CRS``, ``"EPSG:32619"``, a WKT or PROJ string).
- Angles: files and the command line use compass degrees (0 = north, 90 = east, clockwise; the
  maritime convention); code may use mathematical radians (counter-clockwise from +x = east).
  :func:`compass_to_math` and :func:`math_to_compass` are the one place where they meet.

Thin glue over pyproj; nothing here re-implements projection maths.
"""

from __future__ import annotations

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
    """A pyproj transformer taking (x, y) = (lon, lat) / (east, north) order on both sides."""
    from pyproj import Transformer

    return Transformer.from_crs(pyproj_crs(src), pyproj_crs(dst), always_xy=True)


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


# --- compass angles ------------------------------------------------------------------------


def wrap_deg(a):
    """Degrees wrapped to (-180, 180] (scalar in, float out; arrays element-wise).

    >>> wrap_deg(190.0), wrap_deg(-180.0), wrap_deg(180.0), wrap_deg(-190.0), wrap_deg(720.0)
    (-170.0, 180.0, 180.0, 170.0, 0.0)
    """
    a = np.asarray(a, float)
    out = 180.0 - np.mod(180.0 - a, 360.0)
    out = np.where(out <= -180.0, out + 360.0, out)  # mod may round up to 360
    return _out(out + 0.0)


def compass_to_math(deg):
    """Compass degrees (0 = north, clockwise) to mathematical radians in (-pi, pi] (counter-
    clockwise from +x = east). North is pi/2, east 0, south -pi/2 and west pi (not -pi).

    Computed as ``radians(wrap_deg(90 - deg))``: whole degrees give exact multiples of pi/180.

    >>> import math
    >>> [compass_to_math(d) / math.pi for d in (0.0, 90.0, 180.0, 270.0, 360.0, 45.0)]
    [0.5, 0.0, -0.5, 1.0, 0.5, 0.25]
    >>> compass_to_math(np.array([0.0, 90.0, 180.0, 270.0])).tolist() == [
    ...     math.pi / 2, 0.0, -math.pi / 2, math.pi]
    True
    """
    return _out(np.radians(wrap_deg(90.0 - np.asarray(deg, float))))


def math_to_compass(rad):
    """Mathematical radians (counter-clockwise from east) to compass degrees in [0, 360).

    >>> import math
    >>> [math_to_compass(r) for r in (math.pi / 2, 0.0, -math.pi / 2, math.pi, -math.pi)]
    [0.0, 90.0, 180.0, 270.0, 270.0]
    >>> math_to_compass(np.array([3 * math.pi / 2, 2 * math.pi + 1e-12, math.pi / 4])).round(9)
    array([180.,  90.,  45.])
    """
    deg = np.mod(90.0 - np.degrees(np.asarray(rad, float)), 360.0)
    deg = np.where(deg >= 360.0, 0.0, deg)  # mod of a tiny negative rounds to 360
    return _out(deg + 0.0)


def _out(a: np.ndarray):
    """A 0-d result as a Python float, anything else as the array."""
    return float(a) if np.ndim(a) == 0 else a


def _pair(xy):
    a, b = xy
    if np.ndim(a) == 0:
        return float(a), float(b)
    return np.asarray(a, float), np.asarray(b, float)
