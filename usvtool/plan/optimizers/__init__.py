"""The population-based optimizers, by name."""

from __future__ import annotations

from usvtool.errors import UsvError
from usvtool.plan.optimizers.base import Objective, Optimizer, Result
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

OPTIMIZERS: dict[str, type[Optimizer]] = {
    cls.name: cls for cls in (WSO, IWSO, SSA, SSARedraw, ISSA, PSO, PSOISSA, GWO, WOA, MRFO, BOA)
}


def make_optimizer(name: str, pop: int = 50, iters: int = 300, seed=None, **params) -> Optimizer:
    """The optimizer registered as ``name``; :class:`UsvError` for an unknown name."""
    try:
        cls = OPTIMIZERS[name]
    except KeyError:
        known = ", ".join(OPTIMIZERS)
        raise UsvError(f"unknown algorithm {name!r} (known: {known})") from None
    return cls(pop=pop, iters=iters, seed=seed, **params)


__all__ = ["OPTIMIZERS", "Objective", "Optimizer", "Result", "make_optimizer"]
