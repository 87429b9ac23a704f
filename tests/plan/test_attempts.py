"""``plan_route`` with ``PlanOptions(attempts=N)``: independent optimizer runs until the best
route is collision-free.

Tiny populations and one iteration make single runs fail often, so the stopping rule shows on a
10 x 10 grid in milliseconds. Collisions are judged by the shapely reference, not by the planner.
"""

from __future__ import annotations

import numpy as np
import pytest
from affine import Affine

from usvtool.grid import Grid
from usvtool.plan.optimizers import make_optimizer
from usvtool.plan.planner import PlanOptions, plan_route
from usvtool.plan.problem import PathProblem

START, GOAL = (0.5, 5.0), (9.5, 5.0)
WEAK = dict(algo="pso", pop=2, iters=1, waypoints=1)  # a search that often ends in the block


def grid_with(blocked: np.ndarray) -> Grid:
    return Grid(blocked.astype(np.uint8), Affine(1, 0, 0, 0, -1, blocked.shape[0]))


@pytest.fixture(scope="module")
def block():
    """A 2 x 4 block across the straight route: one waypoint above or below it clears it."""
    cells = np.zeros((10, 10), np.uint8)
    cells[3:7, 4:6] = 1
    return grid_with(cells)


@pytest.fixture(scope="module")
def wall():
    """A wall with a gap in the top row: no one-waypoint route gets through."""
    cells = np.zeros((10, 10), np.uint8)
    cells[1:10, 5] = 1
    return grid_with(cells)


def free(grid: Grid, route, reference) -> bool:
    col, row = grid.to_cell_coords(*np.asarray(route.points).T)
    return reference(grid.blocked).route_free(np.column_stack([col, row]))


def first_seed_needing_a_second_run(grid, reference) -> int:
    for seed in range(50):
        if not free(
            grid, plan_route(grid, START, GOAL, PlanOptions(seed=seed, **WEAK)).route, reference
        ):
            return seed
    raise AssertionError("every single run was collision-free: the test map is too easy")


def test_runs_stop_at_the_first_collision_free_route(block, reference):
    seed = first_seed_needing_a_second_run(block, reference)
    route = plan_route(block, START, GOAL, PlanOptions(seed=seed, attempts=20, **WEAK)).route
    assert free(block, route, reference) and route.collision_free
    k = route.attempt
    assert 2 <= k <= 20 and route.parameters["attempts"] == 20
    # the same route with exactly k runs allowed; with k - 1, every run collided
    again = plan_route(block, START, GOAL, PlanOptions(seed=seed, attempts=k, **WEAK)).route
    np.testing.assert_array_equal(again.points, route.points)
    fewer = plan_route(block, START, GOAL, PlanOptions(seed=seed, attempts=k - 1, **WEAK)).route
    assert not free(block, fewer, reference) and not fewer.collision_free


def test_one_attempt_is_the_single_run(block):
    single = plan_route(block, START, GOAL, PlanOptions(seed=3, **WEAK)).route
    once = plan_route(block, START, GOAL, PlanOptions(seed=3, attempts=1, **WEAK)).route
    np.testing.assert_array_equal(single.points, once.points)
    assert single.attempt == once.attempt == 1 and single.parameters["attempts"] == 1


def test_the_second_run_is_seeded_by_the_seeds_first_spawned_child(block, reference):
    """The documented seed derivation: run 2 uses SeedSequence(seed).spawn(...)[0]."""
    seed = first_seed_needing_a_second_run(block, reference)
    problem = PathProblem(block, START, GOAL, waypoints=1)
    search = problem.search()
    child = np.random.SeedSequence(seed).spawn(1)[0]
    result = make_optimizer("pso", 2, 1, np.random.default_rng(child)).minimize(
        search, search.lower, search.upper
    )
    run2 = problem.decode(search.to_problem(result.x))
    run1 = plan_route(block, START, GOAL, PlanOptions(seed=seed, **WEAK)).route
    route = plan_route(block, START, GOAL, PlanOptions(seed=seed, attempts=2, **WEAK)).route
    run2_fitness = problem.cost(run2, exact=True)[0]
    expected = problem.to_map(run2[0]) if run2_fitness < run1.fitness else run1.points
    np.testing.assert_allclose(route.points, expected)  # run 2's route if free (then cheaper)


def test_when_every_run_collides_the_cheapest_route_is_kept(wall, reference):
    routes = [
        plan_route(wall, START, GOAL, PlanOptions(seed=7, attempts=n, **WEAK)).route
        for n in (1, 2, 4, 8)
    ]
    assert not any(free(wall, r, reference) or r.collision_free for r in routes)
    fitness = [r.fitness for r in routes]
    assert fitness == sorted(fitness, reverse=True)  # more runs never keep a dearer route
    assert fitness[-1] < fitness[0]  # and the runs differ
    assert routes[-1].attempt in range(1, 9)


def test_exact_planners_run_once(block):
    route = plan_route(block, START, GOAL, PlanOptions("anyangle", attempts=5)).route
    assert route.attempt is None and "attempts" not in route.parameters


def test_attempts_below_one_is_refused(block):
    from usvtool.errors import UsvError

    with pytest.raises(UsvError, match="attempts must be >= 1"):
        plan_route(block, START, GOAL, PlanOptions(attempts=0, **WEAK))
