"""The DEM state in five bundles, each a named tuple of numpy arrays.

The compiled kernels take each bundle as ONE argument (numba types a named tuple of
arrays like a struct and caches functions taking it), so a kernel reads ``P.x[i, 0]``
and a new field is added in one place.  :class:`gsi.dem.simulation.Simulation`
exposes the bundles as ``sim.particles``, ``sim.wall_contacts``, ``sim.pairs``,
``sim.plane_state`` and ``sim.mesh_state`` (checkpoints and tests read them there).

Per-particle bundles (:data:`PARTICLE_FIELDS`, :data:`WALL_CONTACT_FIELDS`): the
simulation stores each field at a capacity >= n and hands the kernels views of the
first n rows; to add a per-particle field, add one line to the table (name, trailing
shape, dtype; ``"npl"`` stands for the plane count and ``"S"`` for the wall-contact
slots) and read it in the kernels.  New rows start at 0 unless
:meth:`Simulation.add_particles` sets them.

numba 0.56 on Python 3.11 cannot pass a named tuple of 16 or more fields into a
``prange`` body (it rebuilds it there with keyword arguments); a kernel with a
``prange`` therefore passes ``as_tuple(B)`` (a plain tuple, the same struct) into the
loop, to a function that names it again, ``P = Particles(*Pt)`` (free at run time).

Units are SI; the rows of ``pairs``, ``plane_state`` and ``mesh_state`` are
described with each named tuple below.
"""
from collections import namedtuple

import numpy as np
from numba import types
from numba.core.imputils import impl_ret_borrowed
from numba.extending import intrinsic

from gsi.jit import DISABLE_JIT

#: wall-contact slots per particle (mesh walls); more contacts raise an overflow flag
MAX_WALL_SLOTS = 8

#: per-particle state: name -> (trailing shape, dtype)
PARTICLE_FIELDS = {
    "x": ((3,), np.float64),         # position (m)
    "v": ((3,), np.float64),         # velocity (m/s)
    "omega": ((3,), np.float64),     # angular velocity (rad/s)
    "force": ((3,), np.float64),     # total force incl. gravity (N)
    "torque": ((3,), np.float64),    # total torque (N m)
    "q": ((), np.float64),           # heat rate into the particle (W)
    "radius": ((), np.float64),      # (m)
    "mass": ((), np.float64),        # (kg)
    "inertia": ((), np.float64),     # moment of inertia 2/5 m R^2 (kg m^2)
    "T": ((), np.float64),           # temperature
    "mcp_inv": ((), np.float64),     # 1/(m c_p) (K/J)
    "type": ((), np.int32),          # material index (row of the pair table)
    "fixed": ((), np.uint8),         # 1: held in place
    "ncontact": ((), np.int32),      # contacts at the last step
    "x0": ((3,), np.float64),        # position at the last neighbour build (m)
    "id": ((), np.int64),            # stable particle id (ascending in the rows)
    "heat_friction": ((), np.float64),  # accumulated frictional heat into it (J)
    "fd": ((3,), np.float64),        # this step's dissipative force x dt (N s; friction heat)
    "td": ((3,), np.float64),        # this step's dissipative torque x dt (N m s)
}

#: particle fields only frictional heating uses: a simulation without it stores them with
#: no rows (the kernels touch them only when it is on), so they cost no memory and no
#: copying at a list build (bytes per particle: benchmarks/settle.py)
FRICTION_FIELDS = ("heat_friction", "fd", "td")

#: per-particle wall-contact state: name -> (trailing shape, dtype)
WALL_CONTACT_FIELDS = {
    "plane_hist": (("npl", 3), np.float64),  # tangential spring per plane (m)
    "plane_mask": ((), np.int64),            # bit p set: touched plane p at the last step
    "plane_cand": ((), np.int64),            # bit p set: plane p within R + skin at the build
    "count": ((), np.int32),                 # triangle contacts (used slots)
    "tri": (("S",), np.int32),               # triangle of each slot
    "kind": (("S",), np.int32),              # closest feature: 0 face, 1 edge, 2 vertex
    "feature": (("S",), np.int64),           # triangle, edge or vertex id of the feature
    "cand": (("S",), np.int64),              # row of the slot's candidate in pairs.tri_hist
    "weight": (("S", 3), np.float64),        # barycentric weights of the contact point
    "force": (("S", 3), np.float64),         # force on the particle (N)
    "heat": (("S",), np.float64),            # heat rate into the particle (W)
    "point": (("S", 3), np.float64),         # contact point (m)
    "fheat": (("S",), np.float64),           # frictional heat rate into the wall (W)
}

#: per-particle state, views of the first n rows (see :data:`PARTICLE_FIELDS`)
Particles = namedtuple("Particles", list(PARTICLE_FIELDS))

#: per-particle wall contacts (see :data:`WALL_CONTACT_FIELDS`) and ``overflow`` (1,)
#: int64, counting triangle contacts dropped because all slots were used
WallContacts = namedtuple("WallContacts", list(WALL_CONTACT_FIELDS) + ["overflow"])

Pairs = namedtuple("Pairs", [
    "slab_start",   # (nslab + 1,) int64: slab s holds slab_list[slab_start[s]:slab_start[s+1]]
    "slab_list",    # (n,) int64: particle rows, slab by slab
    "start",        # (n + 1,) int64: partners of i are j[start[i]:start[i+1]] (half list)
    "j",            # (npair,) int32
    "hist",         # (npair, 3) float64: tangential spring of each pair (m), n from i to j
    "active",       # (npair,) uint8: 1 if the pair touched at the last step
    "tri_start",    # (n + 1,) int64: triangle candidates of i are tri[tri_start[i]:...]
    "tri",          # (ncand,) int32: triangle rows of mesh_state
    "tri_hist",     # (ncand, 3) float64: tangential spring of each candidate (m)
])
"""Neighbour lists (rebuilt when a particle or wall vertex moved skin/2) and the
tangential springs that live on them."""

Planes = namedtuple("Planes", [
    "point",        # (npl, 3): a point of each plane (m), moves with the velocity
    "point0",       # (npl, 3): the point at the last neighbour build (m)
    "normal",       # (npl, 3): unit normal into the domain
    "velocity",     # (npl, 3): (m/s)
    "type",         # (npl,) int32: material index
    "T",            # (npl,): temperature (if has_T)
    "has_T",        # (npl,) uint8
    "force",        # (npl, 3): force of the particles on the plane, last step (N)
    "torque",       # (npl, 3): their torque about ``point`` (N m)
    "impulse",      # (npl, 3): accumulated impulse ON the particles (N s)
    "heat",         # (npl,): accumulated heat INTO the particles (J)
    "friction_heat",  # (npl,): accumulated frictional heat INTO the plane (J)
    "work",         # (npl,): accumulated work of the plane ON the particles (J)
])
"""Infinite plane walls."""

Mesh = namedtuple("Mesh", [
    "x",            # (nv, 3): vertex positions (m)
    "v",            # (nv, 3): vertex velocities (m/s)
    "T",            # (nv,): vertex temperatures
    "x0",           # (nv, 3): positions at the last neighbour build (m)
    "vertex_wall",  # (nv,) int32: wall of each vertex
    "tri",          # (nt, 3) int32: vertex rows of each triangle
    "tri_edge",     # (nt, 3) int64: global edge ids of edges ab, bc, ca
    "tri_wall",     # (nt,) int32: wall of each triangle
    "tri_p6",       # (nt, 6) int32: P2 parent nodes (vertex rows), -1: linear weights
    "tri_lam",      # (nt, 3, 3): parent coordinates of each triangle vertex
    "tri_force",    # (nt, 3): force of the particles on each triangle, last step (N)
    "vertex_impulse",  # (nv, 3): accumulated -F w_k dt (N s)
    "vertex_heat",  # (nv,): accumulated -Q w_k dt (J)
    "wall_type",    # (nw,) int32: material index
    "wall_has_T",   # (nw,) uint8
    "wall_rigid",   # (nw,) uint8: 1: moves rigidly (velocity, omega about centre)
    "wall_velocity",  # (nw, 3) (m/s)
    "wall_omega",   # (nw, 3) (rad/s)
    "wall_centre",  # (nw, 3): rotation centre and torque reference (m)
    "wall_force",   # (nw, 3): force of the particles on the wall, last step (N)
    "wall_torque",  # (nw, 3): their torque about the centre (N m)
    "wall_impulse",  # (nw, 3): accumulated impulse ON the particles (N s)
    "wall_heat",    # (nw,): accumulated heat INTO the particles (J)
    "wall_friction_heat",  # (nw,): accumulated frictional heat INTO the wall (J)
    "wall_work",    # (nw,): accumulated work of the wall ON the particles (J)
])
"""Triangle-mesh walls (all walls' vertices and triangles in global arrays)."""


def empty_pairs(n):
    """Neighbour lists of ``n`` particles with no pairs and no candidates (one slab)."""
    return Pairs(np.array([0, n], np.int64), np.arange(n, dtype=np.int64),
                 np.zeros(n + 1, np.int64), np.zeros(0, np.int32), np.zeros((0, 3)),
                 np.zeros(0, np.uint8), np.zeros(n + 1, np.int64), np.zeros(0, np.int32),
                 np.zeros((0, 3)))


def empty_planes():
    """A plane bundle with no planes."""
    return Planes(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3)),
                  np.zeros(0, np.int32), np.zeros(0), np.zeros(0, np.uint8), np.zeros((0, 3)),
                  np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0), np.zeros(0))


def append_plane(pl, point, normal, velocity, mtype, T):
    """``pl`` with one more plane (accumulators 0; ``T`` None: adiabatic)."""
    def row(a, value):
        return np.concatenate([a, np.asarray([value], a.dtype)])
    return Planes(row(pl.point, point), row(pl.point0, point), row(pl.normal, normal),
                  row(pl.velocity, velocity),
                  row(pl.type, mtype), row(pl.T, 0.0 if T is None else T),
                  row(pl.has_T, T is not None), row(pl.force, np.zeros(3)),
                  row(pl.torque, np.zeros(3)), row(pl.impulse, np.zeros(3)),
                  row(pl.heat, 0.0), row(pl.friction_heat, 0.0), row(pl.work, 0.0))


def mesh_bundle(x, v, T, vertex_wall, tri, tri_edge, tri_wall, p6, lam, walls):
    """A :data:`Mesh` of the given vertex and triangle arrays with fresh accumulators;
    ``walls`` holds the per-wall arrays (wall_type ... wall_work) in field order."""
    x = np.ascontiguousarray(x, float)
    return Mesh(x, np.ascontiguousarray(v, float), np.ascontiguousarray(T, float), x.copy(),
                np.ascontiguousarray(vertex_wall, np.int32), np.ascontiguousarray(tri, np.int32),
                np.ascontiguousarray(tri_edge, np.int64),
                np.ascontiguousarray(tri_wall, np.int32), np.ascontiguousarray(p6, np.int32),
                np.ascontiguousarray(lam, float), np.zeros((len(tri), 3)),
                np.zeros((len(x), 3)), np.zeros(len(x)), *walls)


def empty_mesh():
    """A mesh bundle with no walls."""
    walls = (np.zeros(0, np.int32), np.zeros(0, np.uint8), np.zeros(0, np.uint8),
             np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3)),
             np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0), np.zeros(0))
    return mesh_bundle(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0, np.int32),
                       np.zeros((0, 3), np.int32), np.zeros((0, 3), np.int64),
                       np.zeros(0, np.int32), np.zeros((0, 6), np.int32),
                       np.zeros((0, 3, 3)), walls)


def bundle_bytes(bundle):
    """Bytes of all arrays of a bundle."""
    return sum(a.nbytes for a in bundle)


@intrinsic
def _as_tuple(typingctx, bundle):
    """The named tuple ``bundle`` as a plain tuple of the same members (same struct)."""
    if not isinstance(bundle, types.BaseNamedTuple):
        return None
    ret = types.Tuple(bundle.types)

    def codegen(context, builder, sig, args):
        return impl_ret_borrowed(context, builder, ret, args[0])
    return ret(bundle), codegen


if DISABLE_JIT:
    def as_tuple(bundle):
        """A bundle as a plain tuple (to cross a ``prange``, see the module docstring)."""
        return tuple(bundle)
else:
    as_tuple = _as_tuple
