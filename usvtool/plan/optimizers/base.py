"""The shared base of every optimizer.

An optimizer minimises a vectorised objective: ``objective(X)`` takes the whole population as an
``(n, d)`` array and returns the ``(n,)`` costs in one call. Subclasses implement :meth:`_run`
using the helpers here (bounds handling, the seeded generator, the evaluation budget and the
best-so-far history), never looping over individuals in Python.

A subclass declares its parameters in ``parameters`` (name -> :class:`usvtool.params.Param`:
the default, what it sets, a :class:`Range` where the algorithm's equations need one: a
probability in [0, 1], a divisor > 0); :meth:`Optimizer.check_params` refuses anything else in
one line naming ``--param NAME`` (:func:`usvtool.params.check`). The older ``defaults`` (name ->
value) and ``ranges`` (name -> :class:`Range`) are still read (:func:`usvtool.params.declared`).
"""

from __future__ import annotations

import time
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from usvtool.params import (
    NON_NEGATIVE,
    POSITIVE,
    PROBABILITY,
    Param,
    Range,
    View,
    check,
    declared,
    defaults,
    ranges,
)

__all__ = ["NON_NEGATIVE", "POSITIVE", "PROBABILITY", "Objective", "Optimizer", "OptimizerResult",
           "Param", "Range"]  # fmt: skip

Objective = Callable[[np.ndarray], np.ndarray]


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
    arguments the subclass declares in ``parameters`` (:meth:`declarations`), checked by
    :meth:`check_params`.
    """

    name: str = ""
    parameters: dict[str, Param] = {}
    #: The older attributes, read from :meth:`declarations` (name -> default, name -> Range).
    defaults = View(defaults)
    ranges = View(ranges)

    def __init__(self, pop: int = 50, iters: int = 300, seed=None, **params):
        if pop < 2:
            raise ValueError("pop must be >= 2")
        if iters < 1:
            raise ValueError("iters must be >= 1")
        self.params = check(self.declarations(), params, _where, self.name)
        self.pop = int(pop)
        self.iters = int(iters)
        self.rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)

    @classmethod
    def declarations(cls) -> dict[str, Param]:
        """Its parameters: ``parameters`` (and the older ``defaults`` and ``ranges``) of each
        class from :class:`Optimizer` down (:func:`usvtool.params.declared`)."""
        return declared(cls, ("defaults", "ranges", "parameters"))

    @classmethod
    def check_params(cls, params: Mapping) -> None:
        """Refuse a parameter the algorithm has not got or a value its declaration does not
        take (:func:`usvtool.params.check`), in one line naming ``--param NAME``.

        >>> from usvtool.plan.optimizers.boa import BOA
        >>> BOA.check_params({"p": 0.5})
        >>> BOA.check_params({"p": 1.5})
        Traceback (most recent call last):
        usvtool.errors.UsvError: --param p must be in [0, 1] for boa, not 1.5
        """
        check(cls.declarations(), params, _where, cls.name)

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


def _where(key: str) -> str:
    return f"--param {key}"
