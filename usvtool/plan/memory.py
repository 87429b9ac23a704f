"""The memory ``plan`` needs, estimated from the grid's header before its cells are read
(:mod:`usvtool.budget`).

:data:`PROCESS` plus :data:`CELL_BYTES` per cell: the grid and its blocked masks, the region
labels (int32), the collision check's clearance table (float64) and column counts (int32), and
an exact search's cost, parent and state per cell (A*'s are untouched until reached). Measured
peaks (``/usr/bin/time -v``, env1 scaled to 0.25-36 M cells; docs/planning.md): 24-95 bytes per
cell over a 256 MiB process, the largest, 78 at 4 M cells (astar), 75 at 16 M (anyangle and
iwso+g); every estimate lies 1-16 % above the measured peak.
"""

from __future__ import annotations

from usvtool.budget import MiB, require

PROCESS = 272 * MiB  # Python, NumPy, SciPy, OpenCV, GDAL and numba's kernels
CELL_BYTES = 80


def grid_need(width: int, height: int) -> int:
    """Bytes to plan on a ``width`` x ``height`` grid."""
    return PROCESS + width * height * CELL_BYTES


def check_grid(path, width: int, height: int, budget: int | None = None) -> None:
    """Refuse planning on a grid that would need more than ``budget`` bytes (None: the default
    budget): :func:`grid_need`."""
    require(grid_need(width, height), f"{path}: planning on {width} x {height} cells",
            "preprocess the chart with a larger --cell-size", budget)  # fmt: skip
