"""The path problem: the exact collision check against an independent rasteriser, and the cost."""

from __future__ import annotations

import math

import numpy as np
import pytest
from affine import Affine

from usvtool.errors import UsvError
from usvtool.grid import Grid
from usvtool.plan.problem import PAD, PathProblem
from usvtool.plan.raster import SegmentChecker
from usvtool.plan.route import plan_route


def grid_of(blocked, cell=1.0) -> Grid:
    blocked = np.asarray(blocked)
    h = blocked.shape[0]
    return Grid(blocked.astype(np.uint8), Affine(cell, 0, 0, 0, -cell, h * cell))


def random_segments(rng, n, width, height):
    """Random segments of every length, plus lattice-aligned ones (edges, corners, diagonals)."""
    a = rng.random((n, 2)) * (width, height)
    angle = rng.random(n) * 2 * math.pi
    length = rng.exponential(6.0, n)
    b = a + length[:, None] * np.column_stack([np.cos(angle), np.sin(angle)])
    half = rng.integers(0, 2 * width + 1, (n, 2)) / 2.0
    step = rng.integers(-12, 13, (n, 2)) / 2.0
    step[np.all(step == 0, axis=1)] = (0.5, 1.0)
    a = np.vstack([a, half])
    b = np.vstack([b, half + step])
    limit = (width, height)
    return np.clip(a, 0, limit), np.clip(b, 0, limit)


@pytest.mark.parametrize("density, samples", [(0.02, 24), (0.1, 24), (0.3, 5), (0.05, 2)])
def test_collisions_agree_with_an_independent_rasteriser(density, samples, reference):
    rng = np.random.default_rng(int(density * 100) + samples)
    blocked = rng.random((30, 40)) < density
    chk = SegmentChecker(blocked, samples=samples)
    a, b = random_segments(rng, 3000, 40, 30)
    keep = np.any(a != b, axis=1)
    a, b = a[keep], b[keep]
    expected = reference(blocked).segments_hit(a, b)
    assert 0.05 < expected.mean() < 0.95
    assert np.array_equal(chk.collides(a, b), expected)
    assert np.array_equal(chk.touches(a, b), expected)


def test_long_segments_near_obstacles_agree(reference):
    rng = np.random.default_rng(7)
    blocked = np.zeros((120, 150), bool)
    blocked[rng.integers(0, 120, 60), rng.integers(0, 150, 60)] = True  # isolated single cells
    a = rng.random((2000, 2)) * (150, 120)
    b = rng.random((2000, 2)) * (150, 120)
    expected = reference(blocked).segments_hit(a, b)
    assert np.array_equal(SegmentChecker(blocked).collides(a, b), expected)


@pytest.fixture
def one_cell():
    """A 10 x 10 grid whose only obstacle is the cell x 5..6, y 5..6 (cell coordinates)."""
    blocked = np.zeros((10, 10), bool)
    blocked[5, 5] = True
    return blocked


def test_a_segment_grazing_a_single_cell_is_caught(one_cell):
    chk = SegmentChecker(one_cell)
    # x + y = 11.99 cuts a triangle of legs 0.01 off the cell's corner (6, 6): far thinner
    # than the spacing of the samples along the segment
    a, b = np.array([[2.0, 9.99]]), np.array([[9.99, 2.0]])
    assert chk.collides(a, b)[0]
    # passing the corner exactly also collides; 1e-6 beyond it does not
    assert chk.collides([[2.0, 10.0]], [[10.0, 2.0]])[0]
    assert not chk.collides([[3.0, 9.0 + 1e-6]], [[9.0 + 1e-6, 3.0]])[0]
    # running along the cell's edge touches it; half a cell away does not
    assert chk.collides([[0.5, 5.0]], [[9.5, 5.0]])[0]
    assert not chk.collides([[0.5, 4.5]], [[9.5, 4.5]])[0]


def test_a_diagonal_gap_between_two_cells_is_closed():
    blocked = np.zeros((4, 4), bool)
    blocked[1, 2] = blocked[2, 1] = True  # they share only the corner (2, 2)
    chk = SegmentChecker(blocked)
    assert chk.collides([[0.5, 0.5]], [[3.5, 3.5]])[0]  # through the corner point


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
    from usvtool import metrics

    plain = metrics.path_length(routes) + metrics.turn_cost(routes)
    cost = p(X)
    assert cost[clear] == pytest.approx(plain[clear])
    assert np.all(cost[~clear] > plain[~clear] + p.penalty - 1e-9)
    # the figure reported for a route: no tolerance, penalised exactly when colliding
    exact = p.cost(routes, exact=True)
    assert exact[free] == pytest.approx(plain[free])
    assert np.all(exact[~free] > plain[~free] + p.penalty - 1e-9)


def column_blocks(blocked, pad):
    """Reference for SegmentChecker.inside: per column, the union of its blocked cells grown by
    ``pad`` (open; with pad 0 each cell's open square on its own)."""
    import shapely

    shapes = []
    for c in range(blocked.shape[1]):
        rows = np.nonzero(blocked[:, c])[0]
        boxes = [shapely.box(c - pad, r - pad, c + 1 + pad, r + 1 + pad) for r in rows]
        if pad:
            shapes += [shapely.union_all(boxes)] if boxes else []
        else:
            shapes += boxes
    return [s.buffer(-1e-10, join_style="mitre") for s in shapes]


@pytest.mark.parametrize("pad", [0.0, PAD, 0.2])
def test_length_inside_agrees_with_shapely(pad):
    rng = np.random.default_rng(int(pad * 1e4))
    import shapely

    for _ in range(6):
        h, w = rng.integers(4, 14, 2)
        blocked = rng.random((h, w)) < 0.3
        chk = SegmentChecker(blocked, pad=pad)
        a, b = random_segments(rng, 150, w, h)
        a[:20, 1] = b[:20, 1] = np.floor(a[:20, 1]) + rng.choice([0.0, 0.5], 20)  # level
        b[20:40, 0] = a[20:40, 0]  # north-south
        b[40:50, 0] = np.clip(a[40:50, 0] + 1e-10, 0, w)  # nearly north-south
        lines = shapely.linestrings(np.stack([a, b], 1))
        blocks = column_blocks(blocked, pad)
        expected = [sum(line.intersection(s).length for s in blocks) for line in lines]
        # exact up to rounding, which nearly level pieces amplify (a y-difference over a slope)
        assert chk.inside(a, b) == pytest.approx(expected, rel=1e-6, abs=1e-7)


def test_length_inside_grows_linearly_to_the_grown_corner(one_cell):
    """The segments x + y = 12 + u pass the corner (6, 6) of cell x 5..6, y 5..6 at u = 0, and
    the grown square's corner (6 + pad, 6 + pad) at u = 2 pad: they cut a triangle of legs
    2 pad - u off the grown square, so the length inside is √2 (2 pad - u) up to u = 2 pad
    and 0 beyond: no flat stretch at the real corner for a search to settle on."""
    pad = 1e-3
    chk = SegmentChecker(one_cell, pad=pad)
    u = np.array([-0.01, -pad, 0.0, pad, 1.9 * pad, 2 * pad + 1e-6, 0.01])
    a, b = np.column_stack([np.full(7, 3.0), 9 + u]), np.column_stack([9 + u, np.full(7, 3.0)])
    expected = np.sqrt(2) * np.maximum(2 * pad - u, 0.0)
    assert chk.inside(a, b) == pytest.approx(expected, abs=1e-9)
    touches, inside = chk.guide(a, b)
    assert touches.tolist() == [True] * 5 + [False] * 2
    assert inside == pytest.approx(expected, abs=1e-9)
    assert chk.collides(a, b).tolist() == [True] * 3 + [False] * 4  # the exact check


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
    with pytest.raises(ValueError, match="inside the grid"):
        SegmentChecker(np.zeros((5, 5), bool)).collides([[0, 0]], [[6, 1]])


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
        plan_route(grid_of(blocked, c), (1.5 * c, 10.5 * c), (28.5 * c, 10.5 * c), algo, 20, 40, 2)
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
    route = plan_route(g, (1.0, 7.5), (1.0, 0.5), "gwo", 10, 5, 0)  # check, box, connectivity
    assert calls == [(8, 10)]
    assert g.regions.max() == 1 and route.points.shape[1] == 2
    blocked[3:5, 7] = True
    with pytest.raises(UsvError, match="no navigable connection"):
        plan_route(grid_of(blocked), (1.0, 7.5), (1.0, 0.5), "gwo", 10, 5, 0)
