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
   ``pipe`` (:mod:`gsi.dem.contact.conductance`);
5. **dissipation** (frictional heating on, :func:`evaluate_dissipation`, called by the
   engine after :func:`evaluate`): the power the contact dissipates
   (:mod:`gsi.dem.contact.dissipation`).

Each registry below maps a name to one compiled lane loop
``f(l0, l1, B, tab, row, dt)``; a new sub-model is one function in its own file and one
line in its registry.  The engine is compiled once for all of them: the model is a
small integer array (:func:`model_ids`), and :func:`evaluate` calls the chosen loop of
each stage (``literal_unroll`` over the registry, a direct call per batch, no code
generation and no function pointers).  Damping is part of the normal sub-model, as in
LIGGGHTS' ``hertz``/``hooke`` models, because each law's damping coefficient is tied to
its own stiffness.
"""
import numpy as np
from numba import literal_unroll

from gsi.jit import njit, uint
from gsi.errors import GsiInputError
from gsi.dem.contact import conductance as heat
from gsi.dem.contact import hertz, linear, tangential, rolling
from gsi.dem.contact.dissipation import dissipation

#: normal sub-models (elastic + damping): FN, KT, GT
NORMAL = {"hertz": hertz.hertz, "linear": linear.linear}
#: k_t of each normal sub-model grows as delta^p (the old spring energy of the dissipation)
KT_POWER = {"hertz": 0.5, "linear": 0.0}
#: tangential sub-models: FX..FZ and the spring
TANGENTIAL = {"history": tangential.history}
#: rolling sub-models: MX..MZ
ROLLING = {"none": rolling.none, "cdt": rolling.cdt}
#: heat sub-models: Q
HEAT = {"none": heat.none_lanes, "area": heat.area_lanes, "radius": heat.radius_lanes,
        "constant": heat.constant_lanes, "pipe": heat.pipe_lanes}

# "none" is entry 0 of ROLLING and HEAT: evaluate() skips it (a buffer starts with zeros)
assert list(ROLLING)[0] == "none" and list(HEAT)[0] == "none"

#: k_t/k_n of the linear law (the tangential spring energy of :mod:`gsi.dem.energy`)
K_T_OVER_K_N = linear.K_T_OVER_K_N

_NORMAL = tuple(NORMAL.values())
_KT_POWER = tuple(KT_POWER[name] for name in NORMAL)
_TANGENTIAL = tuple(TANGENTIAL.values())
_ROLLING = tuple(ROLLING.values())
_HEAT = tuple(HEAT.values())

#: entries of the model array (:func:`model_ids`)
M_NORMAL, M_TANGENTIAL, M_ROLLING, M_HEAT, M_LOG, M_FRICTION = range(6)


def model_ids(normal="hertz", tangential="history", rolling="none", heat="none", log=False,
              friction=False):
    """The model array the engine takes: the index of each sub-model in its registry, the
    contact-log switch and the frictional-heating switch.  ``rolling`` also takes
    True/False (cdt/none), ``heat`` None."""
    rolling = {True: "cdt", False: "none", None: "none"}.get(rolling, rolling)
    heat_name = "none" if heat is None else heat
    ids = []
    for key, name, reg in (("contact", normal, NORMAL), ("tangential", tangential, TANGENTIAL),
                           ("rolling", rolling, ROLLING), ("heat", heat_name, HEAT)):
        if name not in reg:
            raise GsiInputError(f"{key} = {name!r}: must be one of {sorted(reg)}")
        ids.append(list(reg).index(name))
    return np.array(ids + [int(bool(log)), int(bool(friction))], np.int64)


# One function per stage, each unrolling its registry (a global tuple: passed as an
# argument, the tuple of functions would be a dynamic global that numba cannot cache).

@njit(_nrt=False)
def normal_stage(idx, l0, l1, B, tab, row, dt):
    """The normal sub-model ``idx`` of :data:`NORMAL` over lanes l0..l1-1."""
    k = 0
    for f in literal_unroll(_NORMAL):
        if k == idx:
            f(l0, l1, B, tab, row, dt)
        k += 1


@njit(_nrt=False)
def tangential_stage(idx, l0, l1, B, tab, row, dt):
    """The tangential sub-model ``idx`` of :data:`TANGENTIAL` over lanes l0..l1-1."""
    k = 0
    for f in literal_unroll(_TANGENTIAL):
        if k == idx:
            f(l0, l1, B, tab, row, dt)
        k += 1


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
    normal_stage(model[M_NORMAL], l0, l1, B, tab, row, dt)
    tangential_stage(model[M_TANGENTIAL], l0, l1, B, tab, row, dt)
    # "none" (entry 0) is skipped: its outputs keep the zeros the buffers start with
    if model[M_ROLLING] != 0:
        rolling_stage(model[M_ROLLING], l0, l1, B, tab, row, dt)
    if model[M_HEAT] != 0:
        heat_stage(model[M_HEAT], l0, l1, B, tab, row, dt)


@njit(_nrt=False)
def evaluate_dissipation(n, B, dt, model):
    """Frictional heating (model switch ``M_FRICTION``): the dissipated power of lanes
    0..n-1 after :func:`evaluate` (:mod:`gsi.dem.contact.dissipation`; it reads only the
    lanes, so one call serves a whole batch; outside :func:`evaluate`, whose compiled
    code then stays as it is without friction)."""
    if model[M_FRICTION] != 0:
        dissipation(uint(0), uint(n), B, dt, _KT_POWER[model[M_NORMAL]])


@njit(_nrt=False)
def evaluate_heat(l0, l1, B, tab, row, model):
    """Only the heat sub-model over lanes l0..l1-1 (the conductance sum of the stability
    check: with ``DTEMP`` = 1 K, ``Q`` is the conductance H in W/K)."""
    heat_stage(model[M_HEAT], l0, l1, B, tab, row, 0.0)
