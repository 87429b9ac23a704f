"""The shared base of every optimizer.

An optimizer minimises a vectorised objective: ``objective(X)`` takes the whole population as an
``(n, d)`` array and returns the ``(n,)`` costs in one call. Subclasses implement :meth:`_run`
using the helpers here (bounds handling, the seeded generator, the evaluation budget and the
best-so-far history), never looping over individuals in Python.
"""

from __future__ import annotations

import time
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

Objective = Callable[[np.ndarray], np.ndarray]


@dataclass
class Result:
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
    arguments listed in the subclass's ``defaults``.
    """

    name: str = ""
    defaults: dict = {}

    def __init__(self, pop: int = 50, iters: int = 300, seed=None, **params):
        if pop < 2:
            raise ValueError("pop must be >= 2")
        if iters < 1:
            raise ValueError("iters must be >= 1")
        unknown = set(params) - set(self.defaults)
        if unknown:
            raise ValueError(f"{self.name}: unknown parameter(s) {sorted(unknown)}")
        self.pop = int(pop)
        self.iters = int(iters)
        self.rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        self.params = {**self.defaults, **params}

    def minimize(self, objective: Objective, lower, upper) -> Result:
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
        return Result(
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
