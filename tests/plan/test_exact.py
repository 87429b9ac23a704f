"""Exact planners: optimal on hand-made grids, and every planned route collision-free."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.sparse.csgraph import dijkstra

from usvtool import measures
from usvtool.collision import SegmentChecker
from usvtool.grid import Grid, read_grid
from usvtool.plan.exact import DELTA, any_angle, astar
from usvtool.plan.planner import PlanOptions, plan_route
from usvtool.plan.shorten import shorten

SQ2 = math.sqrt(2)


def wall() -> np.ndarray:
    """5 x 5, column 2 blocked in rows 0-3: the only way east is through row 4."""
    b = np.zeros((5, 5), bool)
    b[0:4, 2] = True
    return b


def length(route) -> float:
    return float(measures.path_length(route))


def test_astar_is_optimal_on_hand_made_grids():
    free = np.zeros((5, 5), bool)
    assert astar(free, (0.5, 0.5), (4.5, 4.5)).tolist() == [[0.5, 0.5], [4.5, 4.5]]
    # down column 0-1 (3 + √2), through row 4 (2), up column 3-4 (3 + √2); no corner cutting
    route = astar(wall(), (0.5, 0.5), (4.5, 0.5))
    assert length(route) == pytest.approx(8 + 2 * SQ2)
    assert astar(wall(), (0.5, 0.5), (0.5, 4.5)).tolist() == [[0.5, 0.5], [0.5, 4.5]]


def test_astar_does_not_cut_corners_and_reports_no_route():
    b = np.zeros((2, 2), bool)
    b[0, 1] = b[1, 0] = True  # the free cells touch only at a corner
    assert astar(b, (0.5, 0.5), (1.5, 1.5)) is None


def brute_force_8_connected(blocked, start, goal) -> float:
    """Start → centres → goal length of the shortest 8-connected cell path, by scipy's Dijkstra
    on a dense matrix of every allowed move (a diagonal only with both side cells free)."""
    h, w = blocked.shape
    n = h * w
    weights = np.zeros((n, n))
    for r in range(h):
        for c in range(w):
            for dr in (-1, 0, 1):
                for dc in (-1, 0, 1):
                    rr, cc = r + dr, c + dc
                    if (dr or dc) and 0 <= rr < h and 0 <= cc < w:
                        if blocked[r, c] or blocked[rr, cc]:
                            continue
                        if dr and dc and (blocked[r, cc] or blocked[rr, c]):
                            continue
                        weights[r * w + c, rr * w + cc] = SQ2 if dr and dc else 1.0
    s = (int(start[1]), int(start[0]))
    t = (int(goal[1]), int(goal[0]))
    d = dijkstra(weights, indices=s[0] * w + s[1])[t[0] * w + t[1]]
    ends = math.hypot(start[0] - s[1] - 0.5, start[1] - s[0] - 0.5)
    return d + ends + math.hypot(goal[0] - t[1] - 0.5, goal[1] - t[0] - 0.5)


@pytest.mark.parametrize("seed", range(40))
def test_astar_matches_a_brute_force_dijkstra(seed, reference):
    rng = np.random.default_rng(seed)
    h, w = rng.integers(3, 16, 2)
    blocked = rng.random((h, w)) < rng.uniform(0.05, 0.45)
    free = np.argwhere(~blocked)
    if len(free) < 2:
        pytest.skip("no two free cells")
    (r0, c0), (r1, c1) = free[rng.choice(len(free), 2, replace=False)]
    start = (c0 + rng.uniform(0.1, 0.9), r0 + rng.uniform(0.1, 0.9))
    goal = (c1 + rng.uniform(0.1, 0.9), r1 + rng.uniform(0.1, 0.9))
    route = astar(blocked, start, goal)
    best = brute_force_8_connected(blocked, start, goal)
    if math.isinf(best):
        assert route is None
    else:
        assert length(route) == pytest.approx(best, abs=1e-9)
        assert route[0].tolist() == list(start) and route[-1].tolist() == list(goal)
        assert reference(blocked).route_free(route)


def test_astar_finds_a_long_detour_past_its_first_ellipses():
    """A wall with one gap at the far end: the route is 200 times the straight distance, so the
    search's bound must grow several times before it holds the route."""
    blocked = np.zeros((200, 60), bool)
    blocked[1:, 30] = True  # gap in row 0 only
    route = astar(blocked, (29.5, 199.5), (31.5, 199.5))
    # up column 29 to row 0, through the gap in two steps (a diagonal would touch the wall's
    # end cell), down column 31: 199 + 2 + 199 cell steps, no diagonal shorter
    assert length(route) == pytest.approx(400.0, abs=1e-9)
    assert route.tolist() == [[29.5, 199.5], [29.5, 0.5], [31.5, 0.5], [31.5, 199.5]]


@pytest.mark.parametrize(
    "blocked, start, goal, optimum",
    [
        (np.zeros((4, 6), bool), (0.5, 0.5), (5.5, 3.5), math.hypot(5, 3)),
        (wall(), (0.5, 0.5), (4.5, 0.5), 2 * math.hypot(1.5, 3.5) + 1),  # via (2, 4), (3, 4)
        (np.pad([[True]], 1), (0.5, 0.5), (2.5, 2.5), math.sqrt(10)),  # via corner (2, 1)
        (np.pad(np.ones((2, 2), bool), 2), (0.0, 3.0), (6.0, 3.0), 2 * math.hypot(2, 1) + 2),
    ],
)
def test_any_angle_is_optimal_on_hand_made_grids(blocked, start, goal, optimum):
    route = any_angle(SegmentChecker(blocked), blocked, start, goal)
    assert length(route) == pytest.approx(optimum, abs=4 * DELTA * len(route))
    assert route[0].tolist() == list(start) and route[-1].tolist() == list(goal)


def brute_force_optimum(blocked, start, goal, reference) -> float:
    """Shortest route over a full visibility graph of a superset of the vertices.

    Vertices: every grid point moved DELTA diagonally into each of its four quadrants (every
    possible bend point), plus the ends; edges by shapely's exact intersection test.
    """
    h, w = blocked.shape
    ys, xs = np.mgrid[0 : h + 1, 0 : w + 1]
    grid_points = np.column_stack([xs.ravel(), ys.ravel()]).astype(float)
    quadrants = np.array([(1, 1), (1, -1), (-1, 1), (-1, -1)]) * DELTA
    pts = (grid_points[:, None, :] + quadrants[None]).reshape(-1, 2)
    inside = np.all((pts > 0) & (pts < (w, h)), axis=1)
    pts = np.vstack([start, goal, pts[inside]])
    i, j = np.triu_indices(len(pts), k=1)
    ref = reference(blocked)
    seen = ~ref.segments_hit(pts[i], pts[j])
    n = len(pts)
    weights = np.zeros((n, n))
    d = np.hypot(*(pts[i[seen]] - pts[j[seen]]).T)
    weights[i[seen], j[seen]] = d
    weights[j[seen], i[seen]] = d
    return float(dijkstra(weights, directed=False, indices=0)[1])


@pytest.mark.parametrize("seed", range(16))
def test_any_angle_matches_a_brute_force_visibility_graph(seed, reference):
    rng = np.random.default_rng(seed)
    blocked = rng.random((6, 8)) < (0.25 if seed < 8 else 0.4)
    blocked[5, 0] = blocked[0, 7] = False
    start, goal = (0.5, 5.5), (7.5, 0.5)
    route = any_angle(SegmentChecker(blocked), blocked, start, goal)
    best = brute_force_optimum(blocked, start, goal, reference)
    if math.isinf(best):
        assert route is None
    else:
        assert length(route) == pytest.approx(best, abs=4 * DELTA * len(route))  # offsets
        assert reference(blocked).route_free(route)


def test_shortening_keeps_the_ends_never_lengthens_and_never_collides(reference):
    rng = np.random.default_rng(9)
    blocked = rng.random((30, 30)) < 0.05
    chk = SegmentChecker(blocked)
    ref = reference(blocked)
    for _ in range(100):
        route = rng.random((8, 2)) * 30
        short = shorten(chk, route)
        assert short[0].tolist() == route[0].tolist() and short[-1].tolist() == route[-1].tolist()
        assert length(short) <= length(route) + 1e-9
        if ref.route_free(route):
            assert ref.route_free(short)


ENVS = ["env1", "env2"]


@pytest.fixture(scope="module", params=ENVS)
def env(request, charts) -> Grid:
    path = charts / f"{request.param}.tif"
    if not path.exists():
        pytest.skip(f"{path} not built")
    return read_grid(path)


def to_cells(grid: Grid, points) -> np.ndarray:
    return np.column_stack(grid.to_cell_coords(*np.asarray(points).T))


def test_exact_routes_on_the_bundled_environments(env, reference):
    ref = reference(env.blocked)
    routes = {
        a: plan_route(env, (10, 10), (490, 490), PlanOptions(a)).route
        for a in ("anyangle", "astar", "astar+s")
    }
    for r in routes.values():
        assert r.collision_free and ref.route_free(to_cells(env, r.points))
        # the reported fitness of a free route is its length and turning cost (1 m cells):
        # the exact routes pass corners within 1e-5 cell, inside the search's tolerance
        assert r.fitness == pytest.approx(r.length_m + measures.turn_cost(r.points), rel=1e-9)
    best = routes["anyangle"].length_m
    assert math.hypot(480, 480) < best <= routes["astar+s"].length_m <= routes["astar"].length_m
    assert routes["astar"].length_m <= best * (1 + (SQ2 - 1) / 2)  # octile bound, loosely


@pytest.mark.parametrize("algo", ["iwso", "ssa+s", "pso", "gwo"])
def test_optimizer_routes_agree_with_the_independent_check(env, algo, reference):
    ref = reference(env.blocked)
    route = plan_route(env, (10, 10), (490, 490), PlanOptions(algo, pop=20, iters=40, seed=3)).route
    assert route.collision_free == ref.route_free(to_cells(env, route.points))
    assert len(route.convergence) == 40
    assert np.all(np.diff(route.convergence) <= 0)
    anyangle = plan_route(env, (10, 10), (490, 490), PlanOptions("anyangle")).route
    if route.collision_free:
        assert route.length_m >= anyangle.length_m - 1e-6
