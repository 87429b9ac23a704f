"""The parameters of a method (an optimizer, a controller, a scene family), declared and
checked in one way for the three kinds, built in or from a plugin.

A method declares each parameter as a :class:`Param`: its default, what it sets (``help``), a
:class:`Range` for a number, ``choices`` for a word, ``file`` for the path of a file it reads
and ``required`` for one that must be given. The kind of value it takes comes from its default
(or ``kind``), by one rule set (:data:`KINDS`):

- ``true``/``false`` default (``bool``): true or false only;
- an int default (``integer``): an integer (``2.0`` is refused: give ``kind=NUMBER`` to take
  any number with an int default);
- a float default (``number``): any finite real number (an int too);
- ``None`` (``number or null``): a finite number or null;
- a string (``string``): a non-empty string, one of ``choices`` when they are given;
- a list of strings (``strings``): a non-empty list of strings (a command line);
- ``file=True`` (``file``): the path of an existing file;
- anything else (``any``): any value (what the older declarations let through).

A range holds for the numbers. :func:`check` refuses a parameter the method has not got and a
value its declaration does not take, in one line naming the parameter as the caller names it
(``where(name)``: ``--param horizon``, ``scenario.yaml: controller.horizon``, ``--family-option
own_speed``), e.g. ``--param p must be in [0, 1] for boa, not 1.5``.

A class declares its parameters in a mapping attribute (``parameters``; the older attributes
too, :func:`declared`): a :class:`Param` per name, or a plain value, which is a declaration with
no range or help (``{"share": 1.0}``), or, for a name a base class declared, the declaration
with another default (``{"sides": "paper"}`` keeps ``sides``'s choices).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path

from usvtool.errors import UsvError
from usvtool.yamlfile import show

#: ``where(name)``: how an error line names a parameter (``--param NAME``).
Where = Callable[[str], str]

BOOL, INTEGER, NUMBER, NULLABLE = "bool", "integer", "number", "number or null"
STRING, STRINGS, FILE, ANY = "string", "strings", "file", "any"
#: Each kind and what a value of it must be (the error lines' words).
KINDS = {
    BOOL: "true or false",
    INTEGER: "an integer",
    NUMBER: "a finite number",
    NULLABLE: "null or a finite number",
    STRING: "a non-empty string",
    STRINGS: "a non-empty list of strings",
    FILE: "a file's path",
    ANY: "anything",
}


@dataclass(frozen=True)
class Range:
    """The interval a numeric parameter must lie in (``open_low``/``open_high``: that end
    excluded).

    >>> str(Range(0, 1)), str(Range(0, open_low=True)), str(Range(0.0, 1.0, True, True))
    ('in [0, 1]', '> 0', 'in (0, 1)')
    >>> 0 in Range(0, open_low=True), 0.5 in Range(0, 1)
    (False, True)
    """

    low: float = -math.inf
    high: float = math.inf
    open_low: bool = False
    open_high: bool = False

    def __contains__(self, value: float) -> bool:
        above = value > self.low if self.open_low else value >= self.low
        below = value < self.high if self.open_high else value <= self.high
        return above and below

    def __str__(self) -> str:
        if self.high == math.inf:
            return f"{'>' if self.open_low else '>='} {self.low:g}"
        if self.low == -math.inf:
            return f"{'<' if self.open_high else '<='} {self.high:g}"
        return (f"in {'(' if self.open_low else '['}{self.low:g}, {self.high:g}"
                f"{')' if self.open_high else ']'}")  # fmt: skip


PROBABILITY = Range(0.0, 1.0)  # a probability, a threshold against U(0, 1), a population share
POSITIVE = Range(0.0, open_low=True)  # a divisor, a scale that must not vanish
NON_NEGATIVE = Range(0.0)


@dataclass(frozen=True)
class Param:
    """One parameter: its default, what it sets, the range a number must lie in, the words a
    string must be one of, whether it names a file (a string default, ``""`` when none) and
    whether it must be given; ``kind`` (:data:`KINDS`) comes from the default when not given.
    A declaration that contradicts itself (a range on a word, a default outside its own range)
    is a ``ValueError``.

    >>> Param(0.5, "a share", PROBABILITY).takes()
    'a finite number in [0, 1]'
    >>> Param(21, range=Range(2)).takes(), Param("a", choices=("a", "b")).takes()
    ('an integer >= 2', 'one of a, b')
    """

    default: object
    help: str = ""
    range: Range | None = None
    choices: tuple[str, ...] = ()
    file: bool = False
    required: bool = False
    kind: str = ""

    def __post_init__(self):
        kind = self.kind or _kind_of(self.default, self.file)
        object.__setattr__(self, "kind", kind)
        object.__setattr__(self, "choices", tuple(self.choices))
        if kind not in KINDS:
            raise ValueError(f"unknown kind {kind!r} (known: {', '.join(KINDS)})")
        if self.range is not None and kind not in (INTEGER, NUMBER, NULLABLE):
            raise ValueError(f"a range is for numbers, not for a parameter of kind {kind}")
        if self.choices and kind != STRING:
            raise ValueError(f"choices are for strings, not for a parameter of kind {kind}")
        if self.file != (kind == FILE) or (self.file and not isinstance(self.default, str)):
            raise ValueError("a file parameter is of kind file, with a string default")
        unset = self.required or kind == FILE or (kind == STRINGS and not self.default)
        if not unset and self.problem(self.default, "owner") is not None:
            raise ValueError(f"its default {show(self.default)} is not {self.takes()}")

    def takes(self) -> str:
        """What a value must be, in words: ``a finite number > 0``, ``one of a, b``."""
        if self.choices:
            return f"one of {', '.join(self.choices)}"
        return KINDS[self.kind] + (f" {self.range}" if self.range is not None else "")

    def problem(self, value, owner: str) -> str | None:
        """What ``value`` must be (``must be ...``) when this parameter does not take it, else
        None; a rule of the method's own (a range, choices) names ``owner``."""
        kind = self.kind
        number = isinstance(value, numbers.Real) and not isinstance(value, bool)
        if kind == ANY:
            return None
        if kind == BOOL:
            ok = isinstance(value, bool)
        elif kind == INTEGER:
            ok = isinstance(value, numbers.Integral) and not isinstance(value, bool)
        elif kind in (NUMBER, NULLABLE):
            ok = (number and math.isfinite(value)) or (kind == NULLABLE and value is None)
        elif kind == STRINGS:
            ok = (isinstance(value, list | tuple) and len(value) > 0
                  and all(isinstance(v, str) for v in value))  # fmt: skip
        else:  # STRING, FILE
            ok = isinstance(value, str) and value != ""
        if not ok:
            return f"must be {KINDS[kind]}"
        if self.range is not None and value is not None and value not in self.range:
            return f"must be {self.range} for {owner}"
        if self.choices and value not in self.choices:
            return f"must be one of {', '.join(self.choices)} for {owner}"
        if kind == FILE and not Path(value).is_file():
            return "must be an existing file's path"
        return None

    def check(self, value, where: str, owner: str):
        """``value``, or :class:`UsvError`: ``WHERE must be WHAT[ for OWNER], not VALUE``."""
        why = self.problem(value, owner)
        if why is not None:
            raise UsvError(f"{where} {why}, not {show(value)}")
        return value

    def describe(self) -> dict:
        """The declaration as data (``usvtool plugins``): default, kind, what it takes, and its
        range, choices, file, required and help when it has them."""
        out = {"default": self.default, "kind": self.kind, "takes": self.takes()}
        if self.range is not None:
            out["range"] = str(self.range)
        if self.choices:
            out["choices"] = list(self.choices)
        if self.required:
            out["required"] = True
        if self.help:
            out["help"] = self.help
        return out


def _kind_of(default, file: bool) -> str:
    if file:
        return FILE
    if isinstance(default, bool):
        return BOOL
    if isinstance(default, numbers.Integral):
        return INTEGER
    if isinstance(default, numbers.Real):
        return NUMBER
    if default is None:
        return NULLABLE
    if isinstance(default, str):
        return STRING
    if isinstance(default, list | tuple) and all(isinstance(v, str) for v in default):
        return STRINGS
    return ANY


def declared(cls: type, attributes: tuple[str, ...] = ("parameters",)) -> dict[str, Param]:
    """The parameters ``cls`` declares, by name in declaration order: the ``attributes`` of each
    class of its MRO, from the base's to its own, in that order; a :class:`Param` declares, a
    plain value declares one with no range (a new name) or changes a declared one's default. An
    attribute named ``ranges`` (the optimizers' older one) gives names declared so far their
    :class:`Range`. ``ValueError`` for a declaration that contradicts itself.

    >>> class Base:
    ...     parameters = {"sides": Param("none", choices=("none", "paper")), "gain": 1.0}
    >>> class Mine(Base):
    ...     parameters = {"sides": "paper"}
    >>> p = declared(Mine)
    >>> p["sides"].default, p["sides"].choices, p["gain"].kind
    ('paper', ('none', 'paper'), 'number')
    """
    out: dict[str, Param] = {}
    for klass in reversed(cls.__mro__):
        own = vars(klass)
        for attribute in attributes:
            layer = own.get(attribute)
            if not isinstance(layer, Mapping):  # absent, or a base's View of the older name
                continue
            for key, value in layer.items():
                if attribute == "ranges":
                    if key in out:
                        out[key] = replace(out[key], range=value)
                elif isinstance(value, Param):
                    out[key] = value
                elif key in out:
                    out[key] = replace(out[key], default=value)
                else:
                    out[key] = Param(value)
    return out


class View:
    """A class attribute that reads a class's declarations (``cls.declarations()``) through
    ``read``: the older attributes (``defaults``, ``ranges``) as code written for them reads
    them (``{**SSA.defaults, "x": 1}`` in a subclass still declares)."""

    def __init__(self, read: Callable[[dict[str, Param]], dict]):
        self.read = read

    def __get__(self, obj, owner: type) -> dict:
        return self.read(owner.declarations())


def ranges(params: Mapping[str, Param]) -> dict[str, Range]:
    """The :class:`Range` of every parameter that has one, by name."""
    return {k: p.range for k, p in params.items() if p.range is not None}


def defaults(params: Mapping[str, Param]) -> dict:
    """Every parameter's default, by name (a list default copied)."""
    return {k: list(p.default) if isinstance(p.default, list) else p.default
            for k, p in params.items()}  # fmt: skip


def check(params: Mapping[str, Param], given: Mapping, where: Where, owner: str, *,
          complete: bool = False) -> dict:  # fmt: skip
    """The values of a run: the defaults of ``params`` and ``given`` over them, each given one
    checked (:meth:`Param.check`); with ``complete``, every ``required`` one must be given.
    :class:`UsvError` in one line naming the parameter by ``where(name)`` and the method by
    ``owner``.

    >>> ps = {"p": Param(0.8, range=PROBABILITY), "n": Param(3)}
    >>> check(ps, {"p": 0.5}, lambda k: f"--param {k}", "boa")
    {'p': 0.5, 'n': 3}
    >>> check(ps, {"p": 1.5}, lambda k: f"--param {k}", "boa")
    Traceback (most recent call last):
    usvtool.errors.UsvError: --param p must be in [0, 1] for boa, not 1.5
    >>> check(ps, {"n": 2.0}, lambda k: f"--param {k}", "boa")
    Traceback (most recent call last):
    usvtool.errors.UsvError: --param n must be an integer, not 2.0
    >>> check(ps, {"q": 1}, lambda k: f"--param {k}", "boa")
    Traceback (most recent call last):
    usvtool.errors.UsvError: --param q is not a parameter of boa (known: p, n)
    """
    for key, value in given.items():
        if key not in params:
            known = ", ".join(params) or "none"
            raise UsvError(f"{where(key)} is not a parameter of {owner} (known: {known})")
        params[key].check(value, where(key), owner)
    if complete:
        for key, p in params.items():
            if p.required and key not in given:
                what = f": {p.help}" if p.help else ""
                raise UsvError(f"{where(key)} must be given for {owner}{what}")
    return {**defaults(params), **given}


def describe(params: Mapping[str, Param]) -> dict[str, dict]:
    """Every parameter's :meth:`Param.describe`, by name (``usvtool plugins``)."""
    return {k: p.describe() for k, p in params.items()}
