"""The population-based optimizers, by name: :data:`OPTIMIZERS`, in the order every listing
shows them (the papers' algorithms, each variant after the algorithm it varies).

Adding one is its module (an :class:`Optimizer` subclass with ``name``, ``parameters`` and
``_run``) and its entry in the tuple below; :func:`register` adds one at run time, and an
installed distribution adds one under the entry-point group ``usvtool.planners``
(:class:`usvtool.registry.Registry`; docs/extending.md).
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
from usvtool.registry import Registry


def no_suffix(cls: type) -> str | None:
    """Why ``cls``'s name cannot be an ``--algo`` name (it has a ``+``), or None."""
    return "has a '+' (the planners' variant suffix)" if "+" in cls.name else None


#: Every optimizer: the built-ins below, then the ``usvtool.planners`` plugins of its base (the
#: group it shares with the exact planners, usvtool.plan.planners.EXACT; docs/extending.md).
OPTIMIZERS = Registry("optimizer", Optimizer, "usvtool.planners", no_suffix)
#: Add an optimizer (a class decorator too); ``ValueError`` for a taken or bad name.
register = OPTIMIZERS.register
#: Remove the optimizer registered under a name (``KeyError`` when there is none).
unregister = OPTIMIZERS.unregister

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
