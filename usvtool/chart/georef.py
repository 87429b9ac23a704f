"""Raster frames of the chart stage: north-up transforms, their extent and their scale error.

CRSs, reprojection, lon/lat <-> map metres and geodesic lengths are the shared contract
:mod:`usvtool.geodesy`; this module adds only what is specific to raster frames. Thin glue over
pyproj and rasterio; nothing here re-implements projection maths.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from affine import Affine

from usvtool.geodesy import pyproj_crs


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

    proj = Proj(pyproj_crs(frame.crs))
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
