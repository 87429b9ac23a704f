"""The benchmark functions F1-F10 (IWSO paper, Table 1)."""

from __future__ import annotations

import numpy as np
import pytest

from usvtool.errors import UsvError
from usvtool.plan.benchmark_functions import FUNCTIONS, get_function


def value(name, x, rng=None):
    return float(get_function(name).objective(rng)(np.atleast_2d(np.asarray(x, float)))[0])


@pytest.mark.parametrize(
    ("name", "x", "expected"),
    [
        ("F1", [1, 2, 3], 14.0),  # 1 + 4 + 9
        ("F2", [1, -2, 3], 12.0),  # (1 + 2 + 3) + 1 * 2 * 3
        ("F3", [1, 2, 3], 46.0),  # partial sums 1, 3, 6: 1 + 9 + 36
        ("F4", [1, -7, 3], 7.0),  # max |x|
        ("F5", [-1, 1, 0], 104.0),  # 100 (1 - 1)^2 + (-2)^2 + 100 (0 - 1)^2 + 0^2
        ("F6", [0.4, -0.6, 1.5], 5.0),  # floor(x + 0.5) = 0, -1, 2: 0 + 1 + 4
        ("F8", [1.0, 4.0], -1.0 * np.sin(1.0) - 4.0 * np.sin(2.0)),  # -x sin(sqrt|x|)
        ("F9", [0.5, 1.0], 21.25),  # (0.25 + 10 + 10) + (1 - 10 + 10)
        ("F10", [1.0, 1.0], 20.0 - 20.0 * np.exp(-0.2)),  # -20 e^-0.2 - e^1 + 20 + e
    ],
)
def test_hand_computed_values(name, x, expected):
    assert value(name, x) == pytest.approx(expected, rel=1e-12)


def test_quartic_noise_is_uniform_and_seeded():
    f7 = get_function("F7")
    X = np.array([[1.0, 1.0]] * 200)  # 1 * 1 + 2 * 1 = 3 before the noise
    a = f7.objective(np.random.default_rng(1))(X)
    b = f7.objective(np.random.default_rng(1))(X)
    c = f7.objective(np.random.default_rng(2))(X)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    assert np.all((a >= 3.0) & (a < 4.0)) and 3.3 < a.mean() < 3.7


def test_schwefel_226_optimum_in_30_dimensions():
    assert value("F8", np.full(30, 420.9687)) == pytest.approx(-12569.5, abs=0.05)
    assert get_function("F8").optimum(30) == pytest.approx(-12569.4866, abs=1e-4)


@pytest.mark.parametrize("name", list(FUNCTIONS))
def test_minimiser_reaches_the_known_optimum(name):
    fn = get_function(name)
    x_star = np.full((1, 30), fn.x_star)
    got = fn.objective(np.random.default_rng(0))(x_star)[0]
    if fn.noisy:
        assert 0.0 <= got - fn.optimum(30) < 1.0
    else:
        assert got == pytest.approx(fn.optimum(30), abs=1e-9)
    # and nearby points are worse (noise-free part for F7)
    near = x_star + np.random.default_rng(1).uniform(-0.05, 0.05, (20, 30)) * fn.bound
    lower, upper = fn.bounds(30)
    near = np.clip(near, lower, upper)
    assert np.all(fn.func(near) > fn.func(x_star)[0])


def test_bounds_and_table():
    expected = {
        "F1": 100, "F2": 10, "F3": 100, "F4": 100, "F5": 30,
        "F6": 100, "F7": 1.28, "F8": 500, "F9": 5.12, "F10": 32,
    }  # fmt: skip
    assert {n: f.bound for n, f in FUNCTIONS.items()} == expected
    lower, upper = get_function("F9").bounds(30)
    assert lower.shape == upper.shape == (30,)
    assert np.all(lower == -5.12) and np.all(upper == 5.12)


@pytest.mark.parametrize("name", [n for n in FUNCTIONS if n != "F7"])
def test_vectorised_rows_are_independent(name):
    fn = get_function(name)
    X = np.random.default_rng(4).uniform(-fn.bound, fn.bound, (7, 30))
    rows = [fn.func(x[None])[0] for x in X]
    np.testing.assert_allclose(fn.func(X), rows, rtol=1e-12)


def test_unknown_function():
    assert get_function("f10").name == "F10"
    with pytest.raises(UsvError, match=r"unknown function 'F11' \(known: F1, .*F10\)"):
        get_function("F11")
