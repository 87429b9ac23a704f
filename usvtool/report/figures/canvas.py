"""The canvas every figure is drawn on: one style, deterministic PNG bytes, the data as CSV.

A figure is a :class:`matplotlib.figure.Figure` on an Agg canvas (no pyplot: nothing global is
switched or left open, and the figure is freed with its last reference), drawn inside
:func:`figure`, which sets Matplotlib's defaults plus :data:`STYLE` and the print sizes of
:mod:`~usvtool.report.figures.styles` whatever the user's matplotlibrc holds. The PNG is
written at :data:`~usvtool.report.figures.styles.DPI` with no ``Software`` or date metadata, so
the same inputs give the same bytes in any process.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from usvtool.errors import UsvError
from usvtool.report.figures.styles import DPI, apply_rc

#: Settings beside :func:`~usvtool.report.figures.styles.rc_params` (its DPI and font sizes).
STYLE = {
    "axes.grid": True,
    "grid.alpha": 0.35,
    "grid.linewidth": 0.6,
    "axes.axisbelow": True,
    "image.interpolation": "antialiased",
    "figure.facecolor": "white",
    "savefig.facecolor": "white",
}


@dataclass(frozen=True)
class Plot:
    """A figure: its PNG and the CSV text (header row, ``\\n`` line ends) of what it plots."""

    png: bytes
    data: str


@contextmanager
def figure(width: float, height: float, layout: str = "constrained") -> Iterator:
    """A new figure of ``width`` x ``height`` inches under the fixed style and the fonts that
    print at >= 7 pt at its width (:func:`~usvtool.report.figures.styles.rc_params`), laid out
    by Matplotlib's ``layout`` (``compressed`` for maps: constrained layout that also closes the
    gaps of equal-aspect axes, whose labels it would otherwise leave outside the figure); draw
    and :func:`png` it inside the block (the style applies when it is drawn)."""
    import matplotlib as mpl
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    with mpl.rc_context():
        mpl.rcdefaults()
        mpl.rcParams.update(STYLE)
        apply_rc(width)
        fig = Figure(figsize=(width, height), dpi=DPI, layout=layout)
        FigureCanvasAgg(fig)
        yield fig


def png(fig) -> bytes:
    """The figure's PNG bytes: fixed size and dpi (its ``pHYs`` chunk), no metadata that
    varies. The canvas's pixels as ``savefig`` would write them (the figure is drawn at
    :data:`DPI` on white), saved by Pillow as RGB when no pixel is see-through (every figure
    here: a white figure), at zlib's default level: on the report's 75 figures 2.8 s and
    7.1 MB, against 11.8 s and 7.7 MB for Matplotlib's RGBA with Pillow's ``optimize``."""
    from PIL import Image

    fig.canvas.draw()
    rgba = np.asarray(fig.canvas.buffer_rgba())
    opaque = bool((rgba[..., 3] == 255).all())
    image = Image.fromarray(np.ascontiguousarray(rgba[..., :3]) if opaque else rgba)
    buf = io.BytesIO()
    image.save(buf, format="png", dpi=(DPI, DPI), compress_level=6)
    return buf.getvalue()


def csv_text(header: Iterable[str], rows: Iterable[Iterable]) -> str:
    """CSV text with a header row and ``\\n`` line ends."""
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(rows)
    return buf.getvalue()


def fixed(values, decimals: int) -> list[str]:
    """Fixed-point texts with ``decimals`` decimals, never ``-0.0…``.

    >>> fixed([1.23456, -0.0001, 2], 3)
    ['1.235', '0.000', '2.000']
    """
    texts = [f"{v:.{decimals}f}" for v in np.asarray(values, float).ravel().tolist()]
    return [s[1:] if s.startswith("-") and not s.strip("-0.") else s for s in texts]


def finite_array(where: str, values, ndim: int | None = None, columns: int | None = None):
    """``values`` as a float array, refused (one line naming ``where``) unless it is finite and
    of ``ndim`` dimensions with ``columns`` columns when given."""
    try:
        a = np.asarray(values, float)
    except (TypeError, ValueError):
        raise UsvError(f"{where}: not an array of numbers") from None
    if ndim is not None and a.ndim != ndim or columns is not None and a.shape[-1:] != (columns,):
        want = f"({'n, ' * (ndim - 1) if ndim else ''}{columns if columns else 'n'})"
        raise UsvError(f"{where}: has shape {a.shape}, expected {want}")
    if not np.isfinite(a).all():
        raise UsvError(f"{where}: holds NaN or infinite values")
    return a


def panel_grid(n: int, columns: int) -> tuple[int, int]:
    """(rows, columns) of a grid of ``n`` panels at most ``columns`` wide."""
    cols = max(1, min(n, columns))
    return math.ceil(n / cols), cols
