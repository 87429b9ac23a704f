"""The memory ``preprocess`` needs, estimated before it allocates (:mod:`usvtool.budget`).

Two phases peak, each checked before it starts:

- reading and segmenting a raster chart, checked from its header before any pixel is read
  (:func:`check_pixels`): :data:`PROCESS` plus, per pixel, the bytes of the bands read (RGB
  uint8: 3, RGBA uint16: 8, a palette: 1) and :data:`PIXEL_WORK` (the indexed colour, the
  valid mask, the segmentation's masks and labels, a warp's copies);
- gridding (:func:`check_cells`): per cell :data:`CELL_RASTER` (the occupancy products'
  float64 areas, the obstacle and distance arrays) beside :data:`PIXEL_HELD` per chart pixel
  still held, or for a vector chart :data:`CELL_VECTOR` (:data:`CELL_VECTOR_FINE` with
  ``occupancy`` > 0: the 8 x 8 finer raster and its mean).

The figures come from measured peaks (benchmarks/bench_memory.py; docs/preprocess.md has the
table): 18.1-18.6 bytes per pixel for RGB GeoTIFFs of 14-191 megapixels, 23.5 for a 16-bit
RGBA one, 18.3 for the palette KAP SanDiego_2 (warped), 11-12 bytes per cell for S-57 and
GeoJSON grids, 110-126 with ``occupancy``; the process itself (Python, NumPy, GDAL, OpenCV,
scikit-fuzzy) takes 130-230 MB. Every estimate lies 5-40 % above the measured peak.

Each check returns the guard (:func:`usvtool.budget.allocating`) its phase runs in.
"""

from __future__ import annotations

from contextlib import AbstractContextManager

from usvtool.budget import MiB, allocating, require

PROCESS = 256 * MiB  # the process and the 2^24-entry colour tables of colours.index_packed
PIXEL_WORK = 18  # bytes per pixel while reading and segmenting, beyond the bands read
PIXEL_HELD = 12  # bytes per chart pixel still held while gridding
CELL_RASTER = 34  # bytes per grid cell of a raster chart
CELL_VECTOR = 12  # bytes per grid cell of a vector chart (S-57, GeoJSON)
CELL_VECTOR_FINE = 120  # the same with occupancy > 0
MAX_BANDS = 4  # colour and alpha: the bands a raster source reads at most
PIXELS_REMEDY = "give a smaller chart image (e.g. gdal_translate -outsize or -srcwin)"
CELLS_REMEDY = "give a larger --cell-size"


def pixels_need(width: int, height: int, bands: int, itemsize: int) -> int:
    """Bytes to read and segment a ``width`` x ``height`` raster of ``bands`` bands of
    ``itemsize`` bytes."""
    return PROCESS + width * height * (min(bands, MAX_BANDS) * itemsize + PIXEL_WORK)


def cells_need(width: int, height: int, pixels: int, fine: bool) -> int:
    """Bytes to grid ``width`` x ``height`` cells from a raster of ``pixels`` pixels (0: a
    vector chart, ``fine`` with occupancy > 0)."""
    if pixels:
        return PROCESS + pixels * PIXEL_HELD + width * height * CELL_RASTER
    return PROCESS + width * height * (CELL_VECTOR_FINE if fine else CELL_VECTOR)


def check_pixels(path, width: int, height: int, bands: int, itemsize: int,
                 budget=None) -> AbstractContextManager:  # fmt: skip
    """Refuse reading a raster that would need more than ``budget`` bytes (None: the default
    budget): :func:`pixels_need`; else the guard to read it in."""
    need = pixels_need(width, height, bands, itemsize)
    require(need, f"{path}: reading {width} x {height} pixels", PIXELS_REMEDY, budget)
    return allocating(need, f"reading {width} x {height} pixels of {path}", PIXELS_REMEDY)


def segmenting(path, width: int, height: int) -> AbstractContextManager:
    """The guard of segmenting ``path``'s ``width`` x ``height`` indexed pixels (checked with
    its reading: :func:`check_pixels`)."""
    return allocating(pixels_need(width, height, 1, 1),
                      f"segmenting {width} x {height} pixels of {path}", PIXELS_REMEDY)  # fmt: skip


def check_cells(path, width: int, height: int, pixels: int, fine: bool,
                budget=None) -> AbstractContextManager:  # fmt: skip
    """Refuse gridding that would need more than ``budget`` bytes: :func:`cells_need`; else the
    guard to grid in."""
    need = cells_need(width, height, pixels, fine)
    require(need, f"{path}: gridding {width} x {height} cells", CELLS_REMEDY, budget)
    return allocating(need, f"gridding {width} x {height} cells of {path}", CELLS_REMEDY)
