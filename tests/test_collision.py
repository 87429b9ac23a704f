"""The exact collision check (:mod:`usvtool.collision` and its compiled kernels) against an
independent rasteriser (the shapely reference of tests/conftest.py), and the per-point and
per-route checks."""

from __future__ import annotations

import math

import numpy as np
import pytest
from affine import Affine

from usvtool.collision import SegmentChecker, check_point, is_collision_free
from usvtool.errors import UsvError
from usvtool.grid import Grid

PAD = 1e-3  # the path problem's growth of the blocked squares (usvtool.plan.problem.PAD)


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


@pytest.mark.parametrize("seed", range(6))
def test_the_planners_line_of_sight_agrees_with_an_independent_rasteriser(seed, reference):
    """collision_kernels.touches, one segment at a time as the any-angle search calls it, on
    random segments and on segments between grid points, some moved 1e-5 off them (the
    any-angle vertices): there corner passes decide."""
    from usvtool.collision_kernels import touches

    rng = np.random.default_rng(seed)
    h, w = rng.integers(2, 25, 2)
    blocked = rng.random((h, w)) < rng.uniform(0.02, 0.2)
    prefix = SegmentChecker(blocked)._prefix
    k = 400
    a, b = rng.uniform(0, 1, (2, k, 2)) * [w, h]
    a[: k // 2] = rng.integers(0, [w + 1, h + 1], (k // 2, 2))
    b[: k // 2] = rng.integers(0, [w + 1, h + 1], (k // 2, 2))
    a[: k // 4] = np.clip(a[: k // 4] + rng.choice([-1e-5, 1e-5], (k // 4, 2)), 0, [w, h])
    expected = reference(blocked).segments_hit(a, b)
    assert 0.02 < expected.mean() < 0.98
    assert [touches(prefix, w + 2, *a[i], *b[i]) for i in range(k)] == expected.tolist()


def test_long_segments_near_obstacles_agree(reference):
    rng = np.random.default_rng(7)
    blocked = np.zeros((120, 150), bool)
    blocked[rng.integers(0, 120, 60), rng.integers(0, 150, 60)] = True  # isolated single cells
    a = rng.random((2000, 2)) * (150, 120)
    b = rng.random((2000, 2)) * (150, 120)
    expected = reference(blocked).segments_hit(a, b)
    assert np.array_equal(SegmentChecker(blocked).collides(a, b), expected)


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


@pytest.mark.parametrize("pad", [0.0, PAD])
def test_a_segments_answer_does_not_depend_on_the_rest_of_the_call(pad):
    """A route's cost must not depend on the other routes of its population: each segment's
    touches and length inside are the same, to the bit, checked alone or among 400 others
    (lattice-aligned ones included, where rounding decides)."""
    rng = np.random.default_rng(11)
    blocked = rng.random((30, 40)) < 0.15
    chk = SegmentChecker(blocked, pad=pad or 0.0)
    a, b = random_segments(rng, 200, 40, 30)
    together = chk.guide(a, b, exact=pad == 0.0)
    alone = [chk.guide(a[i : i + 1], b[i : i + 1], exact=pad == 0.0) for i in range(len(a))]
    assert together[0].tolist() == [bool(t[0][0]) for t in alone]
    assert together[1].tolist() == [float(t[1][0]) for t in alone]
    assert 0.05 < together[0].mean() < 0.95


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


def test_segments_must_lie_inside_the_grid():
    chk = SegmentChecker(np.zeros((5, 5), bool))
    with pytest.raises(ValueError, match="inside the grid"):
        chk.collides([[0, 0]], [[6, 1]])
    # guide does not check its arrays first, but its compiled filter refuses a sample off the
    # tables rather than read past them
    with pytest.raises(ValueError, match="inside the grid"):
        chk.guide(np.array([[0.5, 0.5]]), np.array([[0.5, 12.0]]))


def test_a_route_in_map_metres_is_checked_on_the_grid_cells(one_cell):
    g = Grid(one_cell.astype(np.uint8), Affine(2, 0, 100, 0, -2, 220))  # 2 m cells, top y 220
    # cell (row 5, col 5) spans x 110..112, y 208..210
    assert is_collision_free(g, [[101, 219], [119, 219]])
    assert not is_collision_free(g, [[101, 209], [119, 209]])  # through the cell
    assert not is_collision_free(g, [[101, 219], [112, 210], [119, 219]])  # its corner
    assert not is_collision_free(g, [[101, 219], [125, 219]])  # leaves the grid


def test_a_point_is_in_the_grid_and_touches_no_blocked_cell():
    cells = np.zeros((4, 4), np.uint8)
    cells[1, 1], cells[2, 2] = 1, 2  # an obstacle and a margin cell
    g = Grid(cells, Affine(10, 0, 1000, 0, -10, 2040))  # x 1000..1040, y 2000..2040
    assert check_point(g, (1005, 2035), "start") == (0.5, 0.5)
    assert check_point(g, (1040, 2000), "goal") == (4.0, 4.0)  # the far corner is in
    for point, message in [
        ((1015, 2025), "start (1015, 2025) is on an obstacle"),
        ((1010, 2020), "start (1010, 2020) is on an obstacle"),  # its corner
        ((1025.06, 2015), "start (1025.1, 2015) is in the safety margin around an obstacle"),
        ((1040.01, 2000), "start (1040, 2000) is outside the grid (x 1000..1040, y 2000..2040)"),
        ((999.5, 2000), "start (999.5, 2000) is outside the grid (x 1000..1040, y 2000..2040)"),
    ]:
        with pytest.raises(UsvError) as info:
            check_point(g, point, "start")
        assert str(info.value) == message
    assert check_point(g, (1010 - 1e-6, 2030)) == pytest.approx((1.0 - 1e-7, 1.0))  # 1e-7 cell off


@pytest.mark.parametrize("seed", range(4))
def test_the_filter_clearance_is_a_lower_bound_on_the_distance_to_blocked_squares(seed):
    """R of a cell is at most the distance between the cell's square and the nearest blocked
    square (brute force over every blocked cell), and at least 1/√2 of the Euclidean bound
    EDT - √2 the filter used before."""
    from scipy.ndimage import distance_transform_edt

    rng = np.random.default_rng(seed)
    blocked = rng.random((25, 31)) < 0.03
    clear = SegmentChecker(blocked)._clear.reshape(26, 32)[:25, :31]
    rows, cols = np.nonzero(blocked)
    r, c = np.mgrid[0:25, 0:31]
    gap_x = np.maximum(np.abs(c[..., None] - cols) - 1, 0)
    gap_y = np.maximum(np.abs(r[..., None] - rows) - 1, 0)
    exact = np.hypot(gap_x, gap_y).min(axis=-1)
    assert np.all(clear[~blocked] <= exact[~blocked] + 1e-12)
    assert np.all(clear[blocked] == -1)
    euclid = np.maximum(distance_transform_edt(~blocked) - math.sqrt(2), 0)
    assert np.all(clear[~blocked] >= euclid[~blocked] / math.sqrt(2) - 1e-12)


def test_checkers_of_the_same_cells_share_their_table_and_others_do_not(monkeypatch):
    """The filter's table is kept per process for the next checker of the same cells (a batch
    worker's many plans on one grid): the same object for the same cells, its own for cells that
    differ in one cell (equal to the table computed afresh), none kept past the size limit."""
    from usvtool import collision

    rng = np.random.default_rng(5)
    cells = rng.random((40, 50)) < 0.2
    first, again = SegmentChecker(cells), SegmentChecker(cells.copy(), pad=0.2)
    assert again._clear is first._clear
    changed = cells.copy()
    changed[7, 9] = not changed[7, 9]
    other = SegmentChecker(changed)
    assert other._clear is not first._clear
    np.testing.assert_array_equal(other._clear, collision._clearance(changed))
    np.testing.assert_array_equal(first._clear, collision._clearance(cells))
    monkeypatch.setattr(collision, "_RECENT_CELLS", cells.size - 1)
    assert SegmentChecker(cells)._clear is not first._clear  # over the limit: computed anew
