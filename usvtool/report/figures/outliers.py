"""One rule for an axis that a few far values would squash (docs/report-figures.md, "Outliers at
the axis's edge"): the box plots' value axes and the wind section's arrival differences.

The values are sorted; the ``k`` largest are **beyond** the axis when they lie further from the
rest than the rest spans (the gap from the rest's largest to the smallest of the ``k`` exceeds
the rest's range: drawn whole, the ``k`` values would leave the rest less than half the axis),
for the smallest such ``k`` up to :data:`FEW` and a quarter of the values; the same for the
smallest values, each side in turn until neither has more beyond. Nothing is beyond when the
rest has no range. The axis spans the rest,
padded by :data:`PAD` of its range; each value beyond is marked at the edge it is beyond
(:func:`mark`), with its value. No log axis: the arrival differences straddle 0 and turns count
from 0.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

#: The padding of a clipped axis beyond the rest's range (a share of that range), room for the
#: marks at its edge.
PAD = 0.12
#: At most this many values, and this share of them, are ever beyond one edge: a few far values,
#: never an algorithm's box of many runs, however far.
FEW, MOST = 3, 0.25
#: The marks stand this far inside the edge (a share of the axes), clear of what is beyond it.
EDGE = 0.012
#: The mark of a value beyond the axis: a triangle pointing out of it, in dark grey.
MARK = {"markersize": 6, "color": "0.15", "linestyle": "none", "clip_on": False, "zorder": 6}


class Limits(NamedTuple):
    """An axis's limits (``low``, ``high``) and the bounds past which a value is beyond it
    (``below``, ``above``: None when nothing is beyond on that side)."""

    low: float
    high: float
    below: float | None
    above: float | None

    @property
    def clipped(self) -> bool:
        return self.below is not None or self.above is not None


def _beyond_top(v: np.ndarray, most: int) -> int:
    """How many of the sorted ``v``'s largest values, at most ``most``, are beyond (the
    module's rule)."""
    for k in range(1, most + 1):
        rest = v[: v.size - k]
        span = rest[-1] - rest[0]
        if span > 0 and v[v.size - k] - rest[-1] > span:
            return k
    return 0


def limits(values) -> Limits | None:
    """The axis of ``values`` by the module's rule; None when there are none.

    >>> limits([1, 2, 3, 33])  # 33 is 30 past the rest's range of 2
    Limits(low=0.76, high=3.24, below=None, above=3.0)
    >>> limits([0, 1, 2, 3]).clipped, limits([3, 3, 3, 5]).clipped  # no gap; rest without range
    (False, False)
    >>> limits([-105, 0, 1, 2, 3, 4, 5, 6])  # one value far below
    Limits(low=-0.72, high=6.72, below=0.0, above=None)
    """
    v = np.sort(np.asarray(values, float).ravel())
    if v.size == 0:
        return None
    cap = min(FEW, int(MOST * v.size))
    top = bottom = 0
    while True:  # each side in turn, until neither has more beyond
        kept = v[bottom: v.size - top]
        k = _beyond_top(kept, cap - top)
        top += k
        if not k:
            k = _beyond_top(-kept[::-1], cap - bottom)
            bottom += k
        if not k:
            break
    lo, hi = float(kept[0]), float(kept[-1])
    if not top and not bottom:
        pad = 0.05 * (hi - lo) or 0.5
        return Limits(lo - pad, hi + pad, None, None)
    pad = PAD * (hi - lo)
    return Limits(round(lo - pad, 9), round(hi + pad, 9), lo if bottom else None,
                  hi if top else None)  # fmt: skip


def label(values) -> str:
    """The label of the values beyond one edge at one place: the furthest, and how many when
    more than one (``105`` or ``3: to 105``).

    >>> label([105.04]), label([40.0, 105.04, 60.0]), label([-0.0012])
    ('105', '3: to 105', '-0.0012')
    """
    v = np.asarray(values, float)
    far = float(v[np.argmax(np.abs(v))])
    text = f"{far:.3g}"
    return text if v.size == 1 else f"{v.size}: to {text}"


def mark(ax, where: float, values, edge: str, axis: str = "y") -> None:
    """Mark ``values`` beyond the ``edge`` (``low`` or ``high``) of the value axis ``axis``
    (``y``: a box plot's, ``x``: a horizontal one's) at position ``where`` on the other axis: a
    triangle on the edge pointing out, and :func:`label` beside it, inside the axes."""
    import matplotlib.transforms as mtransforms

    if not len(values):
        return
    at = 1.0 - EDGE if edge == "high" else EDGE
    inward = -1 if edge == "high" else 1
    if axis == "y":
        transform = mtransforms.blended_transform_factory(ax.transData, ax.transAxes)
        ax.plot(where, at, marker="^" if edge == "high" else "v", transform=transform, **MARK)
        ax.annotate(label(values), (where, at), xycoords=transform, rotation=90,
                    xytext=(0, inward * 6), textcoords="offset points", ha="center",
                    va="top" if edge == "high" else "bottom", color="0.15")  # fmt: skip
    else:
        transform = mtransforms.blended_transform_factory(ax.transAxes, ax.transData)
        ax.plot(at, where, marker=">" if edge == "high" else "<", transform=transform, **MARK)
        ax.annotate(label(values), (at, where), xycoords=transform, xytext=(inward * 6, 0),
                    textcoords="offset points", va="center",
                    ha="right" if edge == "high" else "left", color="0.15")  # fmt: skip
