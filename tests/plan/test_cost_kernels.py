"""The compiled path cost (usvtool/plan/cost_kernels.py) against the NumPy path it stands for
(``PathProblem._decode_python``, ``PathProblem._cost_python``), bit for bit, on seeded random
populations over generated grids: both encodings, ``exact`` or not, routes touching and inside
blocked cells, zero-length segments and repeated points; and whole planner runs giving the same
route files with either path."""

from __future__ import annotations

import json

import numpy as np
import pytest
from affine import Affine

from usvtool.grid import Grid
from usvtool.plan import cost_kernels
from usvtool.plan.guided import GuidedProblem, clear_of_corners, stations
from usvtool.plan.planner import PlanOptions, plan_route
from usvtool.plan.problem import PathProblem


def _numpy_fuses_as_the_kernels() -> bool:
    """Whether this machine's NumPy computes a complex ``abs`` and a complex product as the
    kernels repeat them (``cost_kernels.cabs``, ``turn_product``: its SIMD loops with fused
    multiply-adds, x86-64 from AVX2 (X86_V3) up, this project's machines). NumPy picks its
    loops by the CPU: with SSE alone (``NPY_DISABLE_CPU_FEATURES="X86_V3 X86_V4 AVX512_ICL
    AVX512_SPR"``) it computes both otherwise, the NumPy path's last bits change, and so do
    the routes its chaotic searches find. The compiled path is then the reference; the NumPy
    path can only be close to it."""
    rng = np.random.default_rng(0)
    z = rng.normal(size=512) * 10.0 ** rng.integers(-3, 4, 512)
    z = z + 1j * rng.normal(size=512)
    w = np.roll(z, 1)
    product = z * w.conj()
    return all(cost_kernels.cabs(a.real, a.imag) == abs_a
               and cost_kernels.turn_product(a.real, a.imag, b.real, b.imag)
               == (p.real, p.imag)
               for a, b, abs_a, p in zip(z, w, np.abs(z), product, strict=True))  # fmt: skip


#: Whether the NumPy path is the compiled one bit for bit on this machine (above).
BITWISE = _numpy_fuses_as_the_kernels()


def same_bits(a, b) -> bool:
    """The same floats, bit for bit, where NumPy fuses as the kernels do (:data:`BITWISE`);
    elsewhere within a few units in the last place."""
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype != b.dtype or a.shape != b.shape:
        return False
    if BITWISE:
        return a.tobytes() == b.tobytes()
    return bool(np.allclose(a, b, rtol=1e-12, atol=0.0, equal_nan=True))


def random_grid(rng, h: int, w: int, density: float, cell: float = 1.0) -> Grid:
    blocked = rng.random((h, w)) < density
    if density and rng.random() < 0.5:  # a few larger blocks
        for _ in range(3):
            r, c = rng.integers(0, h), rng.integers(0, w)
            blocked[r : r + h // 5, c : c + w // 5] = True
    blocked[:2, :2] = blocked[-2:, -2:] = False  # around the start and the goal
    blocked[-2:, :2] = blocked[:2, -2:] = False
    return Grid(blocked.astype(np.uint8), Affine(cell, 0, 0, 0, -cell, h * cell))


def ends_of(g: Grid, rng) -> tuple[tuple[float, float], tuple[float, float]]:
    left, bottom, right, top = g.bounds
    ell = g.cell_size
    if rng.random() < 0.5:
        return (left + 0.5 * ell, bottom + 0.5 * ell), (right - 0.5 * ell, top - 0.5 * ell)
    return (left + 0.5 * ell, top - 0.5 * ell), (right - 0.5 * ell, bottom + 0.5 * ell)


def degenerate(rng, routes: np.ndarray) -> np.ndarray:
    """Repeated points (zero-length segments, also at the ends), points on grid lines and cell
    corners, in some of the routes."""
    routes = routes.copy()
    n, m = routes.shape[:2]
    for i in range(n):
        kind = rng.integers(0, 6)
        j = int(rng.integers(0, m - 1))
        if kind == 0:
            routes[i, j + 1] = routes[i, j]
        elif kind == 1:
            routes[i, 1:-1] = routes[i, 0]  # all at the start
        elif kind == 2 and m > 3:
            routes[i, j + 1 :] = routes[i, -1]  # at the goal early
        elif kind == 3:
            routes[i, j] = np.round(routes[i, j])  # on a grid point
        elif kind == 4:
            routes[i, j, 0] = np.round(routes[i, j, 0])  # on a column edge
            routes[i, j + 1, 0] = routes[i, j, 0]  # north-south
    return routes


def problems(seed: int):
    rng = np.random.default_rng(seed)
    for h, w, density, cell in [(12, 12, 0.15, 1.0), (30, 40, 0.05, 2.5), (64, 50, 0.3, 10.0),
                                (20, 20, 0.0, 1.0), (9, 130, 0.1, 1.0)]:  # fmt: skip
        g = random_grid(rng, h, w, density, cell)
        start, goal = ends_of(g, rng)
        yield rng, PathProblem(g, start, goal, "columns", turn_weight=float(rng.uniform(0, 3)))
        for k in (1, 3, 7, 11):
            yield rng, PathProblem(g, start, goal, waypoints=k, turn_weight=1.0)


@pytest.mark.parametrize("seed", range(4))
def test_the_compiled_cost_is_the_numpy_cost_bit_for_bit(seed):
    for rng, p in problems(seed):
        for trial in range(3):
            n = int(rng.choice([1, 7, 50, 100]))
            spread = rng.choice([0.05, 0.3, 1.0])
            X = rng.uniform(p.lower * spread, p.upper * spread, (n, p.dim))
            X[rng.random(n) < 0.1] = 0.0  # the straight route
            routes = p.decode(X)
            assert same_bits(routes, p._decode_python(X))
            assert same_bits(p(X), p._cost_python(p._decode_python(X)))
            routes = degenerate(rng, routes)
            for exact in (False, True):
                got, want = p.cost(routes, exact), p._cost_python(routes, exact)
                assert same_bits(got, want), (seed, p.encoding, p.dim, trial, exact)


def test_straight_routes_and_two_point_routes():
    rng = np.random.default_rng(5)
    g = random_grid(rng, 16, 16, 0.1)
    p = PathProblem(g, (0.5, 0.5), (15.5, 15.5), waypoints=2)
    two = np.array([[[0.5, 15.5], [15.5, 0.5]], [[3.0, 3.0], [3.0, 3.0]]])  # m = 2: no turns
    for exact in (False, True):
        assert same_bits(p.cost(two, exact), p._cost_python(two, exact))
    long = np.cumsum(rng.uniform(-0.4, 0.6, (2, 300, 2)), axis=1) % 16  # > 128 segments
    long[0, 100:110] = long[0, 99]
    for exact in (False, True):
        assert same_bits(p.cost(long, exact), p._cost_python(long, exact))


def test_a_point_outside_the_grid_is_refused():
    rng = np.random.default_rng(6)
    p = PathProblem(random_grid(rng, 10, 10, 0.1), (0.5, 0.5), (9.5, 9.5), waypoints=1)
    with pytest.raises(ValueError, match="inside the grid"):
        p.cost(np.array([[[0.5, 9.5], [25.0, 9.5], [9.5, 0.5]]]))
    with pytest.raises(ValueError, match="population"):
        p(np.zeros((3, 3)))


def test_pairwise_sum_is_numpys():
    rng = np.random.default_rng(7)
    for n in [*range(0, 40), 127, 128, 129, 255, 256, 257, 500, 1001]:
        a = rng.uniform(0, 1, (3, n)) * 10.0 ** rng.integers(-8, 8, (3, n))
        for row in a:
            assert same_bits(cost_kernels.row_sum(np.ascontiguousarray(row), 0, n), row.sum())


def test_the_guided_cost_is_the_numpy_cost_bit_for_bit():
    rng = np.random.default_rng(8)
    g = random_grid(rng, 30, 30, 0.0)
    p = PathProblem(g, (0.5, 0.5), (29.5, 29.5), waypoints=3)
    station = np.array([[0.5, 29.5], [10.0, 22.0], [12.0, 12.0], [20.0, 9.0], [29.5, 0.5]])
    gp = GuidedProblem(p, station)
    X = rng.uniform(gp.lower, gp.upper, (60, gp.dim))
    routes = degenerate(rng, gp.decode(X))
    seg = routes[:, 1:] - routes[:, :-1]
    want = g.cell_size * p.free_cost(seg.view(np.complex128)[..., 0])
    assert same_bits(gp.cost(routes), want)
    assert same_bits(gp.cost(routes), p._cost_python(routes, exact=True))


@pytest.mark.parametrize("seed", range(3))
def test_the_guided_decoder_is_the_numpy_decoder_bit_for_bit(seed):
    """Random station routes (stations in land, outside the grid's interior, on grid points)
    and a planner's own (the any-angle route's, off its corners), judged exactly and with the
    margin; waypoints moved within and beyond their bounds."""
    rng = np.random.default_rng(20 + seed)
    g = random_grid(rng, 40, 40, 0.08, cell=2.0)
    p = PathProblem(g, (1.0, 1.0), (79.0, 79.0), waypoints=3)
    cases = []
    for k in (1, 3, 8):
        inner = rng.uniform(0, 40, (k, 2))
        on_points = rng.random(k) < 0.3
        inner[on_points] = np.round(inner[on_points])  # on grid points
        station = np.vstack([[0.5, 39.5], inner, [39.5, 0.5]])
        cases += [GuidedProblem(p, station), GuidedProblem(p, station, margin=True)]
    exact = plan_route(g, (1.0, 1.0), (79.0, 79.0), PlanOptions("anyangle")).route.points
    cells = np.column_stack(g.to_cell_coords(*np.asarray(exact).T))
    station = stations(p.checker, cells)
    clear = clear_of_corners(p.checker, station)
    cases.append(GuidedProblem(p, station))
    if clear is not None:
        cases.append(GuidedProblem(p, clear, margin=True))
    for gp in cases:
        for spread in (0.1, 1.0, 3.0):
            X = rng.uniform(gp.lower, gp.upper, (40, gp.dim)) * spread
            X[:3] = 0.0
            routes = gp.decode(X)
            assert same_bits(routes, gp._decode_python(X)), (seed, gp.waypoints, gp.margin)
            assert same_bits(gp(X), gp._cost_python(gp._decode_python(X)))


def route_file(result) -> str:
    """The route and its figures (as the planner writes them; timing off)."""
    route = result.route
    return json.dumps([np.asarray(route.points).tolist(), result.summary(),
                       np.asarray(route.convergence).tolist()], default=float)  # fmt: skip


@pytest.fixture(scope="module")
def plan_grid() -> Grid:
    rng = np.random.default_rng(9)
    blocked = rng.random((40, 40)) < 0.04
    blocked[10:25, 15:20] = True
    blocked[:3, :3] = blocked[-3:, -3:] = False
    return Grid(blocked.astype(np.uint8), Affine(2.0, 0, 0, 0, -2.0, 80.0))


ALGOS = ["wso", "iwso", "ssa", "issa", "pso", "gwo", "woa", "mrfo", "boa", "iwso+g"]


@pytest.mark.parametrize("encoding", ["waypoints", "columns"])
def test_whole_plans_are_the_same_with_the_numpy_cost(plan_grid, encoding, monkeypatch):
    """Every optimizer's route, fitness and convergence, with the compiled cost and with the
    NumPy one, the same bits (on a machine whose NumPy fuses otherwise, the searches part at
    the first last-bit difference: nothing to compare)."""
    if not BITWISE:
        pytest.skip("this machine's NumPy computes complex abs and products without the fused "
                    "multiply-adds the kernels repeat (SSE only): its costs differ in the last "
                    "bits")
    start, goal = (1.0, 1.0), (79.0, 79.0)
    algos = ALGOS if encoding == "waypoints" else ["ssa", "issa", "pso"]

    def plans() -> list[str]:
        out = []
        for algo in algos:
            opts = PlanOptions(algo, 20, 25, seed=3, encoding=encoding, timing=False)
            out.append(route_file(plan_route(plan_grid, start, goal, opts)))
        return out

    compiled = plans()
    monkeypatch.setattr(PathProblem, "decode", PathProblem._decode_python)
    monkeypatch.setattr(PathProblem, "cost", PathProblem._cost_python)
    if hasattr(GuidedProblem, "_decode_python"):
        monkeypatch.setattr(GuidedProblem, "decode", GuidedProblem._decode_python)
    if hasattr(GuidedProblem, "_cost_python"):
        monkeypatch.setattr(GuidedProblem, "cost", GuidedProblem._cost_python)
    assert plans() == compiled


def test_the_warm_up_compiles_the_signatures_the_problems_call(plan_grid):
    """cost_kernels.warm's arguments have the types of the problems' calls: after plans of
    every kind each kernel has one compiled signature (a second would be compiled inside a
    plan's timing, on its first call)."""
    start, goal = (1.0, 1.0), (79.0, 79.0)
    for algo, encoding in [("iwso", "waypoints"), ("issa", "columns"), ("iwso+g", "waypoints")]:
        opts = PlanOptions(algo, 10, 5, seed=1, encoding=encoding, timing=False)
        plan_route(plan_grid, start, goal, opts)
    kernels = ("decode_waypoints", "decode_columns", "decode_guided", "route_terms", "combine")
    for kernel in (getattr(cost_kernels, name) for name in kernels):
        assert len(kernel.signatures) == 1, kernel.signatures
