"""The shared base of every optimizer.

An optimizer minimises a vectorised objective: ``objective(X)`` takes the whole population as an
``(n, d)`` array and returns the ``(n,)`` costs in one call. Subclasses implement :meth:`_run`
using the helpers here (bounds handling, the seeded generator, the evaluation budget and the
best-so-far history), never looping over individuals in Python.

A subclass declares its parameters beside each other: ``defaults`` (name -> value; the value's
type is the parameter's) and ``ranges`` (name -> :class:`Range`, where the algorithm's equations
need one: a probability in [0, 1], a divisor > 0). :meth:`Optimizer.check_params` refuses
anything else in one line naming ``--param NAME``.
"""

from __future__ import annotations

import math
import time
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from usvtool.errors import UsvError
from usvtool.yamlfile import show

Objective = Callable[[np.ndarray], np.ndarray]


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


@dataclass
class OptimizerResult:
    """Outcome of one optimisation run."""

    x: np.ndarray  # best position found, shape (d,)
    f: float  # its cost
    history: np.ndarray  # best-so-far cost after each iteration, shape (iters,)
    evaluations: int  # objective evaluations of single individuals
    seconds: float  # wall-clock time of the run
    params: dict = field(default_factory=dict)  # the parameters actually used


class Optimizer(ABC):
    """Population-based minimiser over a box ``lower <= x <= upper``.

    Parameters common to all: ``pop`` (population size, >= 2), ``iters`` (iterations, >= 1),
    ``seed`` (an int or a ``numpy.random.Generator``). Algorithm parameters are keyword
    arguments listed in the subclass's ``defaults``, checked by :meth:`check_params`.
    """

    name: str = ""
    defaults: dict = {}
    ranges: dict[str, Range] = {}

    def __init__(self, pop: int = 50, iters: int = 300, seed=None, **params):
        if pop < 2:
            raise ValueError("pop must be >= 2")
        if iters < 1:
            raise ValueError("iters must be >= 1")
        self.check_params(params)
        self.pop = int(pop)
        self.iters = int(iters)
        self.rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        self.params = {**self.defaults, **params}

    @classmethod
    def check_params(cls, params: Mapping) -> None:
        """Refuse a parameter the algorithm has not got, a value not of its default's type (a
        number: a finite int or float; true/false: a bool; an int: an integer; a string: a
        string) or outside its :data:`ranges` entry, in one line naming ``--param NAME``.

        >>> from usvtool.plan.optimizers.boa import BOA
        >>> BOA.check_params({"p": 0.5})
        >>> BOA.check_params({"p": 1.5})
        Traceback (most recent call last):
        usvtool.errors.UsvError: --param p must be in [0, 1] for boa, not 1.5
        """
        for key, value in params.items():
            if key not in cls.defaults:
                known = ", ".join(cls.defaults) or "none"
                raise UsvError(f"--param {key} is not a parameter of {cls.name} (known: {known})")
            what = _kind_error(cls.defaults[key], value)
            if what:
                raise UsvError(f"--param {key} must be {what}, not {show(value)}")
            limits = cls.ranges.get(key)
            if limits is not None and value not in limits:
                raise UsvError(f"--param {key} must be {limits} for {cls.name}, not {show(value)}")

    def minimize(self, objective: Objective, lower, upper) -> OptimizerResult:
        """Minimise ``objective`` over the box; ``lower``/``upper`` are scalars or (d,) arrays."""
        lower = np.atleast_1d(np.asarray(lower, float))
        upper = np.atleast_1d(np.asarray(upper, float))
        lower, upper = np.broadcast_arrays(lower, upper)
        self.lower, self.upper = lower.copy(), upper.copy()
        self.dim = lower.size
        self._objective = objective
        self.evaluations = 0
        self.best_x = None
        self.best_f = np.inf
        self.history = np.empty(self.iters)
        t0 = time.perf_counter()
        self._run()
        return OptimizerResult(
            x=self.best_x.copy(),
            f=float(self.best_f),
            history=self.history,
            evaluations=self.evaluations,
            seconds=time.perf_counter() - t0,
            params=dict(self.params, pop=self.pop, iters=self.iters),
        )

    # -- helpers for subclasses -------------------------------------------------------------

    def evaluate(self, X: np.ndarray) -> np.ndarray:
        """Evaluate a population (one vectorised call) and update the best-so-far."""
        f = np.asarray(self._objective(X), float)
        self.evaluations += X.shape[0]
        i = int(np.argmin(f))
        if f[i] < self.best_f:
            self.best_f = float(f[i])
            self.best_x = X[i].copy()
        return f

    def clip(self, X: np.ndarray) -> np.ndarray:
        """Bring positions back into the box (the usual bounds handling of the papers)."""
        return np.clip(X, self.lower, self.upper)

    def uniform(self, n: int | None = None) -> np.ndarray:
        """A uniformly random population of ``n`` (default ``pop``) positions in the box."""
        n = self.pop if n is None else n
        return self.lower + self.rng.random((n, self.dim)) * (self.upper - self.lower)

    def record(self, iteration: int) -> None:
        """Store the best-so-far cost after ``iteration`` (0-based)."""
        self.history[iteration] = self.best_f

    @abstractmethod
    def _run(self) -> None:
        """Run ``self.iters`` iterations, calling :meth:`evaluate` and :meth:`record`."""


def _kind_error(default, value) -> str | None:
    """What ``value`` must be to stand for ``default`` (its type), or None when it is."""
    number = isinstance(value, int | float) and not isinstance(value, bool)
    if isinstance(default, bool):
        return None if isinstance(value, bool) else "true or false"
    if isinstance(default, int):
        return None if number and isinstance(value, int) else "an integer"
    if isinstance(default, float):
        return None if number and math.isfinite(value) else "a finite number"
    if isinstance(default, str):
        return None if isinstance(value, str) else "a string"
    return None
