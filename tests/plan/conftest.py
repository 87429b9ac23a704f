"""Planner test fixtures: an independent collision reference written plainly with shapely.

A segment collides when it intersects the closed unit square of a blocked cell (edges and
corners included); shapely's predicates are exact, so no tolerance is involved.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely


class ShapelyReference:
    """Blocked cells of ``blocked`` (row 0 = y 0) as closed boxes in cell coordinates, grown
    by ``grow`` on every side."""

    def __init__(self, blocked: np.ndarray, grow: float = 0.0):
        rows, cols = np.nonzero(blocked)
        boxes = shapely.box(cols - grow, rows - grow, cols + 1 + grow, rows + 1 + grow)
        self.tree = shapely.STRtree(boxes)

    def segments_hit(self, a, b) -> np.ndarray:
        """Whether each segment ``a[i] → b[i]`` intersects a blocked cell's closed square."""
        lines = shapely.linestrings(np.stack([np.asarray(a, float), np.asarray(b, float)], 1))
        hit_lines, _ = self.tree.query(lines, predicate="intersects")
        out = np.zeros(len(lines), bool)
        out[hit_lines] = True
        return out

    def route_free(self, route) -> bool:
        """Whether the polyline (cell coordinates) touches no blocked cell."""
        route = np.asarray(route, float)
        return not self.segments_hit(route[:-1], route[1:]).any()


@pytest.fixture(scope="session")
def reference():
    """``reference(blocked)``: the :class:`ShapelyReference` of a blocked mask."""
    return ShapelyReference
