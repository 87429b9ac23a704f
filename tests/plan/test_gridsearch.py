"""The exact planners' compiled kernels (usvtool/plan/gridsearch.py): the any-angle heuristic
against true distances (their line of sight is tested in tests/test_collision.py)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse.csgraph import dijkstra

from usvtool.plan import exact


def visibility_distances(blocked, points, goal, reference) -> np.ndarray:
    """Shortest collision-free distance from each of ``points`` to ``goal`` over a full
    visibility graph of every grid point moved 1e-5 into each quadrant (shapely's test)."""
    h, w = blocked.shape
    ys, xs = np.mgrid[0 : h + 1, 0 : w + 1]
    quadrants = np.array([(1, 1), (1, -1), (-1, 1), (-1, -1)]) * exact.DELTA
    grid = np.column_stack([xs.ravel(), ys.ravel()]).astype(float)
    pts = (grid[:, None, :] + quadrants[None]).reshape(-1, 2)
    pts = np.vstack([goal, points, pts[np.all((pts > 0) & (pts < (w, h)), axis=1)]])
    i, j = np.triu_indices(len(pts), k=1)
    seen = ~reference(blocked).segments_hit(pts[i], pts[j])
    weights = np.zeros((len(pts), len(pts)))
    d = np.hypot(*(pts[i[seen]] - pts[j[seen]]).T)
    weights[i[seen], j[seen]] = weights[j[seen], i[seen]] = d
    return dijkstra(weights, directed=False, indices=0)[1 : 1 + len(points)]


@pytest.mark.parametrize("seed", range(8))
def test_any_angle_heuristic_never_overestimates(seed, reference):
    """h(v) = max(|v - goal|, (D(v) - 2) / 1.0824), D the grid-point graph distance (exact where
    the search settled it, a lower bound elsewhere): at most the true distance at every vertex,
    (vertices the any-angle route cannot reach may have any estimate)."""
    rng = np.random.default_rng(seed)
    blocked = rng.random((7, 9)) < 0.3
    blocked[6, 0] = blocked[0, 8] = False
    start, goal = np.array([0.5, 6.5]), np.array([8.5, 0.5])
    corners, signs = exact.convex_corners(blocked)
    pos = np.vstack([[start, goal], corners - exact.DELTA * signs])
    free = np.pad(~blocked, 1).ravel()
    h, _ = exact._heuristic(free, blocked.shape, corners, pos, np.array([start, goal]))
    true = visibility_distances(blocked, pos[2:], goal, reference)
    reachable = np.isfinite(true)
    assert reachable.any()
    assert np.all(h[2:][reachable] <= true[reachable] + 1e-9)


def test_any_angle_heuristic_sees_round_a_wall():
    """A wall between start and goal with one gap at its far end, and one blocked cell near the
    start: at that cell's corner (1, 16) the estimate sees the way round (up 13 rows to the gap,
    1 across, down 16.5: about 30.7), at least (30.7 - 2) / 1.0824 = 26.5 and at most 30.7, not
    the 5.7 straight across."""
    blocked = np.zeros((20, 7), bool)
    blocked[3:, 3] = True  # gap in rows 0-2
    blocked[15, 0] = True
    start, goal = np.array([1.5, 19.5]), np.array([5.5, 19.5])
    corners, signs = exact.convex_corners(blocked)
    pos = np.vstack([[start, goal], corners - exact.DELTA * signs])
    h, apart = exact._heuristic(np.pad(~blocked, 1).ravel(), blocked.shape, corners, pos,
                                np.array([start, goal]))  # fmt: skip
    at = np.flatnonzero((corners == [1, 16]).all(axis=1))[0] + 2
    assert 26.0 < h[at] <= 30.8
    assert np.hypot(*(pos[at] - goal)) < 6
    # between the ends' cells: up 17 edges (from y 19 or 20 to y 3), 1 across, down 16-17
    assert 33 <= apart <= 37


def test_the_cell_search_grows_its_queue():
    """A detour round a wall of 298 cells (the ends 2 apart, the path 598 long): the search spans
    more buckets (its ``f`` 596 over the start's: 38 000 of 1/64) and queues more entries (the
    90 000 cells) than its queue starts with (2¹⁴, 2¹⁶), and still finds the shortest path."""
    blocked = np.zeros((300, 300), bool)
    blocked[:298, 150] = True
    path = exact._cell_path(~blocked, (0, 149), (0, 151))
    steps = np.diff(path, axis=0)
    assert path[0].tolist() == [0, 149] and path[-1].tolist() == [0, 151]
    assert np.all(np.abs(steps).max(axis=1) == 1) and not blocked[tuple(path.T)].any()
    assert np.hypot(*steps.T).sum() == 598.0
