"""Reading chart inputs into one of two forms the pipeline grids.

* :class:`RasterChart`: an RGB image in a north-up metric frame, with the mask of pixels inside
  the chart. From plain images (PNG, JPEG, TIFF: local metre frame from ``--resolution``, origin
  at the lower-left corner), georeferenced GeoTIFFs (RGB or palette) and BSB/KAP raster charts
  (georeferenced from their GCPs, masked by ``BSB_CUTLINE``). Lon/lat and GCP-referenced sources
  are warped to the UTM zone of their centre with nearest-neighbour resampling, so chart colours
  stay pure.
* :class:`VectorChart`: obstacle geometries in a metric CRS and the polygon of the chart's
  extent. From S-57 cells (:mod:`usvtool.chart.s57`) and GeoJSON obstacle polygons.
"""

from __future__ import annotations

import json
import os
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from usvtool.chart.georef import WGS84, Frame, reproject_geometries, utm_crs
from usvtool.errors import UsvError, check_input_file

MIN_PIXELS = 4  # an image narrower than this cannot hold a chart


@dataclass
class RasterChart:
    rgb: np.ndarray  # (H, W, 3) uint8
    valid: np.ndarray  # (H, W) bool: inside the chart
    frame: Frame
    kind: str  # "image" | "geotiff" | "kap"


@dataclass
class VectorChart:
    obstacles: np.ndarray  # shapely geometries in ``crs`` (metres)
    extent: object  # shapely polygon: the area the chart covers
    crs: object | None  # None: local metre frame
    kind: str  # "s57" | "geojson"


def chart_kind(path: str | os.PathLike) -> str:
    """The input kind from the file name: s57, geojson, kap or raster."""
    suffix = Path(path).suffix.lower()
    if len(suffix) == 4 and suffix[1:].isdigit():
        return "s57"
    if suffix in (".geojson", ".json"):
        return "geojson"
    if suffix == ".kap":
        return "kap"
    return "raster"


def read_raster(path: str | os.PathLike, resolution: float | None = None) -> RasterChart:
    """Read an image, GeoTIFF or KAP chart (see the module docstring)."""
    import rasterio
    from rasterio.errors import NotGeoreferencedWarning, RasterioIOError

    check_input_file(path)
    kind = "kap" if chart_kind(path) == "kap" else None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NotGeoreferencedWarning)
            with rasterio.open(path) as ds:
                if min(ds.width, ds.height) < MIN_PIXELS:
                    raise UsvError(
                        f"{path}: {ds.width} x {ds.height} pixels is too small for a chart "
                        f"(at least {MIN_PIXELS} x {MIN_PIXELS})"
                    )
                rgb, alpha = _read_rgb(ds, path)
                gcps, gcp_crs = ds.gcps
                crs, transform, tags = ds.crs, ds.transform, ds.tags()
    except RasterioIOError as exc:
        raise UsvError(f"{path}: not a readable chart image ({_first_line(exc)})") from None

    height, width = rgb.shape[:2]
    valid = np.ones((height, width), bool) if alpha is None else alpha > 0
    if kind == "kap" or (gcps and crs is None):
        if not gcps:
            raise UsvError(f"{path}: no georeference (the chart has no GCPs)")
        return _warp(rgb, valid, path, gcps=gcps, src_crs=gcp_crs, cutline=tags.get("BSB_CUTLINE"))
    if crs is not None and not transform.is_identity:
        if crs.is_projected and _is_metric(crs) and _square_north_up(transform):
            return RasterChart(rgb, valid, Frame(transform, width, height, crs), "geotiff")
        return _warp(rgb, valid, path, transform=transform, src_crs=crs)
    if resolution is None:
        raise UsvError(
            f"{path}: no georeference; give --resolution (metres per pixel) for a plain image"
        )
    from affine import Affine

    frame = Frame(Affine(resolution, 0, 0, 0, -resolution, height * resolution), width, height)
    return RasterChart(rgb, valid, frame, "image")


def read_geojson(path: str | os.PathLike, bounds=None) -> VectorChart:
    """Read obstacle polygons from GeoJSON.

    Coordinates are lon/lat (RFC 7946) unless the file says otherwise: a legacy ``crs`` member
    names a CRS, and the foreign member ``"frame": "local"`` marks a local metre frame
    (synthetic maps). The extent is ``bounds``, else the file's ``bbox``, else the obstacles'.
    """
    import shapely
    from shapely.geometry import box, shape

    check_input_file(path)
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
        features = doc["features"] if doc.get("type") == "FeatureCollection" else [doc]
        geoms = [shape(f["geometry"] if f.get("type") == "Feature" else f) for f in features]
    except (ValueError, KeyError, TypeError, AttributeError, UnicodeDecodeError) as exc:
        raise UsvError(f"{path}: not a GeoJSON file of obstacles ({_first_line(exc)})") from None
    geoms = np.array([g for g in geoms if not g.is_empty], dtype=object)
    if geoms.size == 0:
        raise UsvError(f"{path}: no obstacle geometries")
    if doc.get("frame") == "local":
        crs = None
    else:
        from rasterio.crs import CRS

        name = (doc.get("crs") or {}).get("properties", {}).get("name", WGS84)
        crs = CRS.from_user_input(name)
    extent_bounds = bounds or doc.get("bbox") or shapely.total_bounds(geoms)
    extent = box(*extent_bounds)
    if crs is not None and not crs.is_projected:
        target = utm_crs(*extent.centroid.coords[0])
        geoms = reproject_geometries(geoms, crs, target)
        extent = reproject_geometries([extent], crs, target)[0]
        crs = target
    return VectorChart(geoms, extent, crs, "geojson")


def read_s57(path: str | os.PathLike, min_depth: float, hazard_radius: float) -> VectorChart:
    """Read an S-57 cell's obstacles and coverage, projected to the UTM zone of its centre."""
    from usvtool.chart import s57

    cell = s57.read_cell(path)
    geoms = np.asarray(s57.obstacles(cell, min_depth, hazard_radius), dtype=object)
    target = cell.utm  # the same zone the S-52 rendering of the cell uses
    return VectorChart(
        reproject_geometries(geoms, WGS84, target),
        reproject_geometries([cell.coverage], WGS84, target)[0],
        target,
        "s57",
    )


def _read_rgb(ds, path):
    """The RGB pixels (H, W, 3) and alpha (or None) of a dataset: RGB(A), palette or grey.

    PNG and JPEG pixels are decoded by OpenCV, which refuses a truncated file where GDAL's
    drivers only log the libpng/libjpeg error and return partial pixels.
    """
    if ds.driver in ("PNG", "JPEG"):
        return _decode_with_opencv(path, ds.driver)
    if ds.count >= 3:
        data = ds.read()
        rgb = np.moveaxis(data[:3], 0, -1)
        alpha = data[3] if ds.count >= 4 else None
    else:
        band = ds.read(1)
        try:
            cmap = ds.colormap(1)
        except ValueError:
            cmap = None
        if cmap:
            lut = np.zeros((256, 4), np.uint8)
            for k, c in cmap.items():
                lut[k] = c
            rgb, alpha = lut[band, :3], None
        else:
            rgb, alpha = np.repeat(band[..., None], 3, axis=2), None
    if rgb.dtype != np.uint8:
        raise UsvError(f"{path}: expected 8-bit colour, found {rgb.dtype}")
    return np.ascontiguousarray(rgb), alpha


def _decode_with_opencv(path, driver: str):
    import cv2

    data = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if data is None:
        raise UsvError(f"{path}: truncated or corrupt {driver} image")
    if data.dtype != np.uint8:
        raise UsvError(f"{path}: expected 8-bit colour, found {data.dtype}")
    if data.ndim == 2:
        return np.ascontiguousarray(np.repeat(data[..., None], 3, axis=2)), None
    if data.shape[2] == 4:
        return cv2.cvtColor(data, cv2.COLOR_BGRA2RGB), data[..., 3]
    return cv2.cvtColor(data, cv2.COLOR_BGR2RGB), None


def _warp(rgb, valid, path, *, src_crs, gcps=None, transform=None, cutline=None) -> RasterChart:
    """Warp to the UTM zone of the chart's centre (nearest neighbour), masking the cutline."""
    from rasterio import features
    from rasterio.transform import from_gcps
    from rasterio.warp import Resampling, calculate_default_transform, reproject, transform_bounds

    height, width = rgb.shape[:2]
    src_transform = from_gcps(gcps) if gcps else transform
    left, top = src_transform @ (0, 0)
    right, bottom = src_transform @ (width, height)
    lon0, lat0 = _centre_lonlat(src_crs, left, bottom, right, top, transform_bounds)
    dst_crs = utm_crs(lon0, lat0)
    edges = {"left": left, "bottom": bottom, "right": right, "top": top}
    kwargs = {"gcps": gcps} if gcps else edges
    dst_transform, w, h = calculate_default_transform(src_crs, dst_crs, width, height, **kwargs)
    res = float(np.sqrt(abs(dst_transform.a * dst_transform.e)))
    dst_transform, w, h = calculate_default_transform(
        src_crs, dst_crs, width, height, resolution=res, **kwargs
    )
    src = np.concatenate([np.moveaxis(rgb, -1, 0), valid[None].astype(np.uint8)])
    out = np.zeros((4, h, w), np.uint8)
    reproject(
        src,
        out,
        src_transform=None if gcps else src_transform,
        gcps=gcps,
        src_crs=src_crs,
        dst_transform=dst_transform,
        dst_crs=dst_crs,
        resampling=Resampling.nearest,
    )
    valid_out = out[3] > 0
    if cutline:
        poly = reproject_geometries([_cutline_polygon(cutline, path)], WGS84, dst_crs)[0]
        inside = features.geometry_mask([poly], (h, w), dst_transform, invert=True)
        valid_out &= inside
    rgb_out = np.ascontiguousarray(np.moveaxis(out[:3], 0, -1))
    kind = "kap" if chart_kind(path) == "kap" else "geotiff"
    return RasterChart(rgb_out, valid_out, Frame(dst_transform, w, h, dst_crs), kind)


def _cutline_polygon(wkt: str, path):
    """The BSB_CUTLINE polygon (lon/lat). GDAL writes its ring unclosed, which strict WKT
    readers refuse, so the vertices are read and the ring closed by shapely."""
    import re

    from shapely.geometry import Polygon

    numbers = [float(v) for v in re.findall(r"-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?", wkt)]
    if len(numbers) < 6 or len(numbers) % 2:
        raise UsvError(f"{path}: unreadable BSB_CUTLINE")
    return Polygon(np.reshape(numbers, (-1, 2)))


def _centre_lonlat(src_crs, left, bottom, right, top, transform_bounds):
    west, south, east, north = transform_bounds(
        src_crs, WGS84, min(left, right), min(bottom, top), max(left, right), max(bottom, top)
    )
    return (west + east) / 2, (south + north) / 2


def _is_metric(crs) -> bool:
    units = (crs.linear_units or "").lower()
    return units in ("metre", "meter", "m", "metres", "meters")


def _square_north_up(t) -> bool:
    return t.b == 0 and t.d == 0 and t.e < 0 and abs(t.a + t.e) <= 1e-9 * abs(t.a)


def _first_line(exc: Exception) -> str:
    return str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
