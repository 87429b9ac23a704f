"""Georeferencing helpers: UTM zones, reprojection of geometries, raster frames, geodesics.

All of it is thin glue over pyproj and rasterio; nothing here re-implements projection maths.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from affine import Affine

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

    return Transformer.from_crs(_pyproj(src), _pyproj(dst), always_xy=True)


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


@dataclass(frozen=True)
class Frame:
    """A north-up raster frame: transform, size and CRS."""

    transform: Affine
    width: int
    height: int
    crs: object | None = None

    @property
    def resolution(self) -> float:
        return float(self.transform.a)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        left, top, r = self.transform.c, self.transform.f, self.resolution
        return (left, top - self.height * r, left + self.width * r, top)


def scale_error(frame: Frame) -> float:
    """The largest departure from true scale, in any direction, of a projected frame's CRS over
    the frame: max |s - 1| for s the semi-axes of Tissot's indicatrix (pyproj ``get_factors``)
    at the frame's centre, corners and edge midpoints; infinite where PROJ cannot say.

    >>> from rasterio.crs import CRS
    >>> f = Frame(Affine(10, 0, 495000, 0, -10, 3230000), 1000, 1000, CRS.from_epsg(32616))
    >>> round(scale_error(f), 6)  # UTM's scale on its central meridian is 0.9996
    0.0004
    """
    from pyproj import Proj

    proj = Proj(_pyproj(frame.crs))
    left, bottom, right, top = frame.bounds
    x, y = np.meshgrid([left, (left + right) / 2, right], [bottom, (bottom + top) / 2, top])
    lon, lat = proj(x.ravel(), y.ravel(), inverse=True)
    factors = proj.get_factors(lon, lat)
    axes = np.concatenate([factors.tissot_semimajor, factors.tissot_semiminor])
    error = np.abs(axes - 1)
    return float(error.max()) if np.isfinite(error).all() else math.inf


def frame_for_bounds(bounds, resolution: float, crs=None) -> Frame:
    """The frame covering ``bounds`` (left, bottom, right, top) with square pixels.

    The frame starts at the lower-left corner and grows right and up by whole pixels, so it
    covers the bounds and at most one pixel more on the right and top edges.

    >>> f = frame_for_bounds((0, 0, 25, 10), 10)
    >>> f.width, f.height, f.bounds
    (3, 1, (0.0, 0.0, 30.0, 10.0))
    """
    left, bottom, right, top = (float(b) for b in bounds)
    width = max(1, math.ceil((right - left) / resolution - 1e-9))
    height = max(1, math.ceil((top - bottom) / resolution - 1e-9))
    top = bottom + height * resolution
    return Frame(Affine(resolution, 0, left, 0, -resolution, top), width, height, crs)


def _pyproj(crs):
    if crs is None:
        raise ValueError("no CRS")
    return crs.to_wkt() if hasattr(crs, "to_wkt") else crs
