"""The memory ``plan`` needs, estimated from the grid's header before its cells are read
(:mod:`usvtool.budget`).

:data:`PROCESS` plus :data:`CELL_BYTES` per cell: the grid and its blocked masks, the region
labels (int32), the collision check's clearance table (float64) and column counts (int32), and
an exact search's cost, parent and state per cell (A*'s are untouched until reached). Measured
peaks (benchmarks/bench_memory.py: env1 scaled to 0.25-36 M cells, astar, anyangle, iwso and
iwso+g; docs/planning.md): up to 76 bytes per cell (astar on 4 M cells) over a process of
246-263 MiB; every estimate lies 8-45 % above the measured peak (anyangle on 36 M cells, whose
search reached few of them, 2.2 times).
"""

from __future__ import annotations

from contextlib import AbstractContextManager

from usvtool.budget import MiB, allocating, require

REMEDY = "preprocess the chart with a larger --cell-size"

PROCESS = 272 * MiB  # Python, NumPy, SciPy, OpenCV, GDAL and numba's kernels
CELL_BYTES = 80


def grid_need(width: int, height: int) -> int:
    """Bytes to plan on a ``width`` x ``height`` grid."""
    return PROCESS + width * height * CELL_BYTES


def check_grid(path, width: int, height: int, budget: int | None = None) -> None:
    """Refuse planning on a grid that would need more than ``budget`` bytes (None: the default
    budget): :func:`grid_need`."""
    require(grid_need(width, height), f"{path}: planning on {width} x {height} cells", REMEDY,
            budget)  # fmt: skip


def planning(path, width: int, height: int) -> AbstractContextManager:
    """The guard of the planning itself: a ``MemoryError`` past the estimate is one line naming
    the grid, its cells and the remedy (:func:`usvtool.budget.allocating`)."""
    return allocating(grid_need(width, height), f"planning on {width} x {height} cells of {path}",
                      REMEDY)  # fmt: skip
