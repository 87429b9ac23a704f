"""The chaotic maps of IWSO (circle, eq. 7) and ISSA (cubic, eqs. 4-5)."""

from __future__ import annotations

import numpy as np
import pytest

from usvtool.plan.optimizers.chaotic import (
    chain,
    chaotic_population,
    circle_step,
    cubic_step,
)


def test_cubic_map_from_the_papers_start_value():
    # c1 = 2.595 * 0.315 * (1 - 0.315^2) = 0.817425 * 0.900775           = 0.7363160
    # c2 = 2.595 * 0.7363160 * (1 - 0.5421613) = 1.9107400 * 0.4578387   = 0.8748108
    # c3 = 2.595 * 0.8748108 * (1 - 0.7652940) = 2.2701340 * 0.2347060   = 0.5328142
    seq = chain(cubic_step, 0.315, 3)[:, 0]
    assert seq == pytest.approx([0.7363160, 0.8748108, 0.5328142], abs=1e-7)


def test_circle_map_hand_computed():
    # 0.5/(2 pi) = 0.0795775
    # w0 = 0.5:       sin(pi) = 0                 -> w1 = 0.5 + 0.2                      = 0.7
    # w1 = 0.7:       sin(1.4 pi) = -0.9510565   -> w2 = 0.9 + 0.0795775 * 0.9510565    = 0.9756827
    # w2 = 0.9756827: sin(2 pi w2) = -0.1521965  -> 1.1756827 + 0.0121114 = 1.1877941, mod 1
    #                                                                                  = 0.1877941
    # w0 = 0.25:      sin(pi/2) = 1              -> w1 = 0.45 - 0.0795775            = 0.3704225
    seq = chain(circle_step, [0.5, 0.25], 3)
    assert seq[:, 0] == pytest.approx([0.7, 0.9756827, 0.1877941], abs=1e-7)
    assert seq[0, 1] == pytest.approx(0.3704225, abs=1e-7)


def test_maps_stay_in_the_unit_interval():
    starts = np.random.default_rng(3).uniform(0.01, 0.99, 200)
    for step in (circle_step, cubic_step):
        seq = chain(step, starts, 500)
        assert seq.min() >= 0.0 and seq.max() < 1.0
        assert seq.std() > 0.2  # spread over the interval, not collapsed onto a cycle


@pytest.mark.parametrize("step", [circle_step, cubic_step])
def test_population_is_one_chain_per_dimension_mapped_to_the_box(step):
    lower, upper = np.array([-5.0, 0.0, 10.0]), np.array([5.0, 2.0, 30.0])
    pop = chaotic_population(step, 8, lower, upper, np.random.default_rng(1))
    assert pop.shape == (8, 3)
    assert np.all(pop >= lower) and np.all(pop <= upper)
    unit = (pop - lower) / (upper - lower)  # eq. 5 inverted
    np.testing.assert_allclose(unit[1:], step(unit[:-1]), atol=1e-12)
    assert len(np.unique(unit[0])) == 3  # each dimension has its own start


def test_population_deterministic_by_seed_and_explicit_start():
    lo, hi = np.zeros(4), np.ones(4)
    a = chaotic_population(cubic_step, 5, lo, hi, np.random.default_rng(7))
    b = chaotic_population(cubic_step, 5, lo, hi, np.random.default_rng(7))
    c = chaotic_population(cubic_step, 5, lo, hi, np.random.default_rng(8))
    np.testing.assert_array_equal(a, b)
    assert not np.allclose(a, c)
    fixed = chaotic_population(cubic_step, 3, lo, hi, np.random.default_rng(0), x0=0.315)
    np.testing.assert_allclose(fixed[:, 2], [0.7363160, 0.8748108, 0.5328142], atol=1e-7)
