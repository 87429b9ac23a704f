"""Borrowed views of a numba kernel's array arguments, for its inner loops (:func:`borrowed`).

numba counts the references to every array a compiled function binds to a variable, with
atomic increments and decrements of the array's "meminfo", and its pruning leaves many of them
in loops: each call of an inlined helper binds its array parameters again, and each call of a
compiled function binds its arguments on entry. In the collision check those counts took a
third of the time (docs/planning.md). A view made by :func:`numba.carray` from the data pointer
has no meminfo, and numba's increments and decrements of it return at once: a kernel that
hands its helpers borrowed views of its arguments pays nothing for them.

Written by hand (a numba intrinsic of a few lines, as :func:`usvtool.plan.cost_kernels.fma`)
because numba offers no borrowed array. A view must not outlive what it views: borrow only a
kernel's arguments (their caller holds them until the kernel returns), never an array the
kernel allocates, which numba frees after its last use.
"""

from __future__ import annotations

from numba import carray, njit, types
from numba.core.errors import TypingError
from numba.extending import intrinsic


@intrinsic
def _data(typingctx, array):
    """The data pointer of a C-contiguous ``array``."""
    if not isinstance(array, types.Array) or array.layout != "C":
        raise TypingError(f"borrowed: a C-contiguous array, not {array}")
    sig = types.CPointer(array.dtype)(array)

    def codegen(context, builder, signature, args):
        return context.make_array(signature.args[0])(context, builder, value=args[0]).data

    return sig, codegen


@njit(inline="always")
def borrowed(array):
    """A view of the C-contiguous ``array`` (same data, shape and dtype, writable) that numba
    does not reference-count; valid while ``array`` is (see the module docstring)."""
    return carray(_data(array), array.shape)
