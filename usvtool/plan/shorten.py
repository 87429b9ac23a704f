"""Route shortening: the ``+s`` variant of every planner (never part of a faithful algorithm).

From the start, jump to the farthest later vertex still in exact line of sight, and repeat. A
shortcut is taken only when it touches no blocked cell, so shortening never adds a collision,
and by the triangle inequality it never makes the route longer; it usually removes the small
detours and superfluous turns that a population-based optimizer leaves behind.
"""

from __future__ import annotations

import numpy as np

from usvtool.plan.raster import SegmentChecker

SUFFIX = "+s"


def shorten(checker: SegmentChecker, route) -> np.ndarray:
    """The route (cell coordinates ``(m, 2)``) with every removable vertex removed, greedily.

    >>> chk = SegmentChecker(np.zeros((4, 4), bool))
    >>> shorten(chk, [(0.5, 0.5), (1, 3), (2, 1), (3.5, 3.5)]).tolist()
    [[0.5, 0.5], [3.5, 3.5]]
    """
    route = np.asarray(route, float)
    keep = [0]
    while keep[-1] < len(route) - 1:
        i = keep[-1]
        later = np.arange(i + 1, len(route))
        seen = later[~checker.collides(np.broadcast_to(route[i], (later.size, 2)), route[later])]
        keep.append(int(seen.max()) if seen.size else i + 1)
    return route[keep]
