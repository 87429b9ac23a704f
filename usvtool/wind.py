"""The wind field raster: the file contract of a scenario's weather field (docs/vessel.md).

Any raster GDAL reads (GeoTIFF, NetCDF, ...). Bands are recognised by their names (band
descriptions; for a file of several variables, such as NetCDF, the variable names) through
:data:`ALIASES`: ``wind_speed`` and ``wind_from``, or ``u`` and ``v``; optionally
``wave_height`` and ``wave_from``; other bands are ignored. Speeds m/s, directions-from compass
degrees (0 = from the north, clockwise), ``u``/``v`` the wind's velocity toward east and north.
Nodata and NaN cells are calm. The simulation interpolates it (:mod:`usvtool.sim.weather`); the
report draws it.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from usvtool.angles import compass_to_math
from usvtool.errors import UsvError, check_input_file

ROLES = ("wind_speed", "wind_from", "u", "v", "wave_height", "wave_from")
# Band names (descriptions, NetCDF variable names; case-insensitive) recognised for each role.
ALIASES = {
    "wind_speed": ("wind_speed", "speed"),
    "wind_from": ("wind_from", "wind_from_direction", "direction"),
    "u": ("u", "u10", "eastward_wind"),
    "v": ("v", "v10", "northward_wind"),
    "wave_height": ("wave_height", "swh", "sea_surface_wave_significant_height"),
    "wave_from": ("wave_from", "mwd", "sea_surface_wave_from_direction"),
}
_ROLE_OF = {alias: role for role, names in ALIASES.items() for alias in names}


@dataclass(frozen=True, eq=False)
class WindField:
    """A field's layers ``(k, rows, cols)``: the wind's velocity ``u`` (east), ``v`` (north)
    in m/s, in the direction it blows; then, when the raster has them, the wave height (m) and
    the unit vector (x, y) pointing where the waves come from. ``transform``: (col, row) to map
    metres; ``crs``: the raster's, or None."""

    layers: np.ndarray
    transform: object  # affine.Affine
    has_wave_height: bool
    has_wave_from: bool
    crs: object | None = None

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """(left, right, bottom, top) in map metres (a north-up raster)."""
        _, rows, cols = self.layers.shape
        t = self.transform
        xs = (t.c, t.c + t.a * cols)
        ys = (t.f, t.f + t.e * rows)
        return (min(xs), max(xs), min(ys), max(ys))


def read_wind_field(
    path: str | os.PathLike, bands: Sequence[str] | None = None, crs=None
) -> WindField:
    """Read a wind (and wave) field raster (module docstring). ``bands`` names the roles in
    band order instead of the names (``"-"`` skips one). ``crs``: the chart's CRS; a raster in
    another CRS is refused (reproject it), one without a CRS is taken to be in the chart's
    frame. Errors are one line naming the file.
    """
    import warnings

    import rasterio
    from rasterio.errors import NotGeoreferencedWarning, RasterioIOError

    check_input_file(path)
    try:
        with warnings.catch_warnings():  # no geotransform: refused below, in one line
            warnings.simplefilter("ignore", NotGeoreferencedWarning)
            with rasterio.open(path) as ds:
                if ds.count == 0 and ds.subdatasets:
                    names, arrays, transform, raster_crs = _read_variables(path, ds.subdatasets)
                else:
                    names = [d or "" for d in ds.descriptions]
                    arrays = [_read_band(ds, i) for i in range(1, ds.count + 1)]
                    transform, raster_crs = ds.transform, ds.crs
    except RasterioIOError as exc:
        raise UsvError(f"{path}: not a readable raster ({' '.join(str(exc).split())})") from None
    if bands is not None:
        if len(bands) != len(arrays):
            raise UsvError(
                f"{path}: bands names {len(bands)} band(s), the raster has {len(arrays)}"
            )
        bad = [b for b in bands if b not in ROLES and b != "-"]
        if bad:
            raise UsvError(f"{path}: unknown band role(s) {bad} (known: {', '.join(ROLES)}, -)")
        roles = list(bands)
    else:
        roles = [_ROLE_OF.get(n.strip().lower(), "-") for n in names]
    found = {}
    for role, array in zip(roles, arrays, strict=True):
        if role == "-":
            continue
        if role in found:
            raise UsvError(f"{path}: two bands are {role}")
        found[role] = array
    if {"u", "v"} <= found.keys() and {"wind_speed", "wind_from"} & found.keys():
        raise UsvError(f"{path}: both u/v and wind_speed/wind_from bands; pass bands to choose")
    if {"u", "v"} <= found.keys():
        u, v = found["u"], found["v"]
    elif {"wind_speed", "wind_from"} <= found.keys():
        _nonnegative(path, "wind_speed", found["wind_speed"])
        # the velocity points away from where the wind comes from
        to = compass_to_math(found["wind_from"]) + np.pi
        u, v = found["wind_speed"] * np.cos(to), found["wind_speed"] * np.sin(to)
    else:
        shown = ", ".join(repr(n) for n in names) or "none"
        raise UsvError(
            f"{path}: no wind bands among {len(arrays)} (names: {shown}); name them "
            "wind_speed + wind_from or u + v, or give bands"
        )
    layers = [u, v]
    if "wave_height" in found:
        _nonnegative(path, "wave_height", found["wave_height"])
        layers.append(found["wave_height"])
    if "wave_from" in found:
        frm = compass_to_math(found["wave_from"])
        layers += [np.cos(frm), np.sin(frm)]
    if raster_crs is not None and crs is not None:
        from rasterio.crs import CRS

        if CRS.from_user_input(crs) != raster_crs:
            raise UsvError(
                f"{path}: CRS {raster_crs.to_string()} is not the chart's "
                f"{CRS.from_user_input(crs).to_string()}; reproject it (gdalwarp -t_srs)"
            )
    if transform.is_identity or transform.determinant == 0:
        raise UsvError(f"{path}: no usable geotransform, so no map position for its cells")
    if transform.b != 0 or transform.d != 0:  # the figures draw a field as a north-up image
        raise UsvError(f"{path}: a rotated or sheared geotransform; warp the field north-up "
                       "(gdalwarp)")  # fmt: skip
    stack = np.nan_to_num(np.stack(layers).astype(float), nan=0.0)
    return WindField(stack, transform, "wave_height" in found, "wave_from" in found, raster_crs)


def _read_band(ds, i: int) -> np.ndarray:
    """Band ``i`` as float with nodata as NaN."""
    band = ds.read(i, masked=True).astype(float)
    return np.ma.filled(band, np.nan)


def _read_variables(path, subdatasets):
    """The single-band variables of a multi-variable file (NetCDF, HDF5): names and arrays."""
    import rasterio

    names, arrays, transform, crs, shape = [], [], None, None, None
    for sub in subdatasets:
        with rasterio.open(sub) as var:
            name = sub.rsplit(":", 1)[-1].strip('"')
            if var.count != 1:
                if _ROLE_OF.get(name.lower()) is None:
                    continue
                raise UsvError(f"{path}: variable {name} has {var.count} bands, one is expected")
            if transform is None:
                transform, crs, shape = var.transform, var.crs, var.shape
            elif var.shape != shape or var.transform != transform:
                raise UsvError(f"{path}: variable {name} is not on the grid of the others")
            names.append(name)
            arrays.append(_read_band(var, 1))
    return names, arrays, transform, crs


def _nonnegative(path, role: str, array: np.ndarray) -> None:
    low = np.nanmin(array, initial=np.inf)
    if low < 0:
        raise UsvError(f"{path}: {role} must be >= 0, the raster has {low:g}")
