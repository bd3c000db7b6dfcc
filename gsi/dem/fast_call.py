"""A compiled kernel called through its overload's entry point when the argument types
are known (docs/design.md, "The DEM engine and its contact model").

numba's dispatcher caches the type of each argument by a fingerprint, but numba 0.56
loses the first 40 bytes of a fingerprint longer than its 40-byte buffer: the engine's
state bundles (:mod:`gsi.dem.state`, 130-420 bytes each) then miss that cache at random
(1-11 % of the calls measured), and each miss types the bundles in Python, ~1 ms per
call.  :class:`FastCall` keys the compiled overload on a fingerprint it takes whole.  A
plain module (no kernels of its own): an edit here does not invalidate the compiled
engine.
"""
import numba
import numpy as np

try:                      # numba's C type fingerprint; absent: no fast path
    from numba._dispatcher import compute_fingerprint
except ImportError:       # pragma: no cover
    compute_fingerprint = None


#: a tuple whose type fingerprint (50 bytes) is longer than numba's static buffer (40)
_PAD = tuple(np.zeros(1) for _ in range(6))
_PAD_END = 1 + (len(compute_fingerprint(_PAD)) if compute_fingerprint is not None else 0)


class FastCall:
    """A compiled kernel called through the entry point of its compiled overload when the
    arguments have the types of an earlier call (module docstring).

    The guard is numba's own type fingerprint of the whole argument tuple (one C call:
    dtype, ndim, layout and writeability of every array, field names of every named
    tuple, the kind of every scalar), with the classes of the arguments; an unknown
    fingerprint, or arguments numba cannot fingerprint, go through the dispatcher, and
    the overload it ran is remembered when its signature is exactly the arguments' types
    (a conversion to another overload is never cached).  Plain Python kernels
    (``GSI_NO_JIT``) are called as they are.

    numba 0.56's fingerprint loses the first 40 bytes it wrote when it outgrows its
    static buffer (``string_writer_ensure`` mallocs without copying), so the arguments
    are fingerprinted behind :data:`_PAD` (a 50-byte fingerprint) and only the bytes
    after it form the key (a fixed numba gives the same key)."""

    def __init__(self, kernel):
        self.kernel = kernel
        self.entries = {}
        self.jitted = hasattr(kernel, "overloads") and compute_fingerprint is not None

    def __call__(self, *args):
        if not self.jitted:
            return self.kernel(*args)
        try:
            key = (compute_fingerprint((_PAD,) + args)[_PAD_END:], tuple(map(type, args)))
        except NotImplementedError:
            return self.kernel(*args)
        entry = self.entries.get(key)
        if entry is not None:
            return entry(*args)
        result = self.kernel(*args)
        sig = tuple(numba.typeof(a) for a in args)
        cres = self.kernel.overloads.get(sig)
        if cres is not None:
            self.entries[key] = cres.entry_point
        return result
