"""benchmarks/bench_fewest_links.py, whose figures say where fewer turns cannot exist: its
shortest routes per number of links on a hand-made wall, against hand computations."""

import math

import numpy as np
import pytest

from usvtool.collision import SegmentChecker


@pytest.fixture(scope="module")
def bench(benchmark):
    return benchmark("bench_fewest_links")


def test_over_a_wall_one_link_is_blocked_two_cost_the_apex_and_three_reach_the_optimum(
    bench, reference
):
    """A wall of cells x 4..6, y 0..7 between (1, 1) and (9, 1), a lattice every 0.1 cell
    (points at 0.05 + 0.1 k). The optimum wraps the wall's two top corners: 2 √45 + 2 =
    15.416; the lattice's nearest points off them are (3.95, 7.05) and (6.05, 7.05): 2 √45.305
    + 2.1. A route of two links must bend above the lines from the start through (4, 7) and
    from the goal through (6, 7), which meet at (5, 9): at least 2 √80 = 17.889; the lattice
    points nearest that apex inside the wedge are (4.95, 9.15) and (5.05, 9.15): √82.825 +
    √82.025. One link crosses the wall."""
    blocked = np.zeros((10, 10), bool)
    blocked[0:7, 4:6] = True
    checker = SegmentChecker(blocked)
    optimum = [(1.0, 1.0), (4.0, 7.0), (6.0, 7.0), (9.0, 1.0)]
    lengths, routes, size = bench.fewest_links(checker, optimum, 0.1, 0.25)
    assert size > 1000
    assert lengths[1] == np.inf and routes[1] is None
    assert lengths[2] == pytest.approx(math.sqrt(82.825) + math.sqrt(82.025), rel=1e-12)
    assert lengths[2] > 2 * math.sqrt(80)
    assert lengths[3] == pytest.approx(2 * math.sqrt(45.305) + 2.1, rel=1e-12)
    assert lengths[3] > 2 * math.sqrt(45) + 2
    for k in (2, 3):
        route = routes[k]
        assert len(route) - 1 == k
        assert route[0].tolist() == [1.0, 1.0] and route[-1].tolist() == [9.0, 1.0]
        assert reference(blocked).route_free(route)
        assert np.hypot(*np.diff(route, axis=0).T).sum() == pytest.approx(lengths[k])
