"""The contact model: sub-models called by name, the same for pairs, planes and triangles.

As LAMMPS' ``GranularModel`` is shared by ``pair granular`` and ``fix wall/gran``, one
contact model serves every kind of contact in gsi: the geometry code of a sphere pair, a
plane or a mesh triangle writes a contact's geometry into a lane of the buffer
(:mod:`gsi.dem.contact.lanes`, computed once per contact), then :func:`evaluate` runs
the sub-models in order over the lanes:

1. **normal** (elastic + damping): ``F_n``, and the tangential coefficients k_t, gamma_t
   -- ``hertz`` (Hertz with the LIGGGHTS damping), ``linear`` (spring-dashpot);
2. **tangential**: the total force with friction -- ``history`` (spring with Coulomb cap);
3. **rolling**: a torque -- ``none``, ``cdt`` (constant directional torque);
4. **heat**: the conducted heat rate -- ``none``, ``area``, ``radius``, ``constant``,
   ``pipe`` (:mod:`gsi.dem.heat`).

A normal or tangential sub-model is a pair ``(params(tab, row), lane)``: the law's
constants of a pair-table row, read once per run of lanes, and the law of one lane,
inlined into one loop with its partner (:func:`force_stage`: the normal law hands F_n,
k_t and gamma_t to the tangential one in registers, and the loop vectorizes).  A rolling
or heat sub-model is one compiled lane loop ``f(l0, l1, B, tab, row, dt)`` (they are
optional, and read F_n or a^2 from the buffer).  A new sub-model is one file and one line
in its registry.  The engine is compiled once for all of them: the model is a small
integer array (:func:`model_ids`), and :func:`evaluate` calls the chosen code of each
stage (``literal_unroll`` over the registry, a direct call per batch, no code
generation and no function pointers).  Damping is part of the normal sub-model, as in
LIGGGHTS' ``hertz``/``hooke`` models, because each law's damping coefficient is tied to
its own stiffness.
"""
import numpy as np
from numba import literal_unroll
from numba.extending import overload

from gsi.jit import njit, uint
from gsi.errors import GsiInputError
from gsi.dem import heat
from gsi.dem.contact import hertz, linear, tangential, rolling

#: normal sub-models (elastic + damping): (params, lane) -> FN, and k_t, gamma_t
NORMAL = {"hertz": (hertz.params, hertz.hertz), "linear": (linear.params, linear.linear)}
#: tangential sub-models: (params, lane) -> FX..FZ and the spring
TANGENTIAL = {"history": (tangential.params, tangential.history)}
#: rolling sub-models (lane loops): MX..MZ
ROLLING = {"none": rolling.none, "cdt": rolling.cdt}
#: heat sub-models (lane loops): Q
HEAT = {"none": heat.none_lanes, "area": heat.area_lanes, "radius": heat.radius_lanes,
        "constant": heat.constant_lanes, "pipe": heat.pipe_lanes}

# "none" is entry 0 of ROLLING and HEAT: evaluate() skips it (a buffer starts with zeros)
assert list(ROLLING)[0] == "none" and list(HEAT)[0] == "none"

_NORMAL = tuple(NORMAL.values())
_TANGENTIAL = tuple(TANGENTIAL.values())
_ROLLING = tuple(ROLLING.values())
_HEAT = tuple(HEAT.values())

#: entries of the model array (:func:`model_ids`)
M_NORMAL, M_TANGENTIAL, M_ROLLING, M_HEAT, M_LOG = range(5)


def model_ids(normal="hertz", tangential="history", rolling="none", heat="none", log=False):
    """The model array the engine takes: the index of each sub-model in its registry, and
    the contact-log switch.  ``rolling`` also takes True/False (cdt/none), ``heat`` None."""
    rolling = {True: "cdt", False: "none", None: "none"}.get(rolling, rolling)
    heat_name = "none" if heat is None else heat
    ids = []
    for key, name, reg in (("contact", normal, NORMAL), ("tangential", tangential, TANGENTIAL),
                           ("rolling", rolling, ROLLING), ("heat", heat_name, HEAT)):
        if name not in reg:
            raise GsiInputError(f"{key} = {name!r}: must be one of {sorted(reg)}")
        ids.append(list(reg).index(name))
    return np.array(ids + [int(bool(log))], np.int64)


# One function per stage, each unrolling its registry (a global tuple: passed as an
# argument, the tuple of functions would be a dynamic global that numba cannot cache).

@njit(_nrt=False)
def force_stage(i_normal, i_tangential, l0, l1, B, tab, row, dt):
    """The normal sub-model ``i_normal`` of :data:`NORMAL` and the tangential one
    ``i_tangential`` of :data:`TANGENTIAL` over lanes l0..l1-1, in one loop."""
    k = 0
    for normal in literal_unroll(_NORMAL):
        if k == i_normal:
            _with_tangential(normal, i_tangential, l0, l1, B, tab, row, dt)
        k += 1


@njit(_nrt=False)
def _with_tangential(normal, i_tangential, l0, l1, B, tab, row, dt):
    """:func:`force_stage` for one normal sub-model (numba unrolls one registry per
    function)."""
    k = 0
    for tangential in literal_unroll(_TANGENTIAL):
        if k == i_tangential:
            _force_lanes(normal, tangential, l0, l1, B, tab, row, dt)
        k += 1


def _normal_lane(law, B, l, p):
    """``law(B, l, p)``, inlined when compiled (see :func:`_inline`)."""
    return law(B, l, p)


def _tangential_lane(law, B, l, p, F_n, k_t, gamma_t, dt):
    """``law(B, l, p, F_n, k_t, gamma_t, dt)``, inlined when compiled (see :func:`_inline`)."""
    law(B, l, p, F_n, k_t, gamma_t, dt)


def _inline(law):
    """The implementation of a lane call: ``law`` (a compiled sub-model passed as a
    value) called through a global, which numba inlines into its caller's IR; called as
    an argument it would be compiled apart and inlined later by LLVM, its arithmetic
    already paired into vectors, and the loop would not vectorize."""
    return law.dispatcher


@overload(_normal_lane, inline="always")
def _normal_lane_inlined(law, B, l, p):
    fn = _inline(law)

    def impl(law, B, l, p):
        return fn(B, l, p)
    return impl


@overload(_tangential_lane, inline="always")
def _tangential_lane_inlined(law, B, l, p, F_n, k_t, gamma_t, dt):
    fn = _inline(law)

    def impl(law, B, l, p, F_n, k_t, gamma_t, dt):
        fn(B, l, p, F_n, k_t, gamma_t, dt)
    return impl


@njit(_nrt=False)
def _force_lanes(normal, tangential, l0, l1, B, tab, row, dt):
    """The loop over lanes of one (normal, tangential) pair of sub-models: each law's
    constants read once, then per lane F_n, k_t, gamma_t handed from the normal to the
    tangential lane function in registers (both inlined: one vectorized loop)."""
    p_n = normal[0](tab, row)
    p_t = tangential[0](tab, row)
    for l in range(uint(l0), uint(l1)):
        F_n, k_t, gamma_t = _normal_lane(normal[1], B, l, p_n)
        _tangential_lane(tangential[1], B, l, p_t, F_n, k_t, gamma_t, dt)


@njit(_nrt=False)
def rolling_stage(idx, l0, l1, B, tab, row, dt):
    """The rolling sub-model ``idx`` of :data:`ROLLING` over lanes l0..l1-1."""
    k = 0
    for f in literal_unroll(_ROLLING):
        if k == idx:
            f(l0, l1, B, tab, row, dt)
        k += 1


@njit(_nrt=False)
def heat_stage(idx, l0, l1, B, tab, row, dt):
    """The heat sub-model ``idx`` of :data:`HEAT` over lanes l0..l1-1."""
    k = 0
    for f in literal_unroll(_HEAT):
        if k == idx:
            f(l0, l1, B, tab, row, dt)
        k += 1


@njit(_nrt=False)
def evaluate(l0, l1, B, tab, row, dt, model):
    """Run the chosen sub-models over lanes l0..l1-1 of the buffer ``B``, which share
    pair-table row ``row``: normal, tangential, rolling, heat (module docstring)."""
    force_stage(model[M_NORMAL], model[M_TANGENTIAL], l0, l1, B, tab, row, dt)
    # "none" (entry 0) is skipped: its outputs keep the zeros the buffers start with
    if model[M_ROLLING] != 0:
        rolling_stage(model[M_ROLLING], l0, l1, B, tab, row, dt)
    if model[M_HEAT] != 0:
        heat_stage(model[M_HEAT], l0, l1, B, tab, row, dt)


@njit(_nrt=False)
def evaluate_heat(l0, l1, B, tab, row, model):
    """Only the heat sub-model over lanes l0..l1-1 (the conductance sum of the stability
    check: with ``DTEMP`` = 1 K, ``Q`` is the conductance H in W/K)."""
    heat_stage(model[M_HEAT], l0, l1, B, tab, row, 0.0)
