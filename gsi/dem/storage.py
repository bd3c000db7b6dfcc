"""Per-particle storage of the DEM: the fields of :data:`gsi.dem.state.PARTICLE_FIELDS`
and :data:`gsi.dem.state.WALL_CONTACT_FIELDS` at a capacity, of which the first ``n``
rows are particles (:class:`ParticleStore`), and the named views a simulation offers on
them (:class:`ParticleViews`).

State (for checkpoints, tests and new kernels; :mod:`gsi.dem.state`): five bundles,
named tuples of numpy arrays that every compiled kernel takes as one argument each:

- ``sim.particles`` (:data:`~gsi.dem.state.Particles`): per-particle arrays (x, v,
  omega, force, torque, q, radius, mass, inertia, T, mcp_inv, type, fixed, ncontact,
  x0, id), views of the first n rows;
- ``sim.wall_contacts`` (:data:`~gsi.dem.state.WallContacts`): per-particle plane
  springs and the triangle-contact slots;
- ``sim.pairs`` (:data:`~gsi.dem.state.Pairs`): slabs, the half neighbour list with
  its tangential springs and contact flags, triangle candidates with their springs;
- ``sim.plane_state`` (:data:`~gsi.dem.state.Planes`) and ``sim.mesh_state``
  (:data:`~gsi.dem.state.Mesh`): the walls (read and written by :class:`PlaneWall`
  and :class:`MeshWall`).
"""
import math

import numpy as np

from gsi.dem.state import (PARTICLE_FIELDS, WALL_CONTACT_FIELDS, Particles, WallContacts,
                           bundle_bytes)


def row_items(arr):
    """A C-contiguous array with rows as a 1-d view of one opaque item per row (numpy's
    ``void`` of the row's bytes), or None if it has none (empty rows, not contiguous)."""
    width = arr.dtype.itemsize * math.prod(arr.shape[1:])
    if width == 0 or not arr.flags.c_contiguous:
        return None
    return arr.reshape(arr.shape[0], -1).view(np.dtype((np.void, width))).reshape(
        arr.shape[0])


#: bytes between the 4 kB offsets of two successive fields (:func:`staggered_zeros`)
STAGGER = 192


def staggered_zeros(shape, dtype, slot):
    """``np.zeros(shape, dtype)`` whose data start ``slot * STAGGER`` bytes past a 4 kB
    boundary (modulo 4 kB).

    Large arrays come from the system page-aligned, so without this the rows i of x, v,
    omega, force, torque and x0 lie at the same address modulo 4 kB: in the same set of
    the 8-way L1 cache, evicting each other, and each store to one looks to the CPU as
    if it might feed a later load of another (4k aliasing).  Staggered, row i of each
    field lies in a set of its own."""
    dtype = np.dtype(dtype)
    nbytes = math.prod(shape) * dtype.itemsize
    buf = np.zeros(nbytes + 4096 + 64, np.uint8)
    want = (slot * STAGGER) % 4096
    off = (want - buf.ctypes.data) % 4096
    return buf[off:off + nbytes].view(dtype).reshape(shape)


class ParticleStore:
    """Arrays of every per-particle field, grown by doubling.

    ``n_planes`` and ``slots`` size the wall-contact fields whose trailing shape names
    ``"npl"`` (one spring per plane) or ``"S"`` (the triangle-contact slots). Particle
    fields named in ``unused`` are kept with no rows (their views are empty): the fields
    of a feature that is off (:data:`gsi.dem.state.FRICTION_FIELDS`)."""

    def __init__(self, capacity: int = 16, *, unused=()):
        self.unused = frozenset(unused)
        unknown = self.unused - set(PARTICLE_FIELDS)
        if unknown:
            raise ValueError(f"ParticleStore: unknown fields {sorted(unknown)}")
        self.n = 0
        self.capacity = 0
        self.n_planes = 0
        self.slots = 0
        self.particle = {}                  # name -> array at capacity (PARTICLE_FIELDS)
        self.wall = {}                      # name -> array at capacity (WALL_CONTACT_FIELDS)
        self.overflow = np.zeros(1, np.int64)
        self.allocate(capacity)

    def _shape(self, cap, trail):
        return (cap,) + tuple({"npl": self.n_planes, "S": self.slots}.get(t, t) for t in trail)

    def _stores(self):
        return ((self.particle, PARTICLE_FIELDS), (self.wall, WALL_CONTACT_FIELDS))

    def allocate(self, cap: int) -> None:
        """Re-allocate every field at capacity ``cap`` (the first n rows kept)."""
        slot = 0
        for store, fields in self._stores():
            for name, (trail, dtype) in fields.items():
                rows = 0 if store is self.particle and name in self.unused else cap
                arr = staggered_zeros(self._shape(rows, trail), dtype, slot)
                slot += 1
                old = store.get(name)
                if old is not None and self.n and rows:
                    src = old[: self.n]
                    sl = tuple(slice(0, min(a, b)) for a, b in zip(src.shape, arr.shape))
                    arr[sl] = src[sl]
                store[name] = arr
        self.capacity = cap

    def set_wall_counts(self, *, n_planes=None, slots=None) -> None:
        """Re-shape the wall-contact fields for ``n_planes`` planes and ``slots`` triangle
        slots (existing entries kept where they fit)."""
        self.n_planes = self.n_planes if n_planes is None else n_planes
        self.slots = self.slots if slots is None else slots
        for slot, (name, (trail, dtype)) in enumerate(WALL_CONTACT_FIELDS.items(),
                                                      len(PARTICLE_FIELDS)):
            shape = self._shape(self.capacity, trail)
            old = self.wall[name]
            if shape == old.shape:
                continue
            arr = staggered_zeros(shape, dtype, slot)
            sl = tuple(slice(0, min(a, b)) for a, b in zip(old.shape, arr.shape))
            arr[sl] = old[sl]
            self.wall[name] = arr

    def append(self, k: int) -> slice:
        """Room for ``k`` more particles, every field zero there; returns their rows
        (the caller sets the fields and then :meth:`commit`)."""
        if self.n + k > self.capacity:
            self.allocate(max(2 * self.capacity, self.n + k))
        s = slice(self.n, self.n + k)
        for store, _ in self._stores():
            for arr in store.values():
                arr[s] = 0
        return s

    def commit(self, k: int) -> None:
        """The ``k`` rows of the last :meth:`append` are particles now."""
        self.n += k

    def add_spheres(self, x, r, *, mtype, rho, cp, v=None, T=None, omega=None, first_id):
        """Append k spheres (centres ``x`` (k, 3), radii ``r`` (k,), material index
        ``mtype`` of density ``rho`` and heat capacity ``cp``; ``v``, ``omega``, ``T``
        default 0) with ids ``first_id``, ...; every other field starts at 0. Returns
        the ids."""
        k = len(x)
        s = self.append(k)
        a = self.particle
        a["x"][s] = x
        a["v"][s] = 0.0 if v is None else np.broadcast_to(np.asarray(v, float), (k, 3))
        a["omega"][s] = 0.0 if omega is None else np.broadcast_to(np.asarray(omega, float),
                                                                  (k, 3))
        a["radius"][s] = r
        m = rho * 4.0 / 3.0 * np.pi * r ** 3
        a["mass"][s] = m
        a["inertia"][s] = 0.4 * m * r * r
        a["T"][s] = 0.0 if T is None else np.broadcast_to(np.asarray(T, float), (k,))
        a["mcp_inv"][s] = 1.0 / (m * cp)
        a["type"][s] = mtype
        a["x0"][s] = x
        ids = np.arange(first_id, first_id + k, dtype=np.int64)
        a["id"][s] = ids
        self.commit(k)
        return ids

    def delete(self, mask) -> None:
        """Remove the rows where ``mask`` (n,) is true (the others keep their order)."""
        keep = ~mask
        nk = int(keep.sum())
        for arr in self._rows():
            arr[:nk] = arr[: self.n][keep]
        self.n = nk

    def permute(self, perm) -> None:
        """Re-order the rows: new row m is old row ``perm[m]``.

        Each field's rows are moved as whole items (:func:`row_items`), so numpy copies a
        row in one piece: 0.72 ms instead of 1.97 ms for the fields of 5,000 particles
        with 8 triangle slots (best of 40, CPU time), at every list build of a sorted
        simulation; the same bytes either way."""
        n = self.n
        for arr in self._rows():
            rows = row_items(arr)
            if rows is None:
                if arr.size:
                    arr[:n] = arr[:n][perm]
            else:
                rows[:n] = np.take(rows[:n], perm)

    def _rows(self):
        """Every field array that has rows (not those in ``unused``)."""
        for store, _ in self._stores():
            for arr in store.values():
                if len(arr):
                    yield arr

    def view(self, name: str):
        """The first n rows of particle field ``name``."""
        return self.particle[name][: self.n]

    def particles(self):
        """:data:`gsi.dem.state.Particles` of views of the first n rows."""
        return Particles(*[self.particle[k][: self.n] for k in PARTICLE_FIELDS])

    def wall_contacts(self):
        """:data:`gsi.dem.state.WallContacts` of views of the first n rows."""
        return WallContacts(*[self.wall[k][: self.n] for k in WALL_CONTACT_FIELDS],
                            self.overflow)

    def nbytes(self, pairs) -> int:
        """Bytes of all per-particle storage and of the ``pairs`` bundle."""
        b = sum(arr.nbytes for store, _ in self._stores() for arr in store.values())
        return b + bundle_bytes(pairs)

    def state(self) -> dict:
        """Copies of the first n rows: ``p.<field>``, ``wc.<field>``, ``wc.overflow``."""
        n = self.n
        d = {f"p.{k}": self.particle[k][:n].copy() for k in PARTICLE_FIELDS}
        d.update({f"wc.{k}": self.wall[k][:n].copy() for k in WALL_CONTACT_FIELDS})
        d["wc.overflow"] = self.overflow.copy()
        return d

    def set_state(self, d: dict, n: int) -> None:
        """Restore :meth:`state` of ``n`` particles."""
        self.n = 0
        self.allocate(max(16, n))
        # fields added later (frictional heat) start at 0 from older checkpoints
        for k in PARTICLE_FIELDS:
            if k in self.unused:
                continue
            v = d.get(f"p.{k}")        # a field unused when the checkpoint was made: 0
            self.particle[k][:n] = 0 if v is None or len(v) != n else v
        for k in WALL_CONTACT_FIELDS:
            self.wall[k][:n] = d.get(f"wc.{k}", 0)
        self.overflow[:] = d["wc.overflow"]
        self.n = n


class ParticleViews:
    """Named views of a simulation's particles (``self.store``, a :class:`ParticleStore`)."""

    @property
    def n(self):
        """Number of particles."""
        return self.store.n

    @property
    def particles(self):
        """Per-particle state (:data:`gsi.dem.state.Particles`): views of the first n
        rows of every field of :data:`gsi.dem.state.PARTICLE_FIELDS`."""
        return self.store.particles()

    @property
    def wall_contacts(self):
        """Per-particle wall contacts (:data:`gsi.dem.state.WallContacts`): plane springs
        and contact flags, the triangle-contact slots; views of the first n rows."""
        return self.store.wall_contacts()

    @property
    def heat_capacity(self):
        """Heat capacity m c_p of each particle (n,) (J/K), a new array."""
        return 1.0 / self.store.view("mcp_inv")

    @property
    def x(self):
        """Positions (n, 3) (m), a view."""
        return self.store.view("x")

    @property
    def v(self):
        """Velocities (n, 3) (m/s), a view."""
        return self.store.view("v")

    @property
    def omega(self):
        """Angular velocities (n, 3) (rad/s), a view."""
        return self.store.view("omega")

    @property
    def force(self):
        """Total force on each particle (n, 3) (N) at the last step, incl. gravity."""
        return self.store.view("force")

    @property
    def torque(self):
        """Total torque on each particle (n, 3) (N m) at the last step."""
        return self.store.view("torque")

    @property
    def radius(self):
        """Radii (n,) (m), a view."""
        return self.store.view("radius")

    @property
    def mass(self):
        """Masses (n,) (kg), a view."""
        return self.store.view("mass")

    @property
    def inertia(self):
        """Moments of inertia (n,) (kg m^2), a view."""
        return self.store.view("inertia")

    @property
    def T(self):
        """Particle temperatures (n,), a view."""
        return self.store.view("T")

    @property
    def ids(self):
        """Particle ids (n,), a view."""
        return self.store.view("id")

    @property
    def type(self):
        """Material index of each particle (n,), a view."""
        return self.store.view("type")

    @property
    def ncontact(self):
        """Contacts per particle at the last step (n,): its touching pairs, planes and
        triangles, counted here from the contact flags the force pass leaves in the lists
        (:func:`gsi.dem.neighbour.count_contacts`; the force pass itself does not count:
        a store per pair partner less in its scatter).  Pairs count only while the lists
        are those of the current rows (after particles are added or removed: from the
        next step on)."""
        from gsi.dem.neighbour import count_contacts
        nc = self.store.view("ncontact")
        pairs = self.pairs
        wc = self.wall_contacts
        count_contacts(pairs.start, pairs.j, pairs.active, len(pairs.start) - 1 == len(nc),
                       wc.plane_mask, wc.count, nc)
        return nc

    def kinetic_energy(self, *, rotational=True):
        """Kinetic energy (J) of all particles: translation (+ rotation)."""
        e = 0.5 * float((self.mass * (self.v ** 2).sum(1)).sum())
        if rotational:
            e += 0.5 * float((self.inertia * (self.omega ** 2).sum(1)).sum())
        return e

    def potential_energy(self):
        """Gravitational potential energy -sum m g.x (J) (zero at the origin)."""
        return -float((self.mass * (self.x @ self.g)).sum())

    def momentum(self):
        """Total linear momentum (3,) (kg m/s)."""
        return (self.mass[:, None] * self.v).sum(0)

    def index(self, ids):
        """Rows of the given particle ids."""
        from gsi.errors import GsiInputError
        ids = np.asarray(ids, np.int64)
        rows = rows_of(self.ids, ids)
        if (rows < 0).any():
            raise GsiInputError(f"particle ids {ids[rows < 0][:5].tolist()}: not present "
                                "(lost or never added)")
        return rows


def rows_of(ids, wanted):
    """Rows of ``wanted`` ids in the id array ``ids`` (-1 where absent); ``ids`` are
    unique, sorted or not."""
    wanted = np.asarray(wanted, np.int64)
    if len(ids) == 0:
        return np.full(len(wanted), -1, np.int64)
    order = None if np.all(ids[1:] > ids[:-1]) else np.argsort(ids, kind="stable")
    srt = ids if order is None else ids[order]
    pos = np.minimum(np.searchsorted(srt, wanted), len(srt) - 1)
    rows = pos if order is None else order[pos]
    return np.where(srt[pos] == wanted, rows, -1).astype(np.int64)
