"""Drawing a navigation grid or its chart behind a figure, fast at any size, and its map axes.

The grid is shown navigable white, obstacle dark and safety margin light grey, in map metres
(row 0 the northern edge); cells outside the chart (known from the chart's preview) hatched.
A grid longer than :data:`MAX_SIDE` cells on a side is reduced for display by whole blocks of
``f x f`` cells, each shown as its most important class (obstacle over margin over navigable),
so that no obstacle, however thin, disappears: one table look-up and one reshaped ``max`` over
the cells, about 0.1 s for 12 million of them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from usvtool.grid import MARGIN, NAVIGABLE, OBSTACLE, Grid
from usvtool.report.figures.canvas import fixed

MAX_SIDE = 1500
#: Display colours and names of the classes, by cell value.
CLASS_RGB = {NAVIGABLE: (255, 255, 255), OBSTACLE: (64, 64, 64), MARGIN: (200, 200, 200)}
CLASS_NAMES = {NAVIGABLE: "navigable", OBSTACLE: "obstacle", MARGIN: "safety margin"}
#: The preview PNG of ``usvtool preprocess --preview`` (docs/preprocess.md; the chart stage's
#: usvtool/chart/preview.py, which the report may not import): its map, north up over the grid's
#: bounds, stands on a white strip of 3 rows of 24 px and 8 px padding; obstacle pixels outside
#: the chart are hatched in these two greys, obstacle cells tinted red and margin cells yellow
#: at opacity 0.6, each swatch of its legend drawn over this water colour.
PREVIEW_STRIP_PX = 3 * 24 + 8
PREVIEW_HATCH = ((160, 160, 160), (90, 90, 90))
PREVIEW_TINT = {OBSTACLE: (200, 30, 30), MARGIN: (250, 200, 0)}
PREVIEW_TINT_ALPHA = 0.6
PREVIEW_WATER = (212, 234, 238)
#: Outside the chart, as its legend and the grid panels show it: the preview's hatch.
OUTSIDE_NAME = "outside the chart (no data)"
#: Above this extent (m) map axes are labelled in kilometres.
KM_ABOVE = 5000.0
#: Tick intervals on a map axis, at most.
TICKS = 5
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


@dataclass(frozen=True)
class ChartImage:
    """A chart drawn north up over map metres: ``rgb`` ``(h, w, 3)`` uint8 covering ``extent``
    (left, right, bottom, top), and ``outside`` ``(h, w)``, its pixels outside the chart."""

    rgb: np.ndarray
    extent: tuple[float, float, float, float]
    outside: np.ndarray


def preview_chart(path: str | Path, grid: Grid) -> ChartImage | None:
    """The map of the preview PNG at ``path`` (``usvtool preprocess --preview``) over ``grid``'s
    bounds, without its strip: its height the PNG's less :data:`PREVIEW_STRIP_PX`, its width
    that height times the grid's aspect (to a pixel: the preview rounds both), its outside
    the pixels of the :data:`PREVIEW_HATCH` greys on obstacle cells. None when the file is
    missing or unreadable or its size does not fit the grid's shape."""
    import cv2

    path = Path(path)
    image = cv2.imread(str(path), cv2.IMREAD_COLOR) if path.is_file() else None
    if image is None:
        return None
    h = image.shape[0] - PREVIEW_STRIP_PX
    w = round(h * grid.width / grid.height) if h > 0 else 0
    if w < 1 or w > image.shape[1] + 1:
        return None
    w = min(w, image.shape[1])
    rgb = np.ascontiguousarray(image[:h, :w, ::-1])
    left, bottom, right, top = grid.bounds
    rows = np.minimum(((np.arange(h) + 0.5) * grid.height / h).astype(int), grid.height - 1)
    cols = np.minimum(((np.arange(w) + 0.5) * grid.width / w).astype(int), grid.width - 1)
    blocked = grid.cells[np.ix_(rows, cols)] == OBSTACLE
    grey = np.zeros((h, w), bool)
    for colour in PREVIEW_HATCH:
        grey |= (rgb == colour).all(axis=2)
    return ChartImage(rgb, (left, right, bottom, top), grey & blocked)


def chart_window(chart: ChartImage, view: tuple[float, float, float, float]):
    """(rows, columns, extent): the slices of ``chart``'s pixels within ``view`` (left, bottom,
    right, top; the pixels it cuts included) and their extent (left, right, bottom, top)."""
    left, right, bottom, top = chart.extent
    h, w = chart.rgb.shape[:2]
    px, py = (right - left) / w, (top - bottom) / h
    c0, c1 = np.clip([math.floor((view[0] - left) / px), math.ceil((view[2] - left) / px)], 0, w)
    r0, r1 = np.clip([math.floor((top - view[3]) / py), math.ceil((top - view[1]) / py)], 0, h)
    c1, r1 = max(c0, c1), max(r0, r1)
    extent = (left + c0 * px, left + c1 * px, top - r1 * py, top - r0 * py)
    return slice(r0, r1), slice(c0, c1), tuple(float(v) for v in extent)


def draw_chart(ax, chart: ChartImage, view: tuple[float, float, float, float]) -> None:
    """Draw the pixels of ``chart`` within ``view`` (left, bottom, right, top) on ``ax`` in map
    metres, at the back; the limits are left to the caller."""
    rows, cols, extent = chart_window(chart, view)
    if rows.start < rows.stop and cols.start < cols.stop:
        ax.imshow(chart.rgb[rows, cols], extent=extent, origin="upper",
                  interpolation="antialiased", zorder=0)  # fmt: skip


def draw_outside(ax, chart: ChartImage) -> None:
    """Hatch, over what is drawn, the pixels of ``chart`` outside the chart (a grid panel's
    cells that the grid calls obstacle for want of data)."""
    if not chart.outside.any():
        return
    h, w = chart.outside.shape
    rgba = np.zeros((h, w, 4), np.uint8)
    stripe = np.add.outer(np.arange(h), np.arange(w)) % 6 == 0
    rgba[..., :3] = np.where(stripe[..., None], PREVIEW_HATCH[1], PREVIEW_HATCH[0])
    rgba[..., 3] = np.where(chart.outside, 255, 0)
    ax.imshow(rgba, extent=chart.extent, origin="upper", interpolation="nearest", zorder=0.5)


def outside_handle(percent: float | None = None):
    """The legend patch of outside the chart: the preview's grey, hatched; with ``percent``, the
    share of the map it covers (of the obstacle's share: the grid counts it as obstacle)."""
    from matplotlib.patches import Patch

    label = OUTSIDE_NAME if percent is None else f"{OUTSIDE_NAME}: {percent:.1f} %, of obstacle's"
    return Patch(facecolor=np.array(PREVIEW_HATCH[0]) / 255,
                 edgecolor=np.array(PREVIEW_HATCH[1]) / 255, hatch="////", linewidth=0.6,
                 label=label)  # fmt: skip


def chart_handles(outside: bool = True) -> list:
    """Legend patches of a chart drawn by its preview: the classes as its own legend draws them
    (each over :data:`PREVIEW_WATER`), then outside the chart when ``outside``."""
    from matplotlib.patches import Patch

    water = np.array(PREVIEW_WATER, float)
    colours = {NAVIGABLE: water}
    colours.update({c: (1 - PREVIEW_TINT_ALPHA) * water + PREVIEW_TINT_ALPHA * np.array(rgb)
                    for c, rgb in PREVIEW_TINT.items()})  # fmt: skip
    names = {NAVIGABLE: "navigable (the chart)", OBSTACLE: "obstacle (tinted red)",
             MARGIN: "safety margin (tinted yellow)"}  # fmt: skip
    return [*(Patch(facecolor=colours[c] / 255, edgecolor="0.3", linewidth=0.6, label=names[c])
              for c in (NAVIGABLE, OBSTACLE, MARGIN)), *([outside_handle()] if outside else [])]


def fit_view(x, y, pad_fraction: float, aspect_range: tuple[float, float],
             bounds: tuple[float, float, float, float] | None = None):
    """(left, bottom, right, top): the box around the points ``x``, ``y`` padded on every side
    by ``pad_fraction`` of its longer side, widened about its centre in its shorter direction
    until its width / height lies in ``aspect_range``, then shifted into ``bounds`` and clipped
    to them when given (the view of a chart's routes: the routes, not the whole chart).

    >>> fit_view([0, 100], [0, 10], 0.1, (0.5, 2.0))
    (-10.0, -25.0, 110.0, 35.0)
    >>> fit_view([0, 100], [0, 10], 0.1, (0.5, 2.0), bounds=(0, 0, 200, 200))
    (0.0, 0.0, 120.0, 60.0)
    """
    x, y = np.asarray(x, float).ravel(), np.asarray(y, float).ravel()
    pad = pad_fraction * max(np.ptp(x), np.ptp(y), 1e-9)
    half = [np.ptp(x) / 2 + pad, np.ptp(y) / 2 + pad]
    low, high = aspect_range
    half[1] = max(half[1], half[0] / high)
    half[0] = max(half[0], half[1] * low)
    centre = [(x.min() + x.max()) / 2, (y.min() + y.max()) / 2]
    if bounds is not None:
        for k in (0, 1):
            lo, hi = bounds[k], bounds[k + 2]
            centre[k] = min(max(centre[k], lo + half[k]), hi - half[k]) \
                if 2 * half[k] <= hi - lo else (lo + hi) / 2
            half[k] = min(half[k], (hi - lo) / 2)
    return tuple(float(v) for v in (centre[0] - half[0], centre[1] - half[1],
                                    centre[0] + half[0], centre[1] + half[1]))


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
    shown, m) exceeds :data:`KM_ABOVE`, at most :data:`TICKS` + 1 round ticks a side (six-digit
    eastings do not run into each other); easting and northing with the CRS named when given."""
    from matplotlib.ticker import FuncFormatter, MaxNLocator

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
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_locator(MaxNLocator(nbins=TICKS, steps=[1, 2, 2.5, 5, 10]))
        axis.set_major_formatter(formatter)
