"""JIT configuration for every numba kernel in gsi (one place, one comment per flag).

Set ``GSI_NO_JIT=1`` to run the kernels as plain Python (debugging); ``NUMBA_NUM_THREADS``
sets the thread count of ``prange`` loops.

Compile time (the engine's budget is a minute, cold, for every contact model):

- **literals**: numba types a call argument that is a constant (``0``, or a counter that
  starts at ``0``) as ``Literal[int](0)`` while it infers types, and compiles the callee
  once for the literal and once more for ``int64``.  Counters passed to a compiled
  function start as ``np.int64(0)`` or ``uint(0)``, lane indices are always ``uint``.
- **inlining**: every compiled function is optimized again, by LLVM, in each library
  that calls it (numba links callees into the caller's module), so a deep chain of
  calls around the contact model costs its size once per level; numba's own IR
  inlining (``inline="always"``) re-types the callee at every call site, and is kept
  for the few helpers where it shapes vectorized loops.
"""
import hashlib
import os
import pathlib
import shutil
import time
import warnings

import numba
import numpy
from numba.core.errors import NumbaExperimentalFeatureWarning

# The contact model unrolls registries of compiled sub-models (gsi/dem/contact/model.py),
# which numba types as first-class functions and reports as experimental at every
# compile: the feature is exercised by the tests, and the warning is noise to a user.
warnings.filterwarnings("ignore", message="First-class function type",
                        category=NumbaExperimentalFeatureWarning)

def _kernel_digest():
    """Hash of the sources of every module of gsi that compiles kernels (those importing
    from ``gsi.jit``) and of this file."""
    here = pathlib.Path(__file__).parent
    h = hashlib.sha1()
    for f in sorted(here.rglob("*.py")):
        text = f.read_bytes()
        if f.name == "jit.py" or b"gsi.jit import" in text:
            h.update(f.relative_to(here).as_posix().encode())
            h.update(text)
    return h.hexdigest()[:12]


def _set_cache_dir():
    """Point numba's cache at a directory named by :func:`_kernel_digest`.

    numba keys a cached function on its own file only, while the code of the functions it
    calls in other files is compiled into it: after an edit of a contact law, the engine
    cached before would still run the old law.  A directory per version of the kernel
    sources makes any edit start a fresh cache (one cold compile, about a minute).  The
    base is ``$NUMBA_CACHE_DIR`` if set, else ``~/.cache/gsi/numba``, where caches unused
    for a week are removed (other checkouts of gsi may still use a younger one).
    """
    base = os.environ.get("NUMBA_CACHE_DIR")
    own = not base
    if own:
        base = os.path.join(os.path.expanduser("~"), ".cache", "gsi", "numba")
    digest = _kernel_digest()
    numba.config.CACHE_DIR = os.path.join(base, digest)
    if own and os.path.isdir(base):
        week_ago = time.time() - 7 * 86400
        for old in os.listdir(base):
            path = os.path.join(base, old)
            if old != digest and os.path.getmtime(path) < week_ago:
                shutil.rmtree(path, ignore_errors=True)
    os.makedirs(numba.config.CACHE_DIR, exist_ok=True)
    os.utime(numba.config.CACHE_DIR)


#: run kernels as plain Python when GSI_NO_JIT=1 (slow; for debugging with pdb/prints)
DISABLE_JIT = os.environ.get("GSI_NO_JIT", "0") == "1"
if not DISABLE_JIT:
    _set_cache_dir()

JIT_FLAGS = dict(
    cache=True,      # compiled kernels are reused by later runs (cache: _set_cache_dir)
    fastmath=False,  # keep IEEE semantics: validation tests compare to round-off
    error_model="numpy",  # division by zero gives inf/nan instead of raising (no branch)
)

#: the parallel transformations used: explicit ``prange`` loops only (numba's automatic
#: parallelization of array expressions is off: no kernel relies on it, and its passes
#: cost compile time)
PARALLEL_OPTIONS = dict(prange=True, comprehension=False, reduction=False,
                        inplace_binop=False, setitem=False, numpy=False, stencil=False,
                        fusion=False)


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
    # a fresh dict each time: numba's ParallelOptions consumes the one it is given
    return njit(*args, **dict(JIT_FLAGS, parallel=dict(PARALLEL_OPTIONS), **kwargs))


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


def _prefetch_intrinsic(write):
    """``prefetch(a, i)``: LLVM's ``llvm.prefetch`` of the first element of row ``i`` of
    array ``a`` (for reading, or with ``write`` for writing: the line arrives owned)."""
    from llvmlite import ir
    from numba import types
    from numba.core import cgutils
    from numba.extending import intrinsic

    @intrinsic
    def prefetch(typingctx, arr, idx):
        """A hint that row ``idx`` of ``arr`` is needed soon (no bounds test: a prefetch
        of an address outside the array is dropped by the CPU, never faults)."""
        if not isinstance(arr, types.Array) or not isinstance(idx, types.Integer):
            return None

        def codegen(context, builder, sig, args):
            aryty = sig.args[0]
            ary = context.make_array(aryty)(context, builder, args[0])
            i = context.cast(builder, args[1], sig.args[1], types.intp)
            zero = context.get_constant(types.intp, 0)
            ptr = cgutils.get_item_pointer2(context, builder, ary.data,
                                            cgutils.unpack_tuple(builder, ary.shape),
                                            cgutils.unpack_tuple(builder, ary.strides),
                                            aryty.layout, [i] + [zero] * (aryty.ndim - 1),
                                            wraparound=False)
            i8p = ir.IntType(8).as_pointer()
            i32 = ir.IntType(32)
            fn = cgutils.get_or_insert_function(
                builder.module, ir.FunctionType(ir.VoidType(), [i8p, i32, i32, i32]),
                "llvm.prefetch.p0i8")
            # (address, 0 read / 1 write, locality 3: keep in all levels, 1: data)
            builder.call(fn, [builder.bitcast(ptr, i8p), i32(int(write)), i32(3), i32(1)])
            return context.get_dummy_value()
        return types.void(arr, idx), codegen
    return prefetch


def _no_prefetch(arr, idx):
    """Without JIT a prefetch hint does nothing."""


#: ``prefetch(a, i)``, ``prefetch_w(a, i)``: ask the CPU to bring row ``i`` of ``a`` into
#: the cache ahead of a read (a write).  The engine's force pass uses them for the rows
#: a particle a few rows ahead will touch first (gsi/dem/engine.py, ``slab_task``): in a
#: bed far larger than the last-level cache these come from memory, in an order the
#: hardware prefetchers do not follow.
prefetch = _no_prefetch if DISABLE_JIT else _prefetch_intrinsic(False)
prefetch_w = _no_prefetch if DISABLE_JIT else _prefetch_intrinsic(True)
