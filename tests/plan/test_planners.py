"""The planner registry (usvtool/plan/planners.py), the options' own checks (PlanOptions) and the
optimizers' parameter checks (usvtool/params.py: the kind of the default, the range where the
equations need one).

Everything here is read from the registries: a new optimizer is covered without a change here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from affine import Affine

from usvtool.errors import UsvError
from usvtool.grid import Grid
from usvtool.plan import planners
from usvtool.plan.optimizers import OPTIMIZERS
from usvtool.plan.optimizers.base import POSITIVE, PROBABILITY, Range
from usvtool.plan.planner import PlanOptions, plan_route
from usvtool.plan.planners import EXACT

OPEN = Grid(np.zeros((12, 12), np.uint8), Affine(1, 0, 0, 0, -1, 12))
START, GOAL = (0.5, 6.0), (11.5, 6.0)
TINY = dict(pop=4, iters=2, seed=1)


def test_the_names_are_the_optimizers_then_the_exact_planners():
    assert planners.names() == [*OPTIMIZERS, "anyangle", "astar"]
    assert tuple(EXACT) == ("anyangle", "astar")
    for name in planners.names():
        planner = planners.resolve(name)
        assert planner.name == name and planner.seeded == (name in OPTIMIZERS)
        assert planners.resolve(name + "+s").name == name + "+s"


def test_each_suffix_resolves_in_one_place():
    shortened, guided = planners.resolve("pso+s"), planners.resolve("pso+g")
    assert isinstance(shortened, planners.Shortened) and shortened.inner.name == "pso"
    assert isinstance(guided, planners.Guided) and guided.optimizer is OPTIMIZERS["pso"]
    assert (guided.guided, guided.default_waypoints, guided.problem_waypoints("auto")) == (
        True, "auto", 1)  # fmt: skip
    assert (shortened.guided, shortened.default_waypoints, shortened.problem_waypoints(5)) == (
        False, 3, 5)  # fmt: skip
    exact = planners.resolve("astar+s")
    assert not exact.seeded and exact.optimizer is None


@pytest.mark.parametrize("algo, message", [
    ("dijkstra", r"^unknown algorithm 'dijkstra' \(known: wso, .*, boa, anyangle, astar, each "
                 r"also with \+s or \+g\)$"),
    ("anyangle+g", r"^'anyangle\+g': anyangle has no \+g variant \(its variants: \+s\)$"),
    ("iwso+g+s", r"^unknown algorithm 'iwso\+g\+s'"),  # one suffix at most
    ("+s", r"^unknown algorithm '\+s'"),
])  # fmt: skip
def test_unknown_names_and_variants_are_refused(algo, message):
    with pytest.raises(UsvError, match=message):
        planners.resolve(algo)
    with pytest.raises(UsvError, match=message):
        PlanOptions(algo).checked()


@pytest.mark.parametrize("options, message", [
    (dict(encoding="rows"), r"^unknown encoding 'rows' \(known: waypoints, columns\)$"),
    (dict(algo="iwso+g", encoding="columns"), r"^'iwso\+g': \+g has its own encoding, "
                                              r"not 'columns'$"),
    (dict(waypoints="auto"), r"^waypoints 'auto' is for the \+g variants$"),
    (dict(algo="astar+s", waypoints="auto"), r"^waypoints 'auto' is for the \+g variants$"),
    (dict(waypoints=0), r"^waypoints must be an integer >= 1 or 'auto', not 0$"),
    (dict(waypoints=2.5), r"^waypoints must be an integer >= 1 or 'auto', not 2.5$"),
    (dict(attempts=0), r"^attempts must be >= 1, not 0$"),
    (dict(params={"bogus": 1}), r"^--param bogus is not a parameter of iwso \(known: f_min, "),
])  # fmt: skip
def test_the_options_check_themselves(options, message):
    with pytest.raises(UsvError, match=message):
        PlanOptions(**options).checked()
    with pytest.raises(UsvError, match=message):  # before anything is planned
        plan_route(OPEN, START, GOAL, PlanOptions(**options))


def test_the_free_waypoints_default_per_planner():
    assert PlanOptions("iwso").checked()[1] == 3
    assert PlanOptions("iwso+g").checked()[1] == "auto"
    assert PlanOptions("iwso+g", waypoints=2).checked()[1] == 2
    assert PlanOptions("astar", waypoints=7).checked()[1] == 7


def test_an_exact_planner_ignores_optimizer_parameters():
    """A route matrix gives its options to every algorithm; astar has no parameters."""
    route = plan_route(OPEN, START, GOAL, PlanOptions("astar", params={"c1": "abc"})).route
    assert route.parameters == {} and route.seed is None


def test_the_range_text_and_membership():
    assert str(PROBABILITY) == "in [0, 1]" and str(POSITIVE) == "> 0"
    assert str(Range(4.0)) == ">= 4" and str(Range(high=2, open_high=True)) == "< 2"
    assert str(Range(0.0, 1.0, True, True)) == "in (0, 1)"
    assert 0 in PROBABILITY and 1 in PROBABILITY and 1.0001 not in PROBABILITY
    assert 0 not in POSITIVE and 1e-300 in POSITIVE and math.inf in POSITIVE
    assert 0 not in Range(0.0, 1.0, True, True) and 1 not in Range(0.0, 1.0, True, True)


PARAMS = [(name, key) for name, cls in OPTIMIZERS.items() for key in cls.declarations()]


@pytest.mark.parametrize("name, key", PARAMS)
def test_every_parameter_is_checked_for_its_type(name, key):
    cls = OPTIMIZERS[name]
    default = cls.declarations()[key].default
    assert isinstance(default, float)  # every default today; the type a value must have
    cls.check_params({key: default})
    for bad, shown in (("abc", "'abc'"), (True, "True"), (None, "None"), (math.nan, "nan"),
                       (math.inf, "inf")):  # fmt: skip
        with pytest.raises(UsvError, match=rf"^--param {key} must be a finite number, "
                                           rf"not {shown}$"):  # fmt: skip
            cls.check_params({key: bad})


RANGED = [(name, key) for name, cls in OPTIMIZERS.items()
          for key, p in cls.declarations().items() if p.range is not None]  # fmt: skip


def test_the_ranges_hold_their_defaults():
    assert len(RANGED) >= 25  # the probabilities, divisors and Nelder-Mead coefficients
    for name, key in RANGED:
        declared = OPTIMIZERS[name].declarations()[key]
        assert declared.default in declared.range, (name, key)


@pytest.mark.parametrize("name, key", RANGED)
def test_every_range_is_enforced_at_its_ends(name, key):
    """The ends themselves as declared (open or closed), and a value just beyond each."""
    cls = OPTIMIZERS[name]
    limits = cls.declarations()[key].range
    for end, is_open, step in ((limits.low, limits.open_low, -1), (limits.high, limits.open_high,
                                                                     1)):  # fmt: skip
        if math.isinf(end):
            continue
        beyond = end + step * max(abs(end), 1.0) * 1e-6
        with pytest.raises(UsvError, match=rf"^--param {key} must be {re_text(limits)} for "
                                           rf"{name}, not "):  # fmt: skip
            cls.check_params({key: beyond})
        if is_open:
            with pytest.raises(UsvError):
                cls.check_params({key: end})
        else:
            cls.check_params({key: end})


def re_text(limits: Range) -> str:
    return str(limits).replace("[", r"\[").replace("(", r"\(").replace(")", r"\)")


def test_hand_picked_ranges_from_the_equations():
    """A probability, a share, Nelder-Mead's coefficients, WSO's tau (mu's square root)."""
    for name, key, bad, text in (
        ("boa", "p", 1.5, "in [0, 1]"), ("ssa", "safety", -0.1, "in [0, 1]"),
        ("ssa", "zeta", 0.0, "> 0"), ("iwso", "chi", 1.0, "> 1"), ("iwso", "phi", 1.0, "in (0, 1)"),
        ("wso", "tau", 3.9, ">= 4"), ("pso-issa", "vmax", 0.0, "> 0"),
    ):  # fmt: skip
        with pytest.raises(UsvError) as info:
            OPTIMIZERS[name].check_params({key: bad})
        assert str(info.value) == f"--param {key} must be {text} for {name}, not {bad!r}"


def test_a_string_value_is_one_line_not_a_numpy_error():
    """Was: internal error UFuncTypeError from inside the optimizer."""
    with pytest.raises(UsvError, match=r"^--param c1 must be a finite number, not 'abc'$"):
        plan_route(OPEN, START, GOAL, PlanOptions("pso", params={"c1": "abc"}, **TINY))
    with pytest.raises(UsvError, match=r"^--param c1 must be"):  # +g: before any search
        plan_route(OPEN, START, GOAL, PlanOptions("pso+g", params={"c1": "abc"}, **TINY))


def test_an_integer_value_for_a_float_parameter_is_kept_as_given():
    route = plan_route(OPEN, START, GOAL, PlanOptions("pso", params={"c1": 2}, **TINY)).route
    assert route.parameters["c1"] == 2 and isinstance(route.parameters["c1"], int)
