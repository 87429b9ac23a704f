"""Routes planned at the papers' budget (50 agents x 300 iterations) on env1, env2 and a real
NOAA chart are collision-free by the independent shapely check, not by the planner's own flag."""

import numpy as np
import pytest

from usvtool.chart.georef import WGS84, transformer
from usvtool.chart.preprocess import Options, preprocess
from usvtool.grid import read_grid
from usvtool.plan.optimizers import OPTIMIZERS
from usvtool.plan.route import plan_route

# the Mississippi's main channel on chart 11361_4, Pilottown to Head of Passes (lon, lat)
CHANNEL_START, CHANNEL_GOAL = (-89.2677, 29.1840), (-89.2619, 29.1240)


def cells(grid, points) -> np.ndarray:
    return np.column_stack(grid.to_cell_coords(*np.asarray(points).T))


@pytest.fixture(scope="module")
def river(kap):
    """The KAP chart gridded at 10 m cells, the channel's ends in its UTM metres, and the
    length of the exact any-angle route between them."""
    grid = preprocess(kap, Options(cell_size=10.0)).grid
    to_utm = transformer(WGS84, grid.crs)
    ends = [tuple(float(v) for v in to_utm.transform(*p)) for p in (CHANNEL_START, CHANNEL_GOAL)]
    return grid, ends, plan_route(grid, *ends, "anyangle").length_m


@pytest.mark.parametrize("algo", [*OPTIMIZERS, "iwso+s", "anyangle", "astar"])
def test_every_algorithm_on_the_river_channel(river, algo, reference):
    grid, (start, goal), optimum = river
    route = plan_route(grid, start, goal, algo, pop=50, iters=300, seed=1)
    assert reference(grid.blocked).route_free(cells(grid, route.points))
    assert route.collision_free
    assert route.length_m >= optimum * (1 - 1e-9)  # nothing beats the exact any-angle route
    assert route.length_m <= optimum * 1.05  # a near-straight channel: all come close


@pytest.mark.parametrize("env", ["env1", "env2"])
def test_iwso_on_the_bundled_environments(charts, env, reference):
    grid = read_grid(charts / f"{env}.tif")
    ref = reference(grid.blocked)
    optimum = plan_route(grid, (10, 10), (490, 490), "anyangle").length_m
    for seed in range(3):
        route = plan_route(grid, (10, 10), (490, 490), "iwso", pop=50, iters=300, seed=seed)
        assert ref.route_free(cells(grid, route.points))
        assert optimum * (1 - 1e-9) <= route.length_m <= optimum * 1.25
