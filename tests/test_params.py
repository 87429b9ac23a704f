"""One parameter declaration and one check for the optimizers, the controllers and the scene
families (usvtool/params.py): the rule set of each kind, the ranges and choices, the error lines
naming the parameter as the caller names it, the layering of a subclass's declarations, and the
older attributes (``defaults``, ``ranges``, ``common``, ``options``) still taken."""

from __future__ import annotations

import math

import numpy as np
import pytest

from usvtool.errors import UsvError
from usvtool.params import (
    NON_NEGATIVE,
    POSITIVE,
    PROBABILITY,
    Param,
    Range,
    check,
    declared,
    defaults,
    describe,
)
from usvtool.plan.optimizers import OPTIMIZERS
from usvtool.plan.optimizers.base import Optimizer
from usvtool.sim.controllers import CONTROLLERS
from usvtool.sim.controllers.dwa import DWA
from usvtool.sim.families import FAMILIES, Family, Option


def refusal(param: Param, value, where: str = "--param x", owner: str = "m") -> str | None:
    """The one line ``param`` refuses ``value`` with, or None when it takes it."""
    try:
        param.check(value, where, owner)
    except UsvError as exc:
        assert "\n" not in str(exc)
        return str(exc)
    return None


@pytest.mark.parametrize("param, takes, refuses", [
    # true/false only
    (Param(False), [True, False], [(0, "must be true or false, not 0"),
                                   ("yes", "must be true or false, not 'yes'")]),
    # an int default: an integer
    (Param(21, range=Range(2)), [2, 21, np.int64(5)],
     [(20.5, "must be an integer, not 20.5"), (2.0, "must be an integer, not 2.0"),
      (True, "must be an integer, not True"), (1, "must be >= 2 for m, not 1")]),
    # a float default: any finite real number
    (Param(0.5, range=PROBABILITY), [0, 1, 0.25, np.float64(0.5)],
     [(math.nan, "must be a finite number, not nan"), (math.inf, "must be a finite number, "
      "not inf"), ("0.5", "must be a finite number, not '0.5'"), (None, "must be a finite "
      "number, not None"), (1.5, "must be in [0, 1] for m, not 1.5")]),
    # null: a finite number or null
    (Param(None, range=POSITIVE), [None, 3, 2.5],
     [(0, "must be > 0 for m, not 0"), ("far", "must be null or a finite number, not 'far'")]),
    # a word: a non-empty string, one of the choices
    (Param("a", choices=("a", "b")), ["a", "b"],
     [("c", "must be one of a, b for m, not 'c'"), ("", "must be a non-empty string, not ''"),
      (1, "must be a non-empty string, not 1")]),
    (Param("anything"), ["x"], [(None, "must be a non-empty string, not None")]),
    # a list of strings (a command line): a non-empty one
    (Param(["prog"]), [["a"], ("a", "b"), ["a", ""]],
     [([], "must be a non-empty list of strings, not []"),
      ("prog", "must be a non-empty list of strings, not 'prog'"),
      (["a", 1], "must be a non-empty list of strings, not ['a', 1]")]),
    (Param([]), [["./client.py"]], [([], "must be a non-empty list of strings, not []")]),
])  # fmt: skip
def test_each_kind_takes_what_its_rule_says(param, takes, refuses):
    for value in takes:
        assert refusal(param, value) is None, value
    for value, words in refuses:
        assert refusal(param, value) == f"--param x {words}"


def test_a_file_parameter_names_an_existing_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    param = Param("", "the tracks", file=True, required=True)
    (tmp_path / "t.csv").write_text("x\n")
    assert refusal(param, "t.csv") is None
    assert refusal(param, 3) == "--param x must be a file's path, not 3"
    assert refusal(param, "no.csv") == "--param x must be an existing file's path, not 'no.csv'"
    with pytest.raises(UsvError, match=r"^--family-option x must be given for family f: the "
                                       r"tracks$"):  # fmt: skip
        check({"x": param}, {}, lambda k: f"--family-option {k}", "family f", complete=True)
    assert check({"x": param}, {}, str, "f") == {"x": ""}  # not complete: a part of the values


def test_the_check_names_the_parameter_as_its_caller_does():
    params = {"gain": Param(1.0, range=NON_NEGATIVE), "n": Param(3)}
    for where, line in [
        (lambda k: f"--param {k}", "--param gain must be >= 0 for udwa, not -1"),
        (lambda k: f"scenario.yaml: controller.{k}", "scenario.yaml: controller.gain must be "
                                                    ">= 0 for udwa, not -1"),
        (lambda k: f"pipelines/x.yaml: families[0].options.{k}", "pipelines/x.yaml: "
                                          "families[0].options.gain must be >= 0 for udwa, not -1"),
    ]:  # fmt: skip
        with pytest.raises(UsvError) as info:
            check(params, {"gain": -1}, where, "udwa")
        assert str(info.value) == line
    with pytest.raises(UsvError) as info:
        check(params, {"gain": 1, "speed": 2}, lambda k: f"--param {k}", "udwa")
    assert str(info.value) == "--param speed is not a parameter of udwa (known: gain, n)"
    assert check(params, {"n": 5}, str, "udwa") == {"gain": 1.0, "n": 5}
    with pytest.raises(UsvError, match=r"known: none\)$"):
        check({}, {"a": 1}, str, "plain")


def test_a_declaration_that_contradicts_itself_is_refused():
    for make, words in [
        (lambda: Param("a", range=POSITIVE), "a range is for numbers"),
        (lambda: Param(1.0, choices=("a",)), "choices are for strings"),
        (lambda: Param(0.0, range=POSITIVE), "its default 0.0 is not a finite number > 0"),
        (lambda: Param("c", choices=("a", "b")), "its default 'c' is not one of a, b"),
        (lambda: Param(1.0, file=True), "a file parameter"),
        (lambda: Param(1, kind="word"), "unknown kind 'word'"),
    ]:
        with pytest.raises(ValueError, match=words):
            make()
    # an int default takes an int, unless the declaration says any number
    assert refusal(Param(1, kind="number"), 1.5) is None


def test_a_subclass_adds_to_and_changes_its_bases_declarations():
    class Base(Optimizer):
        name = "base"
        parameters = {"sides": Param("none", "a side", choices=("none", "paper")),
                      "gain": Param(1.0, "a gain", POSITIVE)}  # fmt: skip

        def _run(self):
            pass

    class Mine(Base):
        parameters = {"sides": "paper", "extra": 2}

    p = declared(Mine, ("parameters",))
    assert list(p) == ["sides", "gain", "extra"]
    sides = p["sides"]
    assert (sides.default, sides.choices, sides.help) == ("paper", ("none", "paper"), "a side")
    assert p["gain"] is Base.parameters["gain"] and p["extra"].kind == "integer"
    with pytest.raises(ValueError, match="its default 'left' is not one of none, paper"):
        declared(type("Bad", (Base,), {"parameters": {"sides": "left"}}), ("parameters",))


def test_older_plugins_declarations_still_work():
    """A plugin written for the older attributes: an optimizer's plain ``defaults`` and
    ``ranges``, a controller's ``defaults`` (over DWA's), a family's ``Option``s; and code that
    reads ``X.defaults`` / ``X.ranges`` / ``X.options`` of a built-in."""

    class Random(Optimizer):
        name = "random"
        defaults = {"share": 1.0, "draws": 3}
        ranges = {"share": Range(0.0, 1.0, open_low=True)}

        def _run(self):
            pass

    assert Random.check_params({"share": 0.5}) is None
    with pytest.raises(UsvError, match=r"^--param share must be in \(0, 1\] for random, not 0$"):
        Random.check_params({"share": 0})
    with pytest.raises(UsvError, match=r"^--param draws must be an integer, not 2.5$"):
        Random.check_params({"draws": 2.5})
    assert Random.defaults == {"share": 1.0, "draws": 3}
    assert Random(pop=4, iters=1).params == {"share": 1.0, "draws": 3}

    class Slow(DWA):
        name = "slow"
        defaults = {"w_velocity": 0.1, "sides": "paper", "slowness": 2.0}

    decl = Slow.declarations()
    assert decl["sides"].choices == DWA.declarations()["sides"].choices
    assert (decl["w_velocity"].default, decl["slowness"].default) == (0.1, 2.0)
    with pytest.raises(UsvError, match=r"^sides must be one of none, "):
        Slow(sides="left")

    class Old(Family):
        name = "old"
        kinds = ("a",)
        options = {"speed": Option(3, "m/s"), "word": Option("x", "w", choices=("x", "y")),
                   "wind": Option(0.0, "deg", False)}  # fmt: skip

    decl = Old.declarations()
    assert decl["speed"].range == POSITIVE and decl["wind"].range == NON_NEGATIVE
    assert Old().check_options({"speed": 2.5}, str)["speed"] == 2.5  # a number, as it was
    with pytest.raises(UsvError, match=r"^speed must be > 0 for family old, not 0$"):
        Old().check_options({"speed": 0}, str)
    from usvtool.plan.optimizers.ssa import SSA

    assert SSA.defaults["zeta"] == 1e-50 and SSA.ranges["zeta"] == POSITIVE
    assert FAMILIES["ais"].options["map"].file


def test_every_built_in_declaration_is_whole():
    """Every parameter of every built-in method has a help line and a default its declaration
    takes; every number of an optimizer or a family is a float; usvtool plugins's data."""
    for registry in (OPTIMIZERS, CONTROLLERS, FAMILIES):
        for name, cls in registry.items():
            for key, p in cls.declarations().items():
                if registry.origin(name)[0] != "usvtool" or name == "exec":
                    continue
                assert p.help, (name, key)
                assert describe({key: p})[key]["default"] == defaults({key: p})[key]
                if registry is not CONTROLLERS and p.kind in ("integer", "number"):
                    assert isinstance(p.default, float), (name, key)
