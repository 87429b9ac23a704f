"""The navigation grid: the contract between preprocessing and planning.

A grid is a uint8 raster, ``0`` navigable, ``1`` obstacle (land, too shallow, hazard), ``2``
safety margin added by swelling, with an affine transform from (col, row) to map metres and,
when georeferenced, a projected metric CRS. Row 0 is the northern edge (GeoTIFF order); map
coordinates are x east, y north. A synthetic grid has no CRS and a local metre frame whose origin
is its lower-left corner.

>>> import numpy as np
>>> from affine import Affine
>>> g = Grid(np.zeros((2, 3), np.uint8), Affine(10, 0, 0, 0, -10, 20))
>>> g.cell_size, g.bounds
(10.0, (0.0, 0.0, 30.0, 20.0))
>>> g.cell_of(25.0, 1.0)
(1, 2)
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from affine import Affine

from usvtool.errors import UsvError, check_input_file

NAVIGABLE = 0
OBSTACLE = 1
MARGIN = 2


@dataclass(frozen=True)
class Grid:
    """A navigation grid (see the module docstring for the conventions)."""

    cells: np.ndarray
    transform: Affine
    crs: object | None = None  # rasterio.crs.CRS, kept untyped to avoid importing rasterio
    tags: dict[str, str] = field(default_factory=dict)

    @property
    def height(self) -> int:
        return int(self.cells.shape[0])

    @property
    def width(self) -> int:
        return int(self.cells.shape[1])

    @property
    def cell_size(self) -> float:
        """Side of a (square) cell in metres."""
        return float(self.transform.a)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(left, bottom, right, top) in map metres."""
        left, top = self.transform.c, self.transform.f
        return (
            float(left),
            float(top - self.height * self.cell_size),
            float(left + self.width * self.cell_size),
            float(top),
        )

    @property
    def blocked(self) -> np.ndarray:
        """Boolean mask of the cells a route must not enter (obstacle or margin)."""
        return self.cells != NAVIGABLE

    @cached_property
    def regions(self) -> np.ndarray:
        """Labels of the navigable regions (1, 2, …; 0 on blocked cells), computed once per grid.

        A region is a 4-connected component of the free cells: a route passes from one free
        cell to another only through a shared edge (crossing a corner touches the other two
        cells), so no collision-free route leaves its region.

        >>> g = Grid(np.array([[0, 1, 0], [1, 0, 0], [0, 0, 0]], np.uint8), Affine.identity())
        >>> g.regions.tolist()  # the north-west cell is cut off
        [[1, 0, 2], [0, 2, 2], [2, 2, 2]]
        """
        from scipy.ndimage import label

        return label(~self.blocked)[0]

    def region_at(self, col: float, row: float) -> int:
        """Label of the region holding the continuous cell coordinates ``(col, row)`` (the far
        edges count in the last row and column)."""
        return int(self.regions[min(int(row), self.height - 1), min(int(col), self.width - 1)])

    def to_cell_coords(self, x, y):
        """Map metres to continuous (col, row) cell coordinates (cell centres at .5)."""
        left, _, _, top = self.bounds
        s = self.cell_size
        return (np.asarray(x, float) - left) / s, (top - np.asarray(y, float)) / s

    def to_map(self, col, row):
        """Continuous (col, row) cell coordinates to map metres."""
        left, _, _, top = self.bounds
        s = self.cell_size
        return left + np.asarray(col, float) * s, top - np.asarray(row, float) * s

    def cell_of(self, x: float, y: float) -> tuple[int, int]:
        """(row, col) of the cell holding the map point (x, y)."""
        col, row = self.to_cell_coords(x, y)
        return int(np.floor(row)), int(np.floor(col))

    def contains(self, x: float, y: float) -> bool:
        left, bottom, right, top = self.bounds
        return left <= x < right and bottom < y <= top


def read_grid(
    path: str | os.PathLike, check_size: Callable[[int, int], None] | None = None
) -> Grid:
    """Read a grid GeoTIFF written by :func:`write_grid` (or any single-band uint8 raster).

    ``check_size(width, height)``, when given, is called with the grid's size from its header
    before its cells are read (a memory guard raises there: :mod:`usvtool.budget`)."""
    import warnings

    import rasterio
    from rasterio.errors import NotGeoreferencedWarning, RasterioIOError

    check_input_file(path)
    try:
        with warnings.catch_warnings():  # no geotransform: refused below, in one line
            warnings.simplefilter("ignore", NotGeoreferencedWarning)
            with rasterio.open(path) as ds:
                if ds.count != 1:
                    raise UsvError(f"{path}: a grid has one band, this raster has {ds.count}")
                if check_size is not None:
                    check_size(ds.width, ds.height)
                cells = ds.read(1)
                transform, crs, tags = ds.transform, ds.crs, ds.tags()
    except RasterioIOError as exc:
        raise UsvError(f"{path}: not a readable grid GeoTIFF ({exc})") from None
    if cells.dtype != np.uint8 or cells.max(initial=0) > MARGIN:
        raise UsvError(f"{path}: not a navigation grid (expected uint8 values 0, 1, 2)")
    if transform.is_identity:
        raise UsvError(f"{path}: no geotransform; a map is a grid GeoTIFF (usvtool preprocess)")
    if transform.b != 0 or transform.d != 0 or abs(transform.a + transform.e) > 1e-9 * abs(
        transform.a
    ):
        raise UsvError(
            f"{path}: grid cells must be square and north-up (preprocess a rotated chart: "
            "it is warped north-up)"
        )
    return Grid(cells, transform, crs, tags)


def write_grid(path: str | os.PathLike, grid: Grid) -> None:
    """Write ``grid`` as a compressed single-band uint8 GeoTIFF, atomically."""
    import rasterio

    from usvtool.atomic import atomic_path

    profile = dict(
        driver="GTiff",
        height=grid.height,
        width=grid.width,
        count=1,
        dtype="uint8",
        transform=grid.transform,
        crs=grid.crs,
        compress="deflate",
    )
    with atomic_path(path) as tmp:
        with rasterio.open(tmp, "w", **profile) as ds:
            ds.write(grid.cells.astype(np.uint8), 1)
            ds.update_tags(**{k: _tag(v) for k, v in grid.tags.items()})
            ds.write_colormap(1, {0: (212, 234, 238), 1: (201, 185, 122), 2: (240, 120, 80)})


def _tag(value) -> str:
    return value if isinstance(value, str) else json.dumps(value)
