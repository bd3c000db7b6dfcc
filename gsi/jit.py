"""JIT configuration for every numba kernel in gsi (one place, one comment per flag).

Set ``GSI_NO_JIT=1`` to run the kernels as plain Python (debugging); ``NUMBA_NUM_THREADS``
sets the thread count of ``prange`` loops.
"""
import os

import numba
import numpy

#: run kernels as plain Python when GSI_NO_JIT=1 (slow; for debugging with pdb/prints)
DISABLE_JIT = os.environ.get("GSI_NO_JIT", "0") == "1"

JIT_FLAGS = dict(
    cache=True,      # compiled kernels are written to __pycache__ and reused by later runs
    fastmath=False,  # keep IEEE semantics: validation tests compare to round-off
    error_model="numpy",  # division by zero gives inf/nan instead of raising (no branch)
)

PARALLEL_FLAGS = dict(JIT_FLAGS, parallel=True)  # kernels with a prange loop over particles


def njit(*args, **kwargs):
    """``numba.njit`` with gsi's flags (serial kernels)."""
    if DISABLE_JIT:
        return args[0] if args and callable(args[0]) else (lambda f: f)
    flags = dict(JIT_FLAGS, **kwargs)
    if args and callable(args[0]):
        return numba.njit(**flags)(args[0])
    return numba.njit(**flags)


def pjit(*args, **kwargs):
    """``numba.njit(parallel=True)`` with gsi's flags (kernels with ``prange``)."""
    return njit(*args, **dict(PARALLEL_FLAGS, **kwargs))


prange = range if DISABLE_JIT else numba.prange


def _trailing_zeros_py(x):
    """Index of the lowest set bit of an integer > 0 (plain Python)."""
    x = int(x)
    return (x & -x).bit_length() - 1


if DISABLE_JIT:
    trailing_zeros = _trailing_zeros_py
else:
    # LLVM's cttz: the count of trailing zero bits (one instruction on x86-64)
    from numba.cpython.unsafe.numbers import trailing_zeros  # noqa: E402,F401


def _sqrt_intrinsic():
    """``sqrt`` as LLVM's ``llvm.sqrt.f64`` (see :data:`sqrt`)."""
    from llvmlite import ir
    from numba import types
    from numba.extending import intrinsic

    @intrinsic
    def sqrt(typingctx, x):
        """Square root of a float64 (LLVM's llvm.sqrt.f64)."""
        if not isinstance(x, types.Float):
            return None

        def codegen(context, builder, sig, args):
            val = context.cast(builder, args[0], sig.args[0], types.float64)
            fn = builder.module.declare_intrinsic("llvm.sqrt", [ir.DoubleType()])
            return builder.call(fn, [val])
        return types.float64(x), codegen
    return sqrt


#: the correctly rounded square root of a float64, as ``math.sqrt``, but compiled to
#: LLVM's ``llvm.sqrt`` intrinsic: numba compiles ``math.sqrt`` to a call of libm's
#: ``sqrt`` declared as reading memory (errno), which LLVM need not widen into a vector
#: root; the intrinsic it widens (the engine's loop of laws, gsi/dem/engine.py).  The
#: same bits (IEEE-754 square root; NaN for a negative argument, without errno).
if DISABLE_JIT:
    from math import sqrt  # noqa: E402,F401
else:
    sqrt = _sqrt_intrinsic()

#: unsigned index of the kernels: numba's uint64 (an index numba need not test for
#: wrap-around, see gsi/dem/engine.py); plain int without JIT, where numpy would turn
#: ``uint64 + int`` into a float
uint = int if DISABLE_JIT else numpy.uint64
