"""numba kernels whose one signature is compiled, or loaded from numba's cache, at their first
call rather than at import (:func:`declared`), and loaded on purpose before a timing
(:func:`load`).

A module of kernels declared so costs its importer nothing until a kernel runs, and a process
loads the kernels it calls and no others: loading every signature at import cost some 0.55 s
of CPU a simulation process (:mod:`usvtool.sim.rollout_kernels`' 37 kernels) and 0.18 s a
planning one (:mod:`usvtool.collision_kernels`' 4, of which a plan calls 1 or 2).
"""

from __future__ import annotations

from types import ModuleType

from numba import njit
from numba.core.dispatcher import Dispatcher


def declared(sig, **options):
    """``njit(sig, **options)``, the signature compiled (or loaded from numba's cache) at the
    kernel's first call, from Python or while a calling kernel is typed, rather than at the
    decoration: then, as ``njit`` with a signature does, compilation is disabled, so that every
    call uses that one specialisation (converting the arguments as numba does: an ``int`` for a
    float), the same machine code as with the signature given at the decoration. A kernel
    inlined (``inline="always"``) is typed in its callers and never compiled by itself unless
    called from Python."""

    def decorate(func):
        dispatcher = njit(**options)(func)

        def compile_declared(_types):  # numba's compile for a call's types: the signature's
            del dispatcher.compile  # the method again
            entry = dispatcher.compile(sig)
            dispatcher.disable_compile()
            return entry

        dispatcher.compile = compile_declared
        return dispatcher

    return decorate


def load(module: ModuleType, *names: str) -> None:
    """Compile the named kernels of ``module``, or load them from numba's cache, now unless
    done: when a controller, a tracker or a collision checker is made, so that the kernels it
    calls are not loaded inside the first step's or the planning's timing."""
    for name in names:
        kernel = getattr(module, name)  # a module's ufuncs: made
        if isinstance(kernel, Dispatcher) and not kernel.signatures:
            kernel.compile(None)  # declared's: the signature


def loaded(module: ModuleType) -> dict[str, int]:
    """The kernels of ``module`` with a specialisation loaded, and how many (one each)."""
    return {name: len(k.signatures) for name, k in vars(module).items()
            if isinstance(k, Dispatcher) and k.signatures}  # fmt: skip
