"""FastCall (gsi/dem/fast_call.py): a compiled kernel called through its overload's entry
point when the argument types are those of an earlier call, through numba's dispatcher
otherwise; the same results either way."""
from collections import namedtuple

import numba
import numpy as np
import pytest

from gsi.dem.fast_call import FastCall

#: a bundle of arrays (its type fingerprint, ~90 bytes, is longer than numba's 40-byte buffer)
Big = namedtuple("Big", [f"a{k}" for k in range(8)])


@numba.njit
def _kernel(n, scale, B, out):
    out[0] = (B.a0[0] + B.a3[0] + B.a5[0] + B.a7[0]) * scale + n
    return n + 1


def _bundle(dtype=np.float64):
    return Big(*[np.full(3, k, dtype) for k in range(8)])


def test_same_types_reuse_the_overload_and_give_the_dispatchers_result():
    call = FastCall(_kernel)
    out = np.zeros(1)
    assert call(2, 0.5, _bundle(), out) == 3
    assert out[0] == 0.5 * 15 + 2
    assert len(call.entries) == 1
    for n in range(5):             # new arrays, same types: the entry is reused
        out2 = np.zeros(1)
        assert call(n, 2.0, _bundle(), out2) == n + 1
        ref = np.zeros(1)
        _kernel(n, 2.0, _bundle(), ref)           # the dispatcher
        assert out2[0] == ref[0] == 30.0 + n
    assert len(call.entries) == 1


@pytest.mark.parametrize("change", ["dtype", "readonly", "layout", "scalar"])
def test_other_argument_types_go_through_the_dispatcher(change):
    call = FastCall(_kernel)
    call(1, 1.0, _bundle(), np.zeros(1))
    B = _bundle()
    out = np.zeros(1)
    scale = 1.0
    if change == "dtype":
        B = _bundle(np.float32)
    elif change == "readonly":
        B.a3.flags.writeable = False
    elif change == "layout":
        B = B._replace(a5=np.full(6, 5.0)[::2])       # a strided view: layout A
    else:
        scale = np.float32(1.0)
    n_before = len(_kernel.overloads)
    assert call(1, scale, B, out) == 2
    assert out[0] == 15 + 1
    assert len(_kernel.overloads) == n_before + 1        # the dispatcher compiled another
    assert len(call.entries) == 2                        # and the fast path keeps both


def test_a_plain_function_is_called_as_it_is():
    call = FastCall(lambda a, b: a + b)
    assert call(1, 2) == 3 and not call.entries


def test_the_engine_reuses_one_entry_over_one_step_calls():
    """A small case stepped one step per call: one entry for the step loop, however the
    heap lies (numba's own fingerprints of the bundles miss at random, see the module)."""
    from gsi.dem import Simulation, Material, engine
    sim = Simulation({"g": Material(E=1e7, nu=0.3, rho=2500.0, e=0.5, mu=0.5)},
                     dt=1e-6, skin=2e-4, domain=((0, 0, 0), (0.01, 0.01, 0.02)))
    sim.add_particles(np.array([[0.005, 0.005, 0.00099], [0.005, 0.005, 0.00297]]), 0.001,
                      material="g")
    sim.add_plane((0, 0, 0), (0, 0, 1), material="g")
    sim.step(2)
    n = len(engine.fast_advance.entries)
    assert n >= 1
    for _ in range(50):
        sim.step(1)
    assert len(engine.fast_advance.entries) == n
