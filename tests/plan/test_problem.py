"""The path problem: encodings, bounds and the cost (the collision check itself:
tests/test_collision.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from affine import Affine

from usvtool.errors import UsvError
from usvtool.grid import Grid
from usvtool.plan.planner import PlanOptions, plan_route
from usvtool.plan.problem import PAD, PathProblem


def grid_of(blocked, cell=1.0) -> Grid:
    blocked = np.asarray(blocked)
    h = blocked.shape[0]
    return Grid(blocked.astype(np.uint8), Affine(cell, 0, 0, 0, -cell, h * cell))


def test_the_cost_penalises_grazing_and_corners(one_cell):
    g = grid_of(one_cell)
    top = 10.0
    # map y = top - cell y; the route start -> waypoint -> goal with a straight line through
    # the waypoint, so there is no turn
    start, goal = (2.0, top - 9.99), (9.99, top - 2.0)
    p = PathProblem(g, start, goal, waypoints=1)
    graze = p(p.encode([[6.0, top - 5.99]]))[0]  # on the line x + y = 11.99
    length = math.hypot(7.99, 7.99)
    assert graze > length + p.penalty - 1e-6
    clear = PathProblem(g, (0.5, 9.5), (9.5, 9.5), waypoints=1)
    assert clear(clear.encode([[5.0, 9.5]]))[0] == pytest.approx(9.0)
    corner = PathProblem(g, (2.0, top - 10.0), (10.0, top - 2.0), waypoints=1)
    assert corner(corner.encode([[6.0, top - 6.0]]))[0] > corner.penalty


@pytest.mark.parametrize("spread", [40.0, 0.002])
def test_penalty_is_zero_exactly_for_routes_clear_of_the_grown_squares(spread, reference):
    """Penalised: every route touching a blocked square grown by PAD, so every colliding
    route; free of charge: every other one. ``spread`` 0.002 puts the routes' waypoint within
    thousandths of a cell of a blocked cell's corner, where the tolerance decides."""
    rng = np.random.default_rng(11)
    blocked = rng.random((40, 40)) < 0.01
    blocked[38:, :2] = blocked[:2, 38:] = False  # around the start and the goal
    g = grid_of(blocked)
    if spread > 1:
        p = PathProblem(g, (1.0, 1.0), (39.0, 39.0), waypoints=3)
        X = rng.uniform(p.lower, p.upper, (500, p.dim))
    else:  # one waypoint at a corner of a blocked cell, nudged
        p = PathProblem(g, (1.0, 1.0), (39.0, 39.0), waypoints=1)
        rows, cols = np.nonzero(blocked)
        k = rng.integers(0, rows.size, 500)
        corners = np.column_stack([cols[k], 40 - rows[k]]) - rng.integers(0, 2, (500, 2))
        X = p.encode(corners + rng.normal(0, spread, (500, 2)))
    routes = p.decode(X)
    clear = ~np.array([reference(blocked, PAD).segments_hit(r[:-1], r[1:]).any() for r in routes])
    free = np.array([reference(blocked).route_free(r) for r in routes])
    assert 0.05 < clear.mean() <= free.mean() < 0.95
    if spread < 1:
        assert (free & ~clear).sum() > 10  # free routes within PAD of a blocked cell
    from usvtool import measures

    plain = measures.path_length(routes) + measures.turn_cost(routes)
    cost = p(X)
    assert cost[clear] == pytest.approx(plain[clear])
    assert np.all(cost[~clear] > plain[~clear] + p.penalty - 1e-9)
    # the figure reported for a route: no tolerance, penalised exactly when colliding
    exact = p.cost(routes, exact=True)
    assert exact[free] == pytest.approx(plain[free])
    assert np.all(exact[~free] > plain[~free] + p.penalty - 1e-9)


def test_waypoints_are_offsets_from_the_straight_line_bounded_by_the_extent():
    g = Grid(np.zeros((4, 6), np.uint8), Affine(10, 0, 1000, 0, -10, 2040))
    p = PathProblem(g, (1005, 2005), (1055, 2035), waypoints=2)
    assert p.dim == 4
    # base points at 1/3 and 2/3 of the way: (1021.667, 2015) and (1038.333, 2025)
    b1, b2 = (1005 + 50 / 3, 2015.0), (1005 + 100 / 3, 2025.0)
    assert p.lower == pytest.approx([1000 - b1[0], 2000 - b1[1], 1000 - b2[0], 2000 - b2[1]])
    assert p.upper == pytest.approx([1060 - b1[0], 2040 - b1[1], 1060 - b2[0], 2040 - b2[1]])
    straight = [0.5, 3.5, (b1[0] - 1000) / 10, (2040 - b1[1]) / 10,
                (b2[0] - 1000) / 10, (2040 - b2[1]) / 10, 5.5, 0.5]  # fmt: skip
    assert p.decode(np.zeros(4))[0].ravel() == pytest.approx(straight)  # zero offsets
    assert p.decode(p.lower)[0, 1:-1].ravel() == pytest.approx([0, 4, 0, 4])  # the SW corner
    assert p.decode(p.upper)[0, 1:-1].ravel() == pytest.approx([6, 0, 6, 0])  # the NE corner
    routes = p.decode(p.encode([[1000, 2040, 1060, 2000]]))
    assert routes.tolist() == [[[0.5, 3.5], [0, 0], [6, 4], [5.5, 0.5]]]
    assert p.to_map(routes[0]).tolist() == [[1005, 2005], [1000, 2040], [1060, 2000], [1055, 2035]]


def test_columns_encoding_is_one_cell_per_column():
    g = grid_of(np.zeros((20, 20), bool))
    p = PathProblem(g, (0.5, 0.5), (19.5, 19.5), encoding="columns")
    assert p.dim == 20 and p.lower.tolist() == [-20] * 20 and p.upper.tolist() == [20] * 20
    straight = np.zeros(20)  # no offset from the start-goal line: the diagonal cells
    route = p.decode([straight])[0]
    assert route[1:-1].tolist() == [[j + 0.5, 19.5 - j] for j in range(20)]
    # start, (0.5, 19.5) again, ..., (19.5, 0.5), goal: a straight diagonal of 19 √2
    assert p([straight])[0] == pytest.approx(19 * math.sqrt(2))
    south = -np.arange(20) - 0.2  # j cells south of the line: along the south row, then up
    assert p.decode([south])[0, 1:-1, 1].tolist() == [19.5] * 20
    assert p([south])[0] == pytest.approx(19 + 19 + 0.4)  # one right-angle turn
    assert p.decode([np.full(20, 20.0)])[0, 1:-1, 1].tolist() == [0.5] * 20  # clipped north


def test_the_population_is_evaluated_in_one_vectorised_call():
    g = grid_of(np.random.default_rng(2).random((50, 50)) < 0.05)
    p = PathProblem(g, (0.5, 0.5), (49.5, 49.5), waypoints=4)
    X = np.random.default_rng(5).uniform(p.lower, p.upper, (64, p.dim))
    together = p(X)
    assert together.shape == (64,)
    assert together == pytest.approx([p(x[None])[0] for x in X])


def test_bad_encoding_and_waypoints_are_refused():
    g = grid_of(np.zeros((5, 5), bool))
    with pytest.raises(ValueError, match="encoding"):
        PathProblem(g, (0.5, 0.5), (4.5, 4.5), encoding="spline")
    with pytest.raises(ValueError, match="waypoints"):
        PathProblem(g, (0.5, 0.5), (4.5, 4.5), waypoints=0)


def test_waypoints_are_bounded_by_the_box_of_the_start_s_navigable_region():
    """Hand-made 8 x 10 grid of 2 m cells (top edge y = 16 m): water in rows 0-2 and 5-6,
    land in rows 3-4 but for a one-cell gap at column 7, land in row 7. With the gap the
    region's box is rows 0-6: x 0..20 m, y 2..16 m; without it, rows 0-2: y 10..16 m."""
    blocked = np.zeros((8, 10), bool)
    blocked[3:5] = blocked[7] = True
    blocked[3:5, 7] = False  # the gap
    base = np.array([[7.0, 15.0], [13.0, 15.0]])  # 1/3 and 2/3 of the way
    p = PathProblem(grid_of(blocked, cell=2.0), (1.0, 15.0), (19.0, 15.0), waypoints=2)
    assert p.lower.tolist() == ([0.0, 2.0] - base).ravel().tolist()
    assert p.upper.tolist() == ([20.0, 16.0] - base).ravel().tolist()
    blocked[3:5, 7] = True
    p = PathProblem(grid_of(blocked, cell=2.0), (1.0, 15.0), (19.0, 15.0), waypoints=2)
    assert p.lower.tolist() == ([0.0, 10.0] - base).ravel().tolist()
    assert p.upper.tolist() == ([20.0, 16.0] - base).ravel().tolist()


def test_the_search_is_in_units_of_the_start_goal_distance():
    """Hand-computed: start (1, 15), goal (19, 15) on 2 m cells, D = 18 m."""
    g = grid_of(np.zeros((8, 10), bool), cell=2.0)
    p = PathProblem(g, (1.0, 15.0), (19.0, 15.0), waypoints=1)
    s = p.search()
    assert p.unit == 18.0 and s.scale == 18.0
    assert s.lower.tolist() == pytest.approx([-10 / 18, -15 / 18])  # box x 0..20, y 0..16
    assert s.upper.tolist() == pytest.approx([10 / 18, 1 / 18])  # around (10, 15)
    Z = np.array([[0.0, 0.0], [0.0, -0.5]])  # straight; the waypoint at (10, 6): 9 m south
    expected = p(Z * 18.0) / 18.0
    assert s(Z) == pytest.approx(expected)
    assert s(Z)[0] == pytest.approx(1.0)
    columns = PathProblem(grid_of(np.zeros((20, 20), bool), cell=2.0), (1, 1), (39, 39), "columns")
    assert columns.search().scale == 1.0 and columns.unit == 2.0  # cells, cost in cells


@pytest.mark.parametrize("algo", ["ssa", "boa"])
def test_the_search_is_the_same_at_any_scale(algo):
    """One geometry on 1 m and on 4 m cells (a power of two keeps the arithmetic exact) gives
    one route: SSA's unit producer step and BOA's fragrance of the cost have a fixed size,
    so in metres they would search differently."""
    blocked = np.zeros((20, 30), bool)
    blocked[4:16, 12:15] = True
    routes = [
        plan_route(grid_of(blocked, c), (1.5 * c, 10.5 * c), (28.5 * c, 10.5 * c),
                   PlanOptions(algo, 20, 40, 2)).route
        for c in (1.0, 4.0)
    ]
    assert routes[1].points / 4.0 == pytest.approx(routes[0].points, rel=1e-12, abs=1e-9)
    assert routes[1].convergence == pytest.approx(np.multiply(routes[0].convergence, 4.0))
    assert routes[0].length_m > 18.0  # around the wall, not through it


def test_a_plan_labels_the_grid_s_regions_once(monkeypatch):
    import scipy.ndimage

    calls = []
    label = scipy.ndimage.label
    monkeypatch.setattr(scipy.ndimage, "label", lambda a: calls.append(a.shape) or label(a))
    blocked = np.zeros((8, 10), bool)
    blocked[3:5] = True
    blocked[3:5, 7] = False
    g = grid_of(blocked)
    # the start/goal check, the search box and the connectivity test share one labelling
    route = plan_route(g, (1.0, 7.5), (1.0, 0.5), PlanOptions("gwo", 10, 5, 0)).route
    assert calls == [(8, 10)]
    assert g.regions.max() == 1 and route.points.shape[1] == 2
    blocked[3:5, 7] = True
    with pytest.raises(UsvError, match="no navigable connection"):
        plan_route(grid_of(blocked), (1.0, 7.5), (1.0, 0.5), PlanOptions("gwo", 10, 5, 0))
