"""The benchmark functions F1-F10 of the IWSO paper's Table 1 (the classic CEC-2005 / Yao et al.
1999 unimodal F1-F7 and multimodal F8-F10 set), vectorised: ``X`` is ``(n, d)``, costs ``(n,)``.

Every function is defined in any dimension (the paper uses 30) on the box ``[-bound, bound]^d``
and knows its minimum ``optimum(d)`` and the coordinate ``x_star`` of the minimiser (the same in
every dimension). F7's noise is drawn from a generator given to :meth:`objective`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from usvtool.errors import UsvError

SCHWEFEL_X = 420.968746  # minimiser of -x sin(sqrt|x|) on [-500, 500]
SCHWEFEL_MIN = -418.982887272433799  # its value, per dimension


def sphere(X: np.ndarray) -> np.ndarray:
    return np.sum(X * X, axis=1)


def schwefel_222(X: np.ndarray) -> np.ndarray:
    A = np.abs(X)
    return np.sum(A, axis=1) + np.prod(A, axis=1)


def schwefel_12(X: np.ndarray) -> np.ndarray:
    return np.sum(np.cumsum(X, axis=1) ** 2, axis=1)


def schwefel_221(X: np.ndarray) -> np.ndarray:
    return np.max(np.abs(X), axis=1)


def rosenbrock(X: np.ndarray) -> np.ndarray:
    a, b = X[:, :-1], X[:, 1:]
    return np.sum(100.0 * (b - a * a) ** 2 + (a - 1.0) ** 2, axis=1)


def step(X: np.ndarray) -> np.ndarray:
    return np.sum(np.floor(X + 0.5) ** 2, axis=1)


def quartic(X: np.ndarray) -> np.ndarray:
    """Without the noise: ``sum i x_i^4``."""
    i = np.arange(1, X.shape[1] + 1)
    return np.sum(i * X**4, axis=1)


def schwefel_226(X: np.ndarray) -> np.ndarray:
    return np.sum(-X * np.sin(np.sqrt(np.abs(X))), axis=1)


def rastrigin(X: np.ndarray) -> np.ndarray:
    return np.sum(X * X - 10.0 * np.cos(2.0 * np.pi * X) + 10.0, axis=1)


def ackley(X: np.ndarray) -> np.ndarray:
    d = X.shape[1]
    return (
        -20.0 * np.exp(-0.2 * np.sqrt(np.sum(X * X, axis=1) / d))
        - np.exp(np.sum(np.cos(2.0 * np.pi * X), axis=1) / d)
        + 20.0
        + np.e
    )


@dataclass(frozen=True)
class BenchmarkFunction:
    name: str
    title: str
    bound: float
    func: Callable[[np.ndarray], np.ndarray]
    x_star: float = 0.0
    optimum_per_dim: float = 0.0  # minimum = optimum_per_dim * d (F8), else 0
    noisy: bool = False

    def bounds(self, dim: int) -> tuple[np.ndarray, np.ndarray]:
        return np.full(dim, -self.bound), np.full(dim, self.bound)

    def optimum(self, dim: int) -> float:
        return self.optimum_per_dim * dim

    def objective(self, rng: np.random.Generator | None = None) -> Callable:
        """The vectorised cost; F7 adds ``U[0, 1)`` noise from ``rng`` (default seed 0)."""
        if not self.noisy:
            return self.func
        noise = rng if rng is not None else np.random.default_rng(0)
        return lambda X: self.func(X) + noise.random(X.shape[0])


FUNCTIONS: dict[str, BenchmarkFunction] = {
    f.name: f
    for f in (
        BenchmarkFunction("F1", "Sphere", 100.0, sphere),
        BenchmarkFunction("F2", "Schwefel 2.22", 10.0, schwefel_222),
        BenchmarkFunction("F3", "Schwefel 1.2", 100.0, schwefel_12),
        BenchmarkFunction("F4", "Schwefel 2.21", 100.0, schwefel_221),
        BenchmarkFunction("F5", "Rosenbrock", 30.0, rosenbrock, x_star=1.0),
        BenchmarkFunction("F6", "Step", 100.0, step),
        BenchmarkFunction("F7", "Quartic with noise", 1.28, quartic, noisy=True),
        BenchmarkFunction("F8", "Schwefel 2.26", 500.0, schwefel_226, SCHWEFEL_X, SCHWEFEL_MIN),
        BenchmarkFunction("F9", "Rastrigin", 5.12, rastrigin),
        BenchmarkFunction("F10", "Ackley", 32.0, ackley),
    )
}


def get_function(name: str) -> BenchmarkFunction:
    """The function called ``name`` (``F1``..``F10``, any case); :class:`UsvError` otherwise."""
    try:
        return FUNCTIONS[name.upper()]
    except KeyError:
        raise UsvError(f"unknown function {name!r} (known: {', '.join(FUNCTIONS)})") from None
