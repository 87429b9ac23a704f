"""The papers' path metrics on tiny hand-computed polylines."""

from __future__ import annotations

import math

import numpy as np
import pytest

from usvtool import measures

RIGHT = [(0, 0), (1, 0), (1, 1)]  # one right-angle turn
OBTUSE = [(0, 0), (1, 0), (2, 1)]  # interior angle 135°: a 45° turn
ZIGZAG = [(0, 0), (1, 0), (1, 1), (2, 1)]  # left 90°, then right 90°


def test_length_is_the_sum_of_segments():
    assert measures.path_length([(0, 0), (3, 4), (3, 10)]) == pytest.approx(11.0)
    assert measures.path_length([(2, 2), (2, 2)]) == 0.0
    assert measures.path_length([(0, 0), (1, 1), (2, 2)]) == pytest.approx(2 * math.sqrt(2))


@pytest.mark.parametrize(
    "route, degrees",
    [
        (RIGHT, [90]),
        (OBTUSE, [45]),
        ([(0, 0), (2, 0), (1, 0)], [180]),
        ([(0, 0), (1, 0), (2, 0), (3, 0)], [0, 0]),
        ([(0, 0), (1, 0), (1, 0), (1, 1)], [0, 90]),  # repeated point: the turn comes after it
        ([(0, 0), (0, 0), (1, 0), (1, 1)], [0, 90]),  # leading repeated point
        ([(0, 0), (1, 0), (1, 0), (1, 0), (2, 1)], [0, 0, 45]),
        ([(0, 0), (1, 0), (1, 0)], [0]),  # trailing repeated point
        ([(0, 0), (3, 0), (3, 0.03)], [90]),
    ],
)
def test_turn_angles(route, degrees):
    assert np.degrees(measures.turn_angles(route)) == pytest.approx(degrees, abs=1e-9)


def test_turns_count_only_real_heading_changes():
    assert measures.turns(RIGHT) == 1
    assert measures.turns(ZIGZAG) == 2
    assert measures.turns([(0, 0), (1, 0), (2, 0), (3, 0)]) == 0  # collinear
    wobble = [(0, 0), (100, 0), (200, math.tan(math.radians(0.5)) * 100)]
    assert measures.turns(wobble) == 0  # 0.5° is below the 1° tolerance
    kink = [(0, 0), (100, 0), (200, math.tan(math.radians(2)) * 100)]
    assert measures.turns(kink) == 1
    assert measures.turns(wobble, tol_deg=0.1) == 1


def test_issa_turn_cost():
    assert measures.turn_cost(RIGHT) == pytest.approx(0.4)  # right-angle turn
    assert measures.turn_cost(OBTUSE) == pytest.approx(0.2)  # obtuse turn
    assert measures.turn_cost(ZIGZAG) == pytest.approx(0.8)
    assert measures.turn_cost([(0, 0), (1, 0), (2, 0)]) == 0.0
    # continuous between: a 30° turn costs a third of a right angle
    thirty = [(0, 0), (1, 0), (1 + math.cos(math.pi / 6), math.sin(math.pi / 6))]
    assert measures.turn_cost(thirty) == pytest.approx(0.4 / 3)
    assert measures.turn_cost([(0, 0), (1, 0), (0, 0)]) == pytest.approx(0.8)  # reversal


def test_mot_hand_computed():
    assert measures.mot([(0, 0), (5, 5)]) == 0.0
    assert measures.mot(RIGHT) == pytest.approx(math.pi / 2)  # ε = 1, θ_2 = 0
    # ε = 2: (π/2)/(1 + 90)^1.5 + (π/2)/(1 + 0)^1.5
    assert measures.mot(ZIGZAG) == pytest.approx(2 * (math.pi / 2 / 91**1.5 + math.pi / 2))
    # 45° then 90°: ε = 2, terms (π/4)/91^1.5 and π/2
    route = [(0, 0), (1, 0), (2, 1), (1, 2)]
    assert measures.mot(route) == pytest.approx(2 * (math.pi / 4 / 91**1.5 + math.pi / 2))


def test_mot_ignores_points_that_are_not_turns():
    padded = [(0, 0), (0.5, 0), (1, 0), (1, 0), (1, 0.5), (1, 1), (1.5, 1), (2, 1)]
    assert measures.mot(padded) == pytest.approx(measures.mot(ZIGZAG))
    assert measures.turns(padded) == 2


def test_population_gives_the_per_route_values():
    rng = np.random.default_rng(3)
    routes = rng.integers(0, 4, (40, 6, 2)).astype(float)  # many repeats and collinear runs
    for fn in (measures.path_length, measures.turns, measures.turn_cost, measures.mot):
        together = fn(routes)
        assert together.shape == (40,)
        assert together == pytest.approx([fn(r) for r in routes])


def test_repeated_points_do_not_hide_turns():
    rng = np.random.default_rng(4)
    for _ in range(50):
        route = rng.random((5, 2))
        doubled = np.repeat(route, rng.integers(1, 4, 5), axis=0)
        assert measures.turn_cost(doubled) == pytest.approx(measures.turn_cost(route))
        assert measures.mot(doubled) == pytest.approx(measures.mot(route))

