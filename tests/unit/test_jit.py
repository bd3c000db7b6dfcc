"""gsi.jit: the prefetch hints compile to LLVM's prefetch and change no value."""
import numba
import numpy as np
import pytest

from gsi.jit import DISABLE_JIT, prefetch, prefetch_w, uint

pytestmark = pytest.mark.skipif(DISABLE_JIT, reason="the hints are no-ops without JIT")


@numba.njit(cache=False)
def _touch(x, r, h, i):
    prefetch(x, i)                       # 2-d row
    prefetch(r, uint(i) + uint(1))       # 1-d, unsigned index
    prefetch_w(h, i)                     # written row of a strided view
    prefetch(r, i + 10 ** 9)             # far outside the array: dropped, no fault
    return x[i, 0] + r[i] + h[i, 2]


def test_prefetch_hints_are_emitted_and_change_nothing():
    x = np.arange(30.0).reshape(10, 3)
    r = np.arange(10.0)
    h = np.arange(60.0).reshape(10, 6)[:, ::2]       # not contiguous (layout 'A')
    before = (x.copy(), r.copy(), h.copy())
    assert _touch(x, r, h, 4) == x[4, 0] + r[4] + h[4, 2]
    for a, b in zip((x, r, h), before):
        np.testing.assert_array_equal(a, b)
    ir = next(iter(_touch.inspect_llvm().values()))
    calls = [ln for ln in ir.splitlines() if "call void @llvm.prefetch" in ln]
    assert len(calls) == 4
    assert sum(", i32 1, i32 3, i32 1)" in ln for ln in calls) == 1   # one for writing
