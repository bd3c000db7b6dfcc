"""JIT configuration for every numba kernel in gsi (one place, one comment per flag).

Set ``GSI_NO_JIT=1`` to run the kernels as plain Python (debugging); ``NUMBA_NUM_THREADS``
sets the thread count of ``prange`` loops.
"""
import os

import numba

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
