"""Route shortening: the ``+s`` variant of every planner (never part of a faithful algorithm).

Two moves, each accepted only when the segments it creates touch no blocked cell (exact check),
so shortening never adds a collision, and each never lengthens the route:

1. Vertex removal: from the start, jump to the farthest later vertex still in line of sight, and
   repeat (the triangle inequality makes the route no longer).
2. Vertex pulling: move each interior vertex ``v`` towards the closest point ``p`` of the chord
   joining its neighbours ``a`` and ``b``, to the first free one of the positions
   ``v + 2^-k (p - v)``, ``k = 0 … STEPS - 1``. ``|a - x| + |x - b|`` is convex in ``x`` and least
   at ``p``, so every such move shortens the route; passes repeat until nothing moves (at most
   ``PASSES``; a vertex caught in the wedge of a corner closes in on it geometrically), then
   vertex removal runs again.

Together they pull the route taut against the corners it wraps around, within its homotopy
class: they remove the small detours and superfluous turns a population-based optimizer leaves.
"""

from __future__ import annotations

import numpy as np

from usvtool.collision import SegmentChecker

SUFFIX = "+s"
STEPS = 20
PASSES = 30


def shorten(checker: SegmentChecker, route) -> np.ndarray:
    """The route (cell coordinates ``(m, 2)``) shortened by vertex removal and pulling.

    >>> chk = SegmentChecker(np.zeros((4, 4), bool))
    >>> shorten(chk, [(0.5, 0.5), (1, 3), (2, 1), (3.5, 3.5)]).tolist()
    [[0.5, 0.5], [3.5, 3.5]]
    """
    return remove_vertices(checker, pull_vertices(checker, remove_vertices(checker, route)))


def remove_vertices(checker: SegmentChecker, route) -> np.ndarray:
    """Greedy vertex removal: keep only the farthest vertex in line of sight, from the start."""
    route = np.asarray(route, float)
    keep = [0]
    while keep[-1] < len(route) - 1:
        i = keep[-1]
        later = np.arange(i + 1, len(route))
        seen = later[~checker.collides(np.broadcast_to(route[i], (later.size, 2)), route[later])]
        keep.append(int(seen.max()) if seen.size else i + 1)
    return route[keep]


def pull_vertices(checker: SegmentChecker, route) -> np.ndarray:
    """Pull every interior vertex towards the chord of its neighbours (module docstring).

    >>> blocked = np.zeros((4, 4), bool); blocked[1:3, 1:3] = True
    >>> r = pull_vertices(SegmentChecker(blocked), [(0.5, 0.5), (0.5, 3.5), (3.5, 3.5)])
    >>> r.round(4).tolist()  # taut against the block's corner (1, 3)
    [[0.5, 0.5], [1.0, 3.0], [3.5, 3.5]]
    """
    route = np.array(route, float)
    fractions = 0.5 ** np.arange(STEPS)[:, None]  # the whole move first
    for _ in range(PASSES):
        moved = False
        for i in range(1, len(route) - 1):
            a, v, b = route[i - 1], route[i], route[i + 1]
            chord = b - a
            t = np.clip(np.dot(v - a, chord) / max(np.dot(chord, chord), 1e-300), 0.0, 1.0)
            spots = v + fractions * (a + t * chord - v)
            hit = checker.collides(
                np.concatenate([np.broadcast_to(a, spots.shape), spots]),
                np.concatenate([spots, np.broadcast_to(b, spots.shape)]),
            )
            free = ~hit.reshape(2, -1).any(axis=0)
            if free.any() and np.any(spots[np.argmax(free)] != v):
                route[i] = spots[np.argmax(free)]
                moved = True
        if not moved:
            break
    return route
