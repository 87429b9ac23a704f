"""Drawing a navigation grid behind a figure, fast at any size, and its map axes.

The grid is shown navigable white, obstacle dark and safety margin light grey, in map metres
(row 0 the northern edge). A grid longer than :data:`MAX_SIDE` cells on a side is reduced for
display by whole blocks of ``f x f`` cells, each shown as its most important class (obstacle
over margin over navigable), so that no obstacle, however thin, disappears: one table look-up
and one reshaped ``max`` over the cells, about 0.1 s for 12 million of them.
"""

from __future__ import annotations

import math

import numpy as np

from usvtool.grid import MARGIN, NAVIGABLE, OBSTACLE, Grid
from usvtool.report.figures.canvas import fixed

MAX_SIDE = 1500
#: Display colours and names of the classes, by cell value.
CLASS_RGB = {NAVIGABLE: (255, 255, 255), OBSTACLE: (64, 64, 64), MARGIN: (200, 200, 200)}
CLASS_NAMES = {NAVIGABLE: "navigable", OBSTACLE: "obstacle", MARGIN: "safety margin"}
#: Above this extent (m) map axes are labelled in kilometres.
KM_ABOVE = 5000.0
_RANK = np.zeros(256, np.uint8)  # display priority by cell value: obstacle > margin > navigable
_RANK[[NAVIGABLE, MARGIN, OBSTACLE]] = [0, 1, 2]
_RANK_RGB = np.array([CLASS_RGB[NAVIGABLE], CLASS_RGB[MARGIN], CLASS_RGB[OBSTACLE]], np.uint8)


def display_rgb(cells: np.ndarray, max_side: int = MAX_SIDE) -> tuple[np.ndarray, int]:
    """The RGB image ``(ceil(h / f), ceil(w / f), 3)`` of ``cells`` and the block side ``f``
    (the smallest with both sides at most ``max_side``); edge blocks are padded navigable.

    >>> rgb, f = display_rgb(np.array([[0, 0, 2, 0], [0, 1, 0, 0]], np.uint8), max_side=2)
    >>> f, rgb[..., 0].tolist()  # the left block holds the obstacle, the right the margin
    (2, [[64, 200]])
    """
    h, w = cells.shape
    f = max(1, math.ceil(max(h, w) / max_side))
    rank = _RANK[cells]
    if f > 1:
        hp, wp = -(-h // f) * f, -(-w // f) * f
        if (hp, wp) != (h, w):
            rank = np.pad(rank, ((0, hp - h), (0, wp - w)))
        rank = rank.reshape(hp // f, f, wp // f, f).max(axis=(1, 3))
    return _RANK_RGB[rank], f


def draw_grid(ax, grid: Grid, view: tuple[float, float, float, float] | None = None) -> None:
    """Draw ``grid`` on ``ax`` in map metres, only the cells within ``view`` (left, bottom,
    right, top) when given, at the back; the limits are left to the caller."""
    cells, left, top = grid.cells, grid.bounds[0], grid.bounds[3]
    s = grid.cell_size
    if view is not None:
        c0, c1 = (np.clip([math.floor((view[0] - left) / s), math.ceil((view[2] - left) / s)],
                          0, grid.width))  # fmt: skip
        r0, r1 = np.clip([math.floor((top - view[3]) / s), math.ceil((top - view[1]) / s)],
                         0, grid.height)  # fmt: skip
        if c0 >= c1 or r0 >= r1:
            return
        cells, left, top = cells[r0:r1, c0:c1], left + c0 * s, top - r0 * s
    rgb, f = display_rgb(cells)
    h, w = rgb.shape[:2]
    extent = (left, left + w * f * s, top - h * f * s, top)
    ax.imshow(rgb, extent=extent, origin="upper", interpolation="antialiased", zorder=0)


def square_view(x, y, pad_fraction: float, min_pad: float = 0.0,
                bounds: tuple[float, float, float, float] | None = None):
    """(left, bottom, right, top): the square around the points ``x``, ``y``, padded by the
    larger of ``pad_fraction`` of its side and ``min_pad``, clipped to ``bounds`` when given.

    >>> square_view([0, 10], [0, 4], 0.1, bounds=(-100, 0, 100, 100))
    (-1.0, 0.0, 11.0, 8.0)
    """
    x, y = np.asarray(x, float).ravel(), np.asarray(y, float).ravel()
    cx, cy = (x.min() + x.max()) / 2, (y.min() + y.max()) / 2
    side = max(x.max() - x.min(), y.max() - y.min())
    half = side / 2 + max(pad_fraction * side, min_pad)
    view = (cx - half, cy - half, cx + half, cy + half)
    if bounds is not None:
        view = (max(view[0], bounds[0]), max(view[1], bounds[1]), min(view[2], bounds[2]),
                min(view[3], bounds[3]))  # fmt: skip
    return tuple(float(v) for v in view)


def class_handles(cells: np.ndarray | None = None) -> list:
    """Legend patches of the three classes, each with its share of ``cells`` when given."""
    from matplotlib.patches import Patch

    handles = []
    for value, name in CLASS_NAMES.items():
        label = name if cells is None else f"{name} ({share(cells, value):.1f} %)"
        handles.append(Patch(facecolor=np.array(CLASS_RGB[value]) / 255, edgecolor="0.3",
                             linewidth=0.6, label=label))  # fmt: skip
    return handles


def share(cells: np.ndarray, value: int) -> float:
    """Percentage of ``cells`` holding ``value``."""
    return 100.0 * float(np.count_nonzero(cells == value)) / cells.size


def map_axes(ax, span: float, crs=None) -> None:
    """Equal-aspect axes labelled in map metres, or kilometres when ``span`` (the larger extent
    shown, m) exceeds :data:`KM_ABOVE`; easting and northing with the CRS named when given."""
    from matplotlib.ticker import FuncFormatter

    ax.set_aspect("equal", adjustable="box")
    ax.grid(False)
    km = span > KM_ABOVE
    unit = "km" if km else "m"
    if crs is None:
        ax.set_xlabel(f"x ({unit})")
        ax.set_ylabel(f"y ({unit})")
    else:
        name = crs.to_string() if hasattr(crs, "to_string") else str(crs)
        ax.set_xlabel(f"easting ({unit}, {name})")
        ax.set_ylabel(f"northing ({unit})")
    scale = 1000.0 if km else 1.0
    formatter = FuncFormatter(lambda v, _: fixed([v / scale], 3)[0].rstrip("0").rstrip("."))
    ax.xaxis.set_major_formatter(formatter)
    ax.yaxis.set_major_formatter(formatter)
