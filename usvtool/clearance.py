"""Clearance: how far a map point is from the grid's blocked cells, for many points at once.

The simulation's controllers roll every velocity sample out over their horizon and need, at each
predicted position, the distance to the nearest static obstacle; the exact segment check of
:mod:`usvtool.collision` answers yes or no for one segment at a time. This is the field version:

- *blocked* cells are the grid's obstacle and margin cells (:attr:`usvtool.grid.Grid.blocked`),
  and everything outside the grid;
- the clearance of a point is the Euclidean distance from the centre of its cell to the centre of
  the nearest blocked cell, less half a cell (the distance to that cell's near side, exact along
  rows and columns and within half a cell's diagonal otherwise), in metres; zero in a blocked
  cell and outside the grid.

The distance transform is OpenCV's exact Euclidean one (``DIST_MASK_PRECISE``), computed once per
grid; a query is one gather.

>>> import numpy as np
>>> from affine import Affine
>>> from usvtool.grid import Grid
>>> cells = np.zeros((5, 5), np.uint8); cells[2, 4] = 1  # one obstacle cell at the east edge
>>> field = Clearance(Grid(cells, Affine(10, 0, 0, 0, -10, 50)))
>>> field.at(np.array([25.0, 35.0, 45.0, 5.0, -1.0]), np.array([25.0, 25.0, 25.0, 45.0, 0.0]))
array([15.,  5.,  0.,  5.,  0.])
"""

from __future__ import annotations

import cv2
import numpy as np

from usvtool.grid import Grid


class Clearance:
    """The clearance field of a grid (see the module docstring)."""

    def __init__(self, grid: Grid):
        self.grid = grid
        free = np.pad(~grid.blocked, 1).astype(np.uint8)  # the outside is blocked
        dist = cv2.distanceTransform(free, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)[1:-1, 1:-1]
        #: the clearance of each cell (m), rows from the north as in the grid
        self.metres = np.where(dist > 0, (dist - 0.5) * grid.cell_size, 0.0).astype(float)
        #: the clearances with a zero border (everything outside), raveled in rows of width + 2:
        #: the table :meth:`at` indexes
        self.padded = np.pad(self.metres, 1).ravel()

    def at(self, x, y) -> np.ndarray:
        """Clearance in metres at the map points ``(x, y)`` (arrays of one shape)."""
        left, _, _, top = self.grid.bounds
        scale = 1.0 / self.grid.cell_size
        h, w = self.metres.shape
        # indices into the padded field, whose border (zero) stands for everything outside;
        # clipped to be >= 0 first, so truncation is the floor
        col = np.clip((np.asarray(x, float) - left) * scale + 1, 0, w + 1).astype(np.intp)
        row = np.clip((top - np.asarray(y, float)) * scale + 1, 0, h + 1).astype(np.intp)
        return self.padded[row * (w + 2) + col]
