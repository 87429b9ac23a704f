"""The optimizers: convergence, bounds, reproducibility, budgets and the registry."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from usvtool.errors import UsvError
from usvtool.plan.optimizers import OPTIMIZERS, make_optimizer
from usvtool.plan.optimizers.issa import fitness_spread
from usvtool.plan.optimizers.pso import PSO
from usvtool.plan.optimizers.ssa import SSA
from usvtool.plan.optimizers.ssa_redraw import SSARedraw
from usvtool.plan.optimizers.wso import WSO, constants, schedule

NAMES = list(OPTIMIZERS)
DIM, HALF = 5, 10.0  # the small sphere: 5-D on [-10, 10]^5


def sphere(X):
    return np.sum(X * X, axis=1)


def random_sampling_quantile(evaluations: int, q: float, d: int = DIM, half: float = HALF):
    """The cost that the best of ``evaluations`` uniform samples beats with probability ``q``.

    P(|x|^2 <= r^2) for one sample is the ball's share of the box, V_d r^d / (2 half)^d (the
    ball stays inside the box for the small r involved); the best of N samples beats r^2 with
    probability 1 - (1 - p)^N = q, so p = 1 - (1 - q)^(1/N).
    """
    p = -math.expm1(math.log1p(-q) / evaluations)
    ball = math.pi ** (d / 2) / math.gamma(d / 2 + 1)
    r = (p * (2 * half) ** d / ball) ** (1 / d)
    assert r < half
    return r * r


class Recorder:
    """An objective that keeps every point it was asked to evaluate."""

    def __init__(self, func):
        self.func = func
        self.points = []

    def __call__(self, X):
        assert X.ndim == 2
        self.points.append(X.copy())
        return self.func(X)

    @property
    def all(self):
        return np.vstack(self.points)


@pytest.mark.parametrize("name", [n for n in NAMES if n != "pso-issa"])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_converges_well_below_random_sampling(name, seed):
    lower, upper = np.full(DIM, -HALF), np.full(DIM, HALF)
    result = make_optimizer(name, pop=20, iters=60, seed=seed).minimize(sphere, lower, upper)
    # random sampling with the same budget reaches this only once in a hundred tries
    rare = random_sampling_quantile(result.evaluations, 0.01)
    assert result.f < rare / 20, (result.f, rare)


def test_pso_issa_preset_only_beats_random_sampling():
    # w = 1 with c1 = c2 = 2.5 (ISSA paper, Table 2) keeps the swarm oscillating at the velocity
    # clamp: it does better than random sampling's median but does not converge
    result = make_optimizer("pso-issa", pop=20, iters=60, seed=0).minimize(
        sphere, np.full(DIM, -HALF), np.full(DIM, HALF)
    )
    assert result.f < random_sampling_quantile(result.evaluations, 0.5)
    assert result.f > 1e-3


@pytest.mark.parametrize("name", NAMES)
def test_every_evaluated_point_is_inside_the_box(name):
    lower = np.array([-5.0, 0.0, 2.0, -1.0, -3.0])
    upper = np.array([5.0, 1.0, 6.0, 4.0, -2.0])
    target = np.array([10.0, -10.0, 0.0, 5.0, -2.5])  # outside the box in 4 of 5 coordinates

    def cost(X):
        return np.sum((X - target) ** 2, axis=1) + 1.0  # positive: IWSO's ratio, BOA's power

    rec = Recorder(cost)
    result = make_optimizer(name, pop=12, iters=30, seed=5).minimize(rec, lower, upper)
    pts = rec.all
    assert np.all(pts >= lower) and np.all(pts <= upper)
    assert np.all(np.isfinite(pts))
    assert result.evaluations == len(pts)
    assert np.all(result.x >= lower) and np.all(result.x <= upper)
    assert result.f == pytest.approx(cost(result.x[None])[0])
    assert result.f == pytest.approx(min(cost(p).min() for p in rec.points))


@pytest.mark.parametrize("name", NAMES)
def test_reproducible_by_seed(name):
    box = (np.full(4, -3.0), np.full(4, 7.0))
    runs = [make_optimizer(name, pop=8, iters=15, seed=s).minimize(sphere, *box) for s in (4, 4, 9)]
    np.testing.assert_array_equal(runs[0].history, runs[1].history)
    np.testing.assert_array_equal(runs[0].x, runs[1].x)
    assert runs[0].evaluations == runs[1].evaluations
    assert not np.array_equal(runs[0].history, runs[2].history)


@pytest.mark.parametrize("name", NAMES)
def test_history_is_best_so_far(name):
    result = make_optimizer(name, pop=6, iters=25, seed=0).minimize(sphere, -2.0, 3.0)
    assert result.history.shape == (25,)
    assert np.all(np.diff(result.history) <= 0)
    assert result.history[-1] == result.f
    assert result.params["pop"] == 6 and result.params["iters"] == 25


@pytest.mark.parametrize("name", NAMES)
def test_smallest_population(name):
    result = make_optimizer(name, pop=2, iters=5, seed=0).minimize(sphere, [-1.0, -1.0], [1, 1])
    assert np.isfinite(result.f) and result.x.shape == (2,)


@pytest.mark.parametrize("name", NAMES)
def test_negative_costs(name):
    # F8-like costs below zero must not break fragrance powers, IWSO's ratio or SSA's walk
    def cost(X):
        return np.sum(-X * np.sin(np.sqrt(np.abs(X))), axis=1)

    result = make_optimizer(name, pop=10, iters=20, seed=0).minimize(cost, -500.0, [500.0] * 3)
    assert np.isfinite(result.f) and result.f < 0


def test_budgets():
    n, iters = 20, 10
    # SSA: one evaluation per sparrow and per scout (15 % of 20 = 3) each iteration
    ssa = SSA(n, iters, seed=0).minimize(sphere, -1.0, [1.0] * 3)
    assert ssa.evaluations == n + iters * (n + 3)
    # IWSO: 2n to start, then the moves, the reflections and the second points, plus shrinks
    iwso = make_optimizer("iwso", n, iters, seed=0).minimize(sphere, -1.0, [1.0] * 3)
    least = 2 * n + iters * (n + 2 * (n - 2))
    assert least <= iwso.evaluations <= least + iters * (n - 2)
    mrfo = make_optimizer("mrfo", n, iters, seed=0).minimize(sphere, -1.0, [1.0] * 3)
    assert mrfo.evaluations == n + 2 * n * iters


def test_ssa_redraw_differs_from_ssa_only_in_the_bounds_rule():
    # same seed, same objective: the evaluated batches agree until SSA first clips a coordinate
    # onto the box; in that batch the variant keeps every coordinate SSA kept and redraws the
    # clipped ones strictly inside the box
    lower, upper = np.full(3, -1.0), np.full(3, 1.0)

    def cost(X):
        return np.sum((X - 0.3) ** 2, axis=1)

    ssa, redraw = Recorder(cost), Recorder(cost)
    SSA(10, 20, seed=7).minimize(ssa, lower, upper)
    SSARedraw(10, 20, seed=7).minimize(redraw, lower, upper)
    on_bound = [(P == lower) | (P == upper) for P in ssa.points]
    first = next(k for k, b in enumerate(on_bound) if b.any())
    assert first > 0  # the uniform start is strictly inside
    for k in range(first):
        np.testing.assert_array_equal(redraw.points[k], ssa.points[k])
    clipped, kept = on_bound[first], ~on_bound[first]
    np.testing.assert_array_equal(redraw.points[first][kept], ssa.points[first][kept])
    moved = redraw.points[first][clipped]
    assert np.all((moved > -1.0) & (moved < 1.0))


def test_ssa_redraw_draws_out_of_box_coordinates_uniformly():
    opt = SSARedraw(pop=2, iters=1, seed=0)
    opt.minimize(sphere, [-2.0, 0.0], [2.0, 10.0])  # sets the box and the generator
    n = 4000
    X = np.tile([[-5.0, 3.0], [1.0, np.inf], [2.0, 0.0]], (n, 1))
    Y = opt.clip(X)
    # in-box coordinates, bounds included, are kept
    assert np.all(Y[0::3, 1] == 3.0) and np.all(Y[1::3, 0] == 1.0)
    np.testing.assert_array_equal(Y[2::3], X[2::3])
    # x = -5 (below -2) and y = inf (above 10) are redrawn from U(-2, 2) and U(0, 10)
    assert stats.kstest(Y[0::3, 0], stats.uniform(-2.0, 4.0).cdf).pvalue > 1e-3
    assert stats.kstest(Y[1::3, 1], stats.uniform(0.0, 10.0).cdf).pvalue > 1e-3
    assert np.unique(Y[0::3, 0]).size == n  # one draw per coordinate


def test_wso_constants_and_schedules():
    p = WSO.defaults
    assert p == {
        "f_min": 0.07, "f_max": 0.75, "tau": 4.11, "p_min": 0.5, "p_max": 1.5,
        "a0": 6.25, "a1": 100.0, "a2": 0.0005,
    }  # fmt: skip
    mu, freq = constants(p)
    # mu = 2 / |2 - 4.11 - sqrt(16.8921 - 16.44)| = 2 / (2.11 + 0.6723838) = 0.7188081
    assert mu == pytest.approx(0.7188081, abs=1e-7)
    # f = 0.07 + (0.75 - 0.07) / (0.75 + 0.07) = 0.07 + 0.8292683 = 0.8992683
    assert freq == pytest.approx(0.8992683, abs=1e-7)
    # k = 150 of 300: p1 = 1.5 + 1.0 e^-4 = 1.5183156, p2 = 0.5183156,
    # mv = 1 / (6.25 + e^0) = 1 / 7.25 = 0.1379310, s_s = 1 - e^-0.00025 = 2.4997e-4
    p1, p2, mv, s_s = schedule(p, 150, 300)
    assert (p1, p2) == pytest.approx((1.5183156, 0.5183156), abs=1e-7)
    assert mv == pytest.approx(0.1379310, abs=1e-7)
    assert s_s == pytest.approx(2.4997e-4, abs=1e-8)


def test_fitness_spread_eqs_6_7():
    # costs 1, 2, 6: mean 3, deviations -2, -1, 3; max |dev| = 3 > 1
    # sigma = sqrt((4 + 1 + 9) / 3) = sqrt(14 / 3) = 2.1602469
    assert fitness_spread(np.array([1.0, 2.0, 6.0])) == pytest.approx(2.1602469)
    # costs 0.1, 0.3: deviations -0.1, 0.1, max 0.1 <= 1 so f = 1: sigma = sqrt(0.02)
    assert fitness_spread(np.array([0.1, 0.3])) == pytest.approx(math.sqrt(0.02))


def test_pso_presets():
    pso = OPTIMIZERS["pso"].declarations()
    assert pso["c1"].default == 2.0 and pso["w_start"].default == 0.9
    issa = {k: p.default for k, p in OPTIMIZERS["pso-issa"].declarations().items()}
    assert (issa["c1"], issa["c2"], issa["w_start"], issa["w_end"]) == (2.5, 2.5, 1.0, 1.0)
    assert issubclass(OPTIMIZERS["pso-issa"], PSO)


def test_registry_and_unknown_names():
    papers = ["wso", "iwso", "ssa", "issa", "pso", "pso-issa", "gwo", "woa", "mrfo", "boa"]
    assert [n for n in NAMES if n in papers] == papers  # the papers' order; variants between
    assert all(OPTIMIZERS[n].name == n for n in NAMES)
    with pytest.raises(UsvError, match=r"unknown algorithm 'abc' \(known: wso, iwso, .*boa\)"):
        make_optimizer("abc")
    with pytest.raises(UsvError, match=r"^--param bogus is not a parameter of gwo \(known: a_st"):
        make_optimizer("gwo", bogus=1)
    with pytest.raises(UsvError, match=r"^--param a_start must be a finite number, not 'x'$"):
        make_optimizer("gwo", a_start="x")
    with pytest.raises(ValueError, match="pop"):
        make_optimizer("gwo", pop=1)
