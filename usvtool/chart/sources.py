"""Reading chart inputs into one of two forms the pipeline grids.

* :class:`RasterChart`: a chart image in a north-up frame whose units are metres on the ground,
  held as colour indices into a palette of distinct colours, with the mask of pixels inside the
  chart. From plain images (PNG, JPEG, TIFF: local metre frame from ``--resolution``, origin at
  the lower-left corner), georeferenced GeoTIFFs (RGB(A), grey or palette, 8 or 16 bits) and
  BSB/KAP raster charts (georeferenced from their GCPs, masked by ``BSB_CUTLINE``). A source is
  kept in its own CRS only when that CRS is metric at the chart and its geotransform north-up
  (:func:`keeps_frame`); every other one (lon/lat, Web Mercator, a chart projection, a far UTM
  zone, GCPs, a rotated or sheared geotransform) is warped north-up to the UTM zone of its
  centre, over its whole footprint. The warp moves the index band alone, nearest neighbour, so
  chart colours stay pure. No-data, alpha and mask bands, and an optional cutline polygon, mark the
  pixels outside the chart.
* :class:`VectorChart`: obstacle geometries in a metric CRS and the polygon of the chart's
  extent. From S-57 cells (:mod:`usvtool.chart.s57`) and GeoJSON obstacle polygons.
"""

from __future__ import annotations

import json
import math
import os
import warnings
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np

from usvtool.chart import memory
from usvtool.chart.colours import colour_index, index_dtype, index_packed, pack
from usvtool.chart.georef import Frame, scale_error
from usvtool.errors import UsvError, check_input_file
from usvtool.geodesy import WGS84, reproject_geometries, utm_crs

MIN_PIXELS = 4  # an image narrower than this cannot hold a chart
#: A projected CRS in metres is kept as the chart's frame when, at the chart, its point scale in
#: every direction is within this of 1 (see :func:`keeps_frame`).
MAX_SCALE_ERROR = 0.002
WARP_THREADS = 2  # GDAL warper threads: 0.27 s against 0.46 s on SanDiego_2 (2 cores)
EDGE_SAMPLES = 21  # points per edge where a footprint is projected (GDAL's suggested output)


@dataclass
class RasterChart:
    """A chart image in a north-up frame, as indexed colour (:mod:`usvtool.chart.colours`).

    ``index`` (H, W) unsigned colour indices into ``palette`` (n, 3) uint8 distinct colours;
    ``valid`` (H, W) bool, the pixels inside the chart (a pixel outside holds some in-range
    index); ``frame``; ``kind`` ("image", "geotiff", "kap", or a caller's own such as "s57").
    :meth:`from_rgb` indexes an RGB image; ``rgb`` is ``palette[index]``, made on first use.
    """

    index: np.ndarray
    palette: np.ndarray
    valid: np.ndarray
    frame: Frame | None
    kind: str

    @classmethod
    def from_rgb(cls, rgb: np.ndarray, valid: np.ndarray, frame: Frame | None, kind: str):
        return cls(*colour_index(rgb), valid, frame, kind)

    @cached_property
    def rgb(self) -> np.ndarray:
        """(H, W, 3) uint8 ``palette[index]``, one channel at a time (fancy indexing of the
        whole palette needs a pixel-sized intp copy of the index and is slower)."""
        out = np.empty((*self.index.shape, 3), np.uint8)
        for c in range(3):
            out[..., c] = self.palette[:, c][self.index]
        return out


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


def read_raster(
    path: str | os.PathLike,
    resolution: float | None = None,
    cutline: str | os.PathLike | None = None,
    max_memory: int | None = None,
) -> RasterChart:
    """Read an image, GeoTIFF or KAP chart (see the module docstring).

    ``resolution`` (metres per pixel) is for plain images and refused for a georeferenced
    source; ``cutline`` is a GeoJSON polygon file (:func:`read_cutline`): pixels outside it are
    outside the chart (for a KAP: outside both it and the chart's own cutline). A chart whose
    preprocessing would need more than ``max_memory`` bytes (None: the default budget) is
    refused from its header, before its pixels are read (:mod:`usvtool.chart.memory`).
    """
    import rasterio
    from rasterio.errors import NotGeoreferencedWarning, RasterioIOError

    check_input_file(path)
    cutlines = [(*read_cutline(cutline), f"--cutline {cutline}")] if cutline is not None else []
    kap = chart_kind(path) == "kap"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NotGeoreferencedWarning)
            with rasterio.open(path) as ds:
                if min(ds.width, ds.height) < MIN_PIXELS:
                    raise UsvError(
                        f"{path}: {ds.width} x {ds.height} pixels is too small for a chart "
                        f"(at least {MIN_PIXELS} x {MIN_PIXELS})"
                    )
                gcps, gcp_crs = ds.gcps
                crs, transform, tags = ds.crs, ds.transform, ds.tags()
                if kap and not gcps:
                    raise UsvError(f"{path}: no georeference (the chart has no GCPs)")
                by_gcps = kap or bool(gcps and crs is None)
                georeferenced = by_gcps or (crs is not None and not transform.is_identity)
                if georeferenced and resolution is not None:
                    raise UsvError(
                        f"{path}: the chart is georeferenced; --resolution is for plain images "
                        "only (drop it)"
                    )
                itemsize = np.dtype(ds.dtypes[0]).itemsize
                with memory.check_pixels(path, ds.width, ds.height, ds.count, itemsize,
                                         max_memory):  # fmt: skip
                    index, palette, valid = _read_pixels(ds, path)
    except RasterioIOError as exc:
        raise UsvError(f"{path}: not a readable chart image ({_first_line(exc)})") from None

    height, width = index.shape
    if not georeferenced:
        if cutlines:
            raise UsvError(f"{path}: no georeference, so --cutline {cutline} cannot be placed")
        if resolution is None:
            raise UsvError(
                f"{path}: no georeference; give --resolution (metres per pixel) for a plain image"
            )
        from affine import Affine

        frame = Frame(Affine(resolution, 0, 0, 0, -resolution, height * resolution), width, height)
        valid = np.ones((height, width), bool) if valid is None else valid
        return RasterChart(index, palette, valid, frame, "image")

    if by_gcps:
        if tags.get("BSB_CUTLINE"):
            own = _cutline_polygon(tags["BSB_CUTLINE"], path)
            cutlines.append((own, WGS84, "its BSB_CUTLINE"))
        index, valid, frame = _warp(index, valid, len(palette), gcps=gcps, src_crs=gcp_crs)
    else:
        if transform.is_degenerate:
            raise UsvError(f"{path}: its geotransform is degenerate (pixels of no area)")
        frame = Frame(transform, width, height, crs)
        if not keeps_frame(frame):
            index, valid, frame = _warp(
                index, valid, len(palette), transform=transform, src_crs=crs
            )
    if valid is None:
        valid = np.ones(index.shape, bool)
    if cutlines:
        _clip(valid, frame, cutlines, path)
    return RasterChart(index, palette, valid, frame, "kap" if kap else "geotiff")


def keeps_frame(frame: Frame) -> bool:
    """Whether a georeferenced raster stays in its own frame (else it is warped to UTM).

    Kept: a projected CRS in metres, a north-up square-pixelled transform, and a point scale
    within :data:`MAX_SCALE_ERROR` (0.2 %) of 1 in every direction at the chart's centre,
    corners and edge midpoints (:func:`usvtool.chart.georef.scale_error`, pyproj's Tissot
    factors). Then the frame's metres are metres on the ground to 0.2 %, in every direction, so
    the cell size, the ship-length rule and the margin hold, and the frame is conformal to
    better than 0.23 degrees. The threshold keeps every UTM zone over the whole zone (scale
    0.9996 to 1.001) and a little beyond its edges, State Plane and national grids in metres
    (scale errors of 1:10 000), and a Mercator whose true-scale latitude runs through a harbour
    chart; it warps EPSG:3857 (scale 1 / cos(latitude): 14 % at 29 N), a Mercator true at
    another latitude, lon/lat CRSs, projections in feet, and UTM zones farther away (UTM 17N
    at Head of Passes, in 16N: 0.77 %). Warping costs a nearest-neighbour resampling (features
    move by up to half a pixel), so a frame already metric to 0.2 % is better kept.
    """
    crs, t = frame.crs, frame.transform
    square_north_up = t.b == 0 and t.d == 0 and t.e < 0 and abs(t.a + t.e) <= 1e-9 * abs(t.a)
    if crs is None or not crs.is_projected or not _is_metric(crs) or not square_north_up:
        return False
    return scale_error(frame) <= MAX_SCALE_ERROR


def read_cutline(path: str | os.PathLike):
    """The (multi)polygon of a ``--cutline`` GeoJSON file and its CRS: lon/lat per RFC 7946, or
    the CRS a legacy ``crs`` member names. Several polygons are united. Refused, naming
    ``--cutline``: a missing or unreadable file, no geometry, a geometry other than a polygon,
    an invalid polygon."""
    import shapely

    what = f"--cutline {path}"
    try:
        check_input_file(path)
    except UsvError as exc:
        raise UsvError(f"--cutline {exc}") from None
    doc, geoms = _parse_geojson(path, what, "polygon")
    kinds = sorted({g.geom_type for g in geoms} - {"Polygon", "MultiPolygon"})
    if kinds:
        raise UsvError(f"{what}: not a polygon ({', '.join(kinds)})")
    area = shapely.union_all(geoms)
    if area.is_empty or not area.is_valid:
        reason = "empty" if area.is_empty else shapely.is_valid_reason(area)
        raise UsvError(f"{what}: not a valid polygon ({reason})")
    return area, _geojson_crs(doc, what)


def read_geojson(path: str | os.PathLike, bounds=None) -> VectorChart:
    """Read obstacle polygons from GeoJSON.

    Coordinates are lon/lat (RFC 7946) unless the file says otherwise: a legacy ``crs`` member
    names a CRS, and the foreign member ``"frame": "local"`` marks a local metre frame
    (synthetic maps). The extent is ``bounds``, else the file's ``bbox``, else the obstacles'.
    """
    import shapely
    from shapely.geometry import box

    check_input_file(path)
    doc, geoms = _parse_geojson(path, str(path), "file of obstacles")
    geoms = np.array(geoms, dtype=object)
    if geoms.size == 0:
        raise UsvError(f"{path}: no obstacle geometries")
    crs = None if doc.get("frame") == "local" else _geojson_crs(doc, str(path))
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


def _parse_geojson(path, what: str, expected: str) -> tuple[dict, list]:
    """The document and its non-empty shapely geometries (FeatureCollection, Feature or bare
    geometry); refused as "not a GeoJSON {expected}" naming ``what``."""
    from shapely.geometry import shape

    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
        features = doc["features"] if doc.get("type") == "FeatureCollection" else [doc]
        geoms = [shape(f["geometry"] if f.get("type") == "Feature" else f) for f in features]
    except (ValueError, KeyError, TypeError, AttributeError, UnicodeDecodeError) as exc:
        raise UsvError(f"{what}: not a GeoJSON {expected} ({_first_line(exc)})") from None
    return doc, [g for g in geoms if not g.is_empty]


def _geojson_crs(doc: dict, what: str):
    """The CRS a GeoJSON document's legacy ``crs`` member names, else lon/lat (RFC 7946)."""
    from rasterio.crs import CRS
    from rasterio.errors import CRSError

    try:
        return CRS.from_user_input((doc.get("crs") or {}).get("properties", {}).get("name", WGS84))
    except (CRSError, TypeError, ValueError, AttributeError) as exc:
        raise UsvError(f"{what}: unknown crs member ({_first_line(exc)})") from None


# --- pixels --------------------------------------------------------------------------------


def _read_pixels(ds, path) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """(index, palette, valid) of a dataset; ``valid`` None when every pixel is inside.

    16-bit and other NBITS colour is scaled to 8 bits (:func:`_to_8bit`); alpha 0 is outside
    the chart and partial alpha is composited over white (charts are printed on white). PNG
    and JPEG pixels are decoded by OpenCV, which refuses a truncated file where GDAL's drivers
    only log the libpng/libjpeg error and return partial pixels; their transparency is
    OpenCV's alpha (an alpha channel, or a PNG tRNS chunk).
    """
    bits = int(ds.tags(1, ns="IMAGE_STRUCTURE").get("NBITS", 0)) or None
    if ds.driver in ("PNG", "JPEG"):
        decoded = _decode_with_opencv(path, ds.driver, ds.width * ds.height)
        (colour, alpha), table, valid = decoded, None, None
    else:
        colour, alpha, table, valid = _read_bands(ds, path)
    if table is not None and alpha is not None:  # a palette with an alpha band: colour it
        colour, table = [table[colour[0], c] for c in range(3)], None
    elif table is None:
        colour = [_to_8bit(c, bits) for c in colour]
    if alpha is not None:
        outside = alpha == 0
        valid = ~outside if valid is None else valid & ~outside
        alpha8 = _to_8bit(alpha, bits)
        colour = [_over_white(c, alpha8) for c in colour]
    if len(colour) == 3:
        index, palette = index_packed(pack(*colour))
        return index, palette, valid
    if table is None:  # grey levels
        table = np.repeat(np.arange(256, dtype=np.uint8)[:, None], 4, axis=1)
        table[:, 3] = 255
    index, palette, inside = _index_table(colour[0], table, path)
    if inside is not None:
        valid = inside if valid is None else valid & inside
    return index, palette, valid


def _read_bands(ds, path):
    """(colour bands, alpha band or None, colour table or None, valid or None) read by GDAL.

    Colour is the first three non-alpha bands (RGB), else band 1 (palette when it has a colour
    table, else grey); the alpha band is the one GDAL calls alpha, else the 4th of four. GDAL's
    dataset mask gives the no-data values and mask bands.
    """
    from rasterio.enums import ColorInterp

    interp = list(ds.colorinterp)
    a = interp.index(ColorInterp.alpha) + 1 if ColorInterp.alpha in interp else None
    a = a or (4 if ds.count == 4 else None)
    bands = [i for i in range(1, ds.count + 1) if i != a]
    bands = bands[:3] if len(bands) >= 3 else bands[:1]
    for i in [*bands, a] if a else bands:
        _check_depth(ds.dtypes[i - 1], path)
    table = _colour_table(ds) if len(bands) == 1 else None
    valid = ds.dataset_mask() > 0 if _declares_mask(ds) else None
    return list(ds.read(bands)), (ds.read(a) if a else None), table, valid


def _decode_with_opencv(
    path, driver: str, pixels: int
) -> tuple[list[np.ndarray], np.ndarray | None]:
    """The colour channels (R, G, B or grey) and alpha channel of a PNG or JPEG of ``pixels``
    pixels. OpenCV decodes at most ``OPENCV_IO_MAX_IMAGE_PIXELS`` pixels (an environment
    variable, 2^30 without it): a larger image is refused in one line naming the limit."""
    import cv2

    text = os.environ.get("OPENCV_IO_MAX_IMAGE_PIXELS", "")
    limit = int(text) if text.isdigit() else 1 << 30
    if pixels > limit:
        raise UsvError(f"{path}: {pixels} pixels, more than OpenCV decodes ({limit}: "
                       "OPENCV_IO_MAX_IMAGE_PIXELS); convert it to a GeoTIFF")  # fmt: skip
    try:
        data = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    except cv2.error as exc:
        if exc.code == cv2.Error.StsNoMem:  # its allocation refused: the caller's memory guard
            raise MemoryError(_first_line(exc)) from None
        raise UsvError(f"{path}: OpenCV cannot decode this {driver} image "
                       f"({_first_line(exc)})") from None  # fmt: skip
    if data is None:
        raise UsvError(f"{path}: truncated or corrupt {driver} image")
    _check_depth(data.dtype, path)
    if data.ndim == 2:
        return [data], None
    return [data[..., 2], data[..., 1], data[..., 0]], data[..., 3] if data.shape[2] == 4 else None


def _check_depth(dtype, path) -> None:
    if np.dtype(dtype) not in (np.uint8, np.uint16):
        raise UsvError(f"{path}: expected 8- or 16-bit colour, found {np.dtype(dtype)}")


def _colour_table(ds) -> np.ndarray | None:
    """Band 1's colour table as (m, 4) RGBA rows covering every value of its data type (entries
    it leaves out are opaque black), or None."""
    try:
        cmap = ds.colormap(1)
    except ValueError:
        return None
    if not cmap:
        return None
    table = np.zeros((256 if ds.dtypes[0] == "uint8" else 65536, 4), np.uint8)
    table[:, 3] = 255
    for k, c in cmap.items():
        table[k] = c
    return table


def _declares_mask(ds) -> bool:
    """Whether some band has no-data or a mask band (an alpha band is read directly)."""
    from rasterio.enums import MaskFlags

    return any(
        MaskFlags.nodata in f or (MaskFlags.per_dataset in f and MaskFlags.alpha not in f)
        for f in ds.mask_flag_enums
    )


def _to_8bit(a: np.ndarray, bits: int | None) -> np.ndarray:
    """Colour or alpha values scaled to 0..255: ``round(v * 255 / (2**bits - 1))``.

    ``bits`` is the NBITS the file declares (GDAL's IMAGE_STRUCTURE metadata, e.g. 12 for a
    12-bit TIFF), else the data type's width. Full-range 16-bit data are so divided by 257,
    which recovers 8-bit colours stored as v * 257 exactly. The observed maximum is not used:
    a chart without pure white would be brightened and its colours would no longer match the
    reference chart colours.
    """
    bits = bits or 8 * a.dtype.itemsize
    if a.dtype == np.uint8 and bits == 8:
        return a
    full = (1 << bits) - 1
    scaled = (a.astype(np.uint32) * 255 + full // 2) // full
    return np.minimum(scaled, 255).astype(np.uint8)


def _over_white(c: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """8-bit colour ``c`` of opacity ``alpha`` composited over white, rounded."""
    a = alpha.astype(np.uint16)
    return ((c * a + 255 * (255 - a) + 127) // 255).astype(np.uint8)


def _index_table(band: np.ndarray, table: np.ndarray, path):
    """(index, palette, valid or None) of a band of colour-table entries (m, 4 RGBA).

    Entries of alpha 0 are outside the chart; partial alpha is composited over white. Entries
    sharing a colour are merged and unused ones dropped, so the palette holds distinct colours
    in entry order; when that leaves every used entry where it was (a KAP's table) the band is
    the index as it is, without a pass over the pixels.
    """
    import cv2

    m = len(table)
    seen = cv2.calcHist([band], [0], None, [m], [0, m]).ravel() > 0  # 8x a numpy scatter's speed
    opaque = table[:, 3] > 0
    keep = np.flatnonzero(seen & opaque)
    if keep.size == 0:
        raise UsvError(f"{path}: every pixel is transparent")
    colours = _over_white(table[keep, :3], table[keep, 3:])
    _, first, inverse = np.unique(
        pack(*colours.T), return_index=True, return_inverse=True
    )
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    lut = np.zeros(len(table), index_dtype(order.size))
    lut[keep] = rank[inverse]
    palette = colours[first[order]]
    same = band.dtype == lut.dtype and np.array_equal(lut[keep], keep)
    index = band if same else lut[band]
    valid = None if opaque[seen].all() else opaque[band]
    return index, palette, valid


# --- georeference --------------------------------------------------------------------------


def _warp(index, valid, nodata: int, *, src_crs, gcps=None, transform=None):
    """(index, valid, frame) warped north-up to the UTM zone of the chart's centre.

    The source is placed by its GCPs or by its geotransform, any affine (north-up, rotated,
    sheared or mirrored). GDAL suggests the output's extent and resolution, made square;
    ``calculate_default_transform`` takes no source transform, so a geotransform is given to it
    as its four corners (GCPs an order-1 fit reproduces exactly), and the frame is grown to
    whole pixels over the footprint (:func:`_covering`). Only the index band moves (nearest
    neighbour, GDAL's warper on :data:`WARP_THREADS` threads); ``nodata``, one past the last
    palette index, carries the pixels outside the chart and marks those outside the source;
    they get index 0 afterwards.
    """
    from rasterio.transform import from_gcps
    from rasterio.warp import Resampling, calculate_default_transform, reproject, transform_bounds

    height, width = index.shape
    src_transform = from_gcps(gcps) if gcps else transform
    xs, ys = src_transform @ (np.array([0, width, 0, width]), np.array([0, 0, height, height]))
    lon0, lat0 = _centre_lonlat(src_crs, xs.min(), ys.min(), xs.max(), ys.max(), transform_bounds)
    dst_crs = utm_crs(lon0, lat0)
    corners = gcps or _corner_gcps(src_transform, width, height)
    dst_transform, w, h = calculate_default_transform(src_crs, dst_crs, width, height, gcps=corners)
    res = float(np.sqrt(abs(dst_transform.a * dst_transform.e)))
    dst_transform, w, h = calculate_default_transform(
        src_crs, dst_crs, width, height, resolution=res, gcps=corners
    )
    if not gcps:
        w, h = _covering(dst_transform, w, h, src_transform, width, height, src_crs, dst_crs)
    if nodata > np.iinfo(index.dtype).max:
        index = index.astype(index_dtype(nodata))
    if valid is not None:
        index = np.where(valid, index, index.dtype.type(nodata))
    out = np.empty((h, w), index.dtype)
    reproject(
        index,
        out,
        src_transform=None if gcps else src_transform,
        gcps=gcps,
        src_crs=src_crs,
        src_nodata=None if valid is None else nodata,
        dst_transform=dst_transform,
        dst_crs=dst_crs,
        dst_nodata=nodata,
        resampling=Resampling.nearest,
        num_threads=WARP_THREADS,
    )
    inside = out != nodata
    np.multiply(out, inside, out=out, casting="unsafe")
    return out, inside, Frame(dst_transform, w, h, dst_crs)


def _corner_gcps(transform, width: int, height: int) -> list:
    """The four corners of a ``width`` x ``height`` raster as GCPs of ``transform``."""
    from rasterio.control import GroundControlPoint

    return [
        GroundControlPoint(row, col, *(transform @ (col, row)), z=0.0)
        for col, row in ((0, 0), (width, 0), (0, height), (width, height))
    ]


def _covering(dst_transform, w: int, h: int, src_transform, width, height, src_crs, dst_crs):
    """(w, h) grown to whole pixels over the source's footprint, its edges sampled at
    :data:`EDGE_SAMPLES` points each (GDAL's count): GDAL rounds its suggested size to the
    nearest pixel, which leaves up to half a pixel of the right and bottom edges out."""
    from rasterio.warp import transform as transform_points

    s = np.linspace(0, 1, EDGE_SAMPLES)
    cols = np.concatenate([s * width, np.full_like(s, width), s * width, np.zeros_like(s)])
    rows = np.concatenate([np.zeros_like(s), s * height, np.full_like(s, height), s * height])
    xs, ys = transform_points(src_crs, dst_crs, *(src_transform @ (cols, rows)))
    right = (max(xs) - dst_transform.c) / dst_transform.a
    bottom = (dst_transform.f - min(ys)) / -dst_transform.e
    return max(w, math.ceil(right - 1e-9)), max(h, math.ceil(bottom - 1e-9))


def _clip(valid: np.ndarray, frame: Frame, cutlines, path) -> None:
    """Clear, in place, the pixels of ``valid`` whose centre is outside any of the cutlines,
    (polygon, crs, name) triples; refused when no pixel is left."""
    import shapely
    from rasterio import features

    area = shapely.intersection_all(
        [reproject_geometries([poly], crs, frame.crs)[0] for poly, crs, _ in cutlines]
    )
    if not area.is_empty:
        shape = (frame.height, frame.width)
        valid &= features.geometry_mask([area], shape, frame.transform, invert=True)
    if area.is_empty or not valid.any():
        names = " and ".join(name for _, _, name in cutlines)
        raise UsvError(f"{path}: no part of the chart lies inside {names}")


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


def _first_line(exc: Exception) -> str:
    return str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
