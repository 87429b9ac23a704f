"""The population-based optimizers, by name: :data:`OPTIMIZERS`, in the order every listing
shows them (the papers' algorithms, each variant after the algorithm it varies).

Adding one is its module (an :class:`Optimizer` subclass with ``name``, ``defaults``, ``ranges``
and ``_run``) and its entry in the tuple below; :func:`register` adds one at run time
(docs/extending.md).
"""

from __future__ import annotations

from usvtool.errors import UsvError
from usvtool.plan.optimizers.base import Objective, Optimizer, OptimizerResult, Range
from usvtool.plan.optimizers.boa import BOA
from usvtool.plan.optimizers.gwo import GWO
from usvtool.plan.optimizers.issa import ISSA
from usvtool.plan.optimizers.iwso import IWSO
from usvtool.plan.optimizers.mrfo import MRFO
from usvtool.plan.optimizers.pso import PSO, PSOISSA
from usvtool.plan.optimizers.ssa import SSA
from usvtool.plan.optimizers.ssa_redraw import SSARedraw
from usvtool.plan.optimizers.woa import WOA
from usvtool.plan.optimizers.wso import WSO

OPTIMIZERS: dict[str, type[Optimizer]] = {}


def register(cls: type[Optimizer]) -> type[Optimizer]:
    """Add ``cls`` to :data:`OPTIMIZERS` under its ``name`` (which must be new, and free of
    ``+``, the planners' variant suffixes); returns ``cls``, so it also serves as a class
    decorator."""
    if not cls.name or "+" in cls.name:
        raise ValueError(f"optimizer name {cls.name!r}: empty or with a '+'")
    if cls.name in OPTIMIZERS:
        raise ValueError(f"optimizer {cls.name!r} is already registered")
    OPTIMIZERS[cls.name] = cls
    return cls


def unregister(name: str) -> None:
    """Remove the optimizer registered as ``name`` (KeyError when there is none)."""
    del OPTIMIZERS[name]


for _cls in (WSO, IWSO, SSA, SSARedraw, ISSA, PSO, PSOISSA, GWO, WOA, MRFO, BOA):
    register(_cls)


def make_optimizer(name: str, pop: int = 50, iters: int = 300, seed=None, **params) -> Optimizer:
    """The optimizer registered as ``name``; :class:`UsvError` for an unknown name."""
    try:
        cls = OPTIMIZERS[name]
    except KeyError:
        known = ", ".join(OPTIMIZERS)
        raise UsvError(f"unknown algorithm {name!r} (known: {known})") from None
    return cls(pop=pop, iters=iters, seed=seed, **params)


__all__ = ["OPTIMIZERS", "Objective", "Optimizer", "OptimizerResult", "Range", "make_optimizer",
           "register", "unregister"]  # fmt: skip
