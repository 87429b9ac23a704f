"""usvtool.kernel_views: a borrowed view is the array's data (read and written through), of its
shape and dtype, and has no meminfo, so numba counts no reference to it; a non-contiguous array
is refused when the kernel is typed."""

import numpy as np
import pytest
from numba import njit, types
from numba.core.errors import TypingError
from numba.extending import intrinsic

from usvtool.kernel_views import borrowed


@intrinsic
def _meminfo(typingctx, array):
    """The address of ``array``'s meminfo (0: none, nothing to count)."""
    sig = types.intp(array)

    def codegen(context, builder, signature, args):
        ary = context.make_array(signature.args[0])(context, builder, value=args[0])
        return builder.ptrtoint(ary.meminfo, context.get_value_type(types.intp))

    return sig, codegen


@njit
def _meminfos(a):
    return _meminfo(a), _meminfo(borrowed(a))


@njit
def _doubled_through_view(a):
    view = borrowed(a)
    total = 0.0
    for i in range(view.shape[0]):
        for j in range(view.shape[1]):
            total += view[i, j]
            view[i, j] *= 2.0
    return total, view.shape[0], view.shape[1]


@njit
def _flags(mask, counts):
    m, c = borrowed(mask), borrowed(counts)
    n = 0
    for i in range(m.size):
        n += c[i] if m[i] else 0
    return n


def test_a_borrowed_view_has_no_meminfo_and_its_array_has_one():
    owner, view = _meminfos(np.arange(5.0))
    assert owner != 0 and view == 0


def test_a_view_reads_and_writes_the_arrays_data_in_its_shape():
    a = np.arange(12.0).reshape(3, 4)
    total, rows, cols = _doubled_through_view(a)
    assert (total, rows, cols) == (66.0, 3, 4)
    np.testing.assert_array_equal(a, 2 * np.arange(12.0).reshape(3, 4))


def test_views_of_bool_and_int32_arrays_keep_their_dtype():
    mask = np.array([True, False, True, True])
    counts = np.array([5, 7, 11, 13], np.int32)
    assert _flags(mask, counts) == 5 + 11 + 13


def test_a_non_contiguous_array_is_refused():
    with pytest.raises(TypingError, match="C-contiguous"):
        _meminfos(np.arange(10.0)[::2])
