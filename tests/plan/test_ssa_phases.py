"""SSA's iteration as its three phases (ISSA paper eqs. 1-3: producers, followers, scouts), and
benchmarks/bench_ssa_mealpy.py's switched variant, which subclasses SSA and overrides only the
parts of the phases that mealpy's rules change instead of copying the step."""

from __future__ import annotations

import numpy as np
import pytest

from usvtool.plan.optimizers.ssa import SSA

PHASES = ("_step", "_producers", "_followers", "_scouts")


def cost(X):
    return np.sum((X - 1.5) ** 2, axis=1) + np.abs(X).sum(axis=1)


def run(cls, seed=3, **params):
    return cls(16, 30, seed, **params).minimize(cost, -5.0, [5.0] * 4)


@pytest.fixture(scope="module")
def bench(benchmark):
    return benchmark("bench_ssa_mealpy")


def test_the_followers_that_fly_off_are_the_ranks_above_half():
    ssa = SSA(10, 5, 0)
    rank = np.arange(1, 11, dtype=float)[:, None]
    assert np.flatnonzero(ssa._flies_off(rank, 10)).tolist() == [5, 6, 7, 8, 9]  # i = 6..10


def test_the_scouts_are_a_share_drawn_without_repeats():
    ssa = SSA(20, 5, 0)
    scouts = ssa._scouts_of(np.arange(20.0))
    assert scouts.size == 3 and len(set(scouts.tolist())) == 3  # round(0.15 * 20)
    ssa.best_f = 2.0
    assert ssa._to_best(np.array([1.0, 2.0, 3.0])).tolist() == [[False], [False], [True]]


def test_the_producers_safe_move_shrinks_towards_the_origin():
    """eq. 1, no alarm: x exp(-i / (alpha iter_max)) with alpha in (0, 1]: every coordinate
    keeps its sign and shrinks by exp(-i / 5) at least (alpha = 1), one factor per sparrow."""
    ssa = SSA(4, 5, 0)
    X = np.array([[2.0, -3.0], [1.0, 4.0]])
    rank = np.array([[1.0], [2.0]])
    moved = ssa._safe_move(X, rank)
    assert np.all(np.sign(moved) == np.sign(X))
    assert np.all(np.abs(moved) <= np.abs(X) * np.exp(-rank / 5))
    factor = moved / X
    assert factor[:, 0] == pytest.approx(factor[:, 1])


def test_the_switched_variant_overrides_no_phase_whole(bench):
    assert not set(vars(bench.Switched)) & set(PHASES)
    assert issubclass(bench.Switched, SSA)


def test_all_switches_off_is_the_very_run_of_ssa(bench):
    a, b = run(SSA), run(bench.Switched)
    assert a.x.tobytes() == b.x.tobytes() and a.history.tobytes() == b.history.tobytes()
    assert a.evaluations == b.evaluations


@pytest.mark.parametrize("switch", ["redraw", "sign", "all_scouts", "scalar_beta", "flyoff",
                                    "alarm_product"])  # fmt: skip
def test_each_switch_changes_the_run(bench, switch):
    base = run(SSA)
    switched = run(bench.Switched, **{switch: True})
    assert switched.history.tobytes() != base.history.tobytes()
