"""The contact log: every contact between t0 and t1, for the long-time heat extrapolation
of Haydar, Martin & Bonnefoy (2023), Chem. Eng. Sci. 277, 118815 (their Table 1 and
Algorithm 2).

Usage::

    sim.start_contact_log(every=10, dt_split=1e-3)   # at t0
    sim.step(k)                                      # any number of calls
    log = sim.stop_contact_log()                     # at t1: a ContactLog
    log.save("period.npz"); log = ContactLog.load("period.npz")

What is recorded.  The contacts are sampled every ``every`` DEM steps, after the force
pass of the sampled step (so exactly the contacts, positions and walls the forces and
the heat of that step saw): every touching particle pair, every plane contact and every
accepted triangle contact (:mod:`gsi.dem.mesh_dedup`).  A sample stands for the
``every`` steps that end with it, so a contact seen by c consecutive samples lasted
c x every x dt; contacts shorter than ``every`` steps may be missed (the seed's sampling
factor n).  A contact becomes one row per stretch of at most ``dt_split`` (the seed's
Delta t_c^max, Algorithm 2: a contact of 25 s with Delta t_c^max = 10 s is the rows
10 + 10 + 5); each row holds

- the pair: two particle indices, or a particle index, a wall and, for a mesh wall, the
  triangle (numbered within its wall; a contact on an edge or vertex is logged under the
  triangle that reported it, so it may change rows when the reporting triangle
  changes);
- its start (steps after t0) and duration m (steps);
- the mean over its samples of the contact size s that the conductance model
  multiplies, H = c s (:mod:`gsi.dem.contact.conductance`): s = sqrt(pi a^2) for ``area`` (the
  seed's sqrt(a_ij)), s = a for ``radius``, s = 1 for ``constant``, with c = 4 k_i k_j/
  (k_i + k_j) (``h_c`` for ``constant``); a run without a heat model logs the ``area``
  size.  The mean size times m is the sampled integral of H/c over the row.

Contacts open at t0 start at t0 and those still open at t1 end at t1.  Rows are sorted
by start, then by the particle pair (the order the replay treats them in).

Particles are logged by their index in the sorted id array of the particles present at
t0 (``ids``), which must be the particles present at t1 (no insertion or loss during a
log).  Positions, temperatures, heat capacities m c_p (J/K) and material types of those
particles at t0 and t1, the conductance factors c of every material pair, the walls'
temperatures (a wall without one is adiabatic) and the time step come with the rows.

Cost.  Logging is a run-time switch of the engine's model (:mod:`gsi.dem.engine`,
``get_engine(..., log=True)``): a simulation that does not log pays one test per step.
The logging engine follows the same trajectory bit for bit; on a sampled step it ends the step before the next one
begins instead of fusing them (one more parallel region per sample) and runs the serial
:func:`sample` (a walk over the contacts and a sort of their keys).

File: :meth:`ContactLog.save` writes an ``.npz``; a particle-particle row takes 18 bytes
(two int32 indices, int32 start, uint16 duration -- int32 if a row is longer than 65,535
steps -- and float32 size), a wall row 20 (int16 wall, int32 triangle).
"""
from __future__ import annotations

import math
import pathlib
from collections import namedtuple

import numpy as np

from gsi.dem.contact_geometry import sphere_pair, pair_radius2, wall_radius2, plane_distance
from gsi.errors import GsiInputError
from gsi.jit import njit

__all__ = ["ContactLog", "LogState", "empty_log_state", "grown", "sample", "has_room",
           "count_contacts", "close_open", "SIZE_MODELS"]

#: size model of each heat model: 0 sqrt(pi a^2) (area, and no heat model), 1 a
#: (radius), 2 one (constant)
SIZE_MODELS = {None: 0, "area": 0, "radius": 1, "constant": 2}

# rows of LogState.ctrl
C_EVERY, C_SPLIT, C_NEXT, C_STEP, C_NOPEN, C_NROWS, C_MODEL, C_SAMPLES, C_START = range(9)
N_CTRL = 9
#: a key is (lower particle id) << 32 | other; other >= WALL_BASE is a wall contact:
#: WALL_BASE + p for plane p, WALL_BASE + TRI_BASE + t for mesh triangle row t
WALL_BASE = 1 << 31
TRI_BASE = 64

LogState = namedtuple("LogState", [
    "ctrl",        # (N_CTRL,) int64: every, split (samples per row, 0: none), next sampled
                   # step, step count at the call, open contacts, rows, size model, samples,
                   # step count at t0
    "open_key",    # (cap,) int64: open contacts (a row in progress), sorted by key
    "open_start",  # (cap,) int64: step at which the open row started
    "open_count",  # (cap,) int64: samples in the open row
    "open_sum",    # (cap,) float64: sum of the sizes of those samples
    "nxt_key",     # (cap,) int64 ... the open contacts being built by a sample
    "nxt_start",
    "nxt_count",
    "nxt_sum",
    "cur_key",     # (cap,) int64: the contacts of the current sample
    "cur_size",    # (cap,) float64
    "row_key",     # (rcap,) int64: finished rows
    "row_start",   # (rcap,) int32: first step of the row (steps after t0)
    "row_dur",     # (rcap,) int32: duration (steps)
    "row_size",    # (rcap,) float32: mean contact size
])
"""The log in the making (arrays the engine writes; :class:`gsi.dem.simulation.Simulation`
grows them when a sample would not fit)."""


def empty_log_state(cap=0, rcap=0):
    """A :data:`LogState` with room for ``cap`` open contacts and ``rcap`` rows."""
    i8 = np.int64
    return LogState(np.zeros(N_CTRL, i8),
                    *[np.zeros(cap, t) for _ in range(2) for t in (i8, i8, i8, float)],
                    np.zeros(cap, i8), np.zeros(cap), np.zeros(rcap, i8),
                    np.zeros(rcap, np.int32), np.zeros(rcap, np.int32),
                    np.zeros(rcap, np.float32))


def grown(lg, cap, rcap):
    """A copy of ``lg`` with room for ``cap`` open contacts and ``rcap`` rows."""
    new = empty_log_state(max(cap, lg.cur_key.shape[0]), max(rcap, lg.row_key.shape[0]))
    new.ctrl[:] = lg.ctrl
    no, nr = int(lg.ctrl[C_NOPEN]), int(lg.ctrl[C_NROWS])
    for k in ("open_key", "open_start", "open_count", "open_sum"):
        getattr(new, k)[:no] = getattr(lg, k)[:no]
    for k in ("row_key", "row_start", "row_dur", "row_size"):
        getattr(new, k)[:nr] = getattr(lg, k)[:nr]
    return new


@njit
def contact_size(a2, model):
    """The size s of a contact of squared radius ``a2`` (m^2) that the heat model
    multiplies (``model``: see :data:`SIZE_MODELS`)."""
    if model == 2:
        return 1.0
    if a2 <= 0.0:
        return 0.0
    if model == 1:
        return math.sqrt(a2)
    return math.sqrt(math.pi * a2)


@njit
def count_contacts(P, pairs, wc):
    """Number of contacts the force pass just found (pairs, planes, triangles)."""
    n = 0
    for k in range(pairs.active.shape[0]):
        n += pairs.active[k]
    for i in range(P.x.shape[0]):
        m = wc.plane_mask[i]
        while m:
            n += m & 1
            m >>= 1
        n += wc.count[i]
    return n


@njit
def has_room(P, pairs, wc, lg):
    """Whether :func:`sample` fits in ``lg`` now."""
    nc = count_contacts(P, pairs, wc)
    return (nc <= lg.cur_key.shape[0]
            and lg.ctrl[C_NROWS] + lg.ctrl[C_NOPEN] <= lg.row_key.shape[0])


@njit
def _emit(lg, key, start, count, total, every):
    r = lg.ctrl[C_NROWS]
    lg.row_key[r] = key
    lg.row_start[r] = start - lg.ctrl[C_START]
    lg.row_dur[r] = count * every
    lg.row_size[r] = total / count
    lg.ctrl[C_NROWS] = r + 1


@njit
def sample(P, pairs, pl, M, wc, lg):
    """Record the contacts of the force pass just done (the sample at step
    ``lg.ctrl[C_NEXT]``, which it advances by ``every``).  The caller has checked
    :func:`has_room`."""
    ctrl = lg.ctrl
    every = ctrl[C_EVERY]
    split = ctrl[C_SPLIT]
    model = ctrl[C_MODEL]
    step = ctrl[C_NEXT]
    x = P.x
    ids = P.id
    nc = 0
    npl = pl.point.shape[0]
    for i in range(x.shape[0]):
        ri = P.radius[i]
        idi = ids[i]
        for k in range(pairs.start[i], pairs.start[i + 1]):
            if pairs.active[k] == 0:
                continue
            j = pairs.j[k]
            rj = P.radius[j]
            touch, L2, inv_L, nx, ny, nz, delta = sphere_pair(
                x[j, 0] - x[i, 0], x[j, 1] - x[i, 1], x[j, 2] - x[i, 2], ri, rj)
            idj = ids[j]
            lo = min(idi, idj)
            hi = max(idi, idj)
            lg.cur_key[nc] = (lo << 32) | hi
            lg.cur_size[nc] = contact_size(pair_radius2(ri, rj, L2, inv_L), model) if touch \
                else 0.0
            nc += 1
        mask = wc.plane_mask[i]
        if mask:
            for p in range(npl):
                if (mask >> p) & 1:
                    dist = plane_distance(x[i, 0], x[i, 1], x[i, 2], pl.point[p, 0],
                                          pl.point[p, 1], pl.point[p, 2], pl.normal[p, 0],
                                          pl.normal[p, 1], pl.normal[p, 2])
                    lg.cur_key[nc] = (idi << 32) | (WALL_BASE + p)
                    lg.cur_size[nc] = contact_size(wall_radius2(ri, ri - dist), model)
                    nc += 1
        for s in range(wc.count[i]):
            d2 = 0.0
            for d in range(3):
                dd = wc.point[i, s, d] - x[i, d]
                d2 += dd * dd
            lg.cur_key[nc] = (idi << 32) | (WALL_BASE + TRI_BASE + wc.tri[i, s])
            lg.cur_size[nc] = contact_size(wall_radius2(ri, ri - math.sqrt(d2)), model)
            nc += 1
    order = np.argsort(lg.cur_key[:nc])
    no = ctrl[C_NOPEN]
    a = 0
    b = 0
    m = 0
    kb = 0
    while a < no or b < nc:
        if b < nc:
            kb = lg.cur_key[order[b]]
        if b >= nc or (a < no and lg.open_key[a] < kb):
            # ended before this sample
            if lg.open_count[a] > 0:
                _emit(lg, lg.open_key[a], lg.open_start[a], lg.open_count[a], lg.open_sum[a],
                      every)
            a += 1
            continue
        size = lg.cur_size[order[b]]
        if a >= no or kb < lg.open_key[a]:
            # new: it began in the interval this sample stands for
            start = step - every
            count = 1
            total = size
        else:
            start = lg.open_start[a]
            count = lg.open_count[a] + 1
            total = lg.open_sum[a] + size
            a += 1
        if split > 0 and count == split:
            _emit(lg, kb, start, count, total, every)
            start = step
            count = 0
            total = 0.0
        lg.nxt_key[m] = kb
        lg.nxt_start[m] = start
        lg.nxt_count[m] = count
        lg.nxt_sum[m] = total
        m += 1
        b += 1
    for q in range(m):
        lg.open_key[q] = lg.nxt_key[q]
        lg.open_start[q] = lg.nxt_start[q]
        lg.open_count[q] = lg.nxt_count[q]
        lg.open_sum[q] = lg.nxt_sum[q]
    ctrl[C_NOPEN] = m
    ctrl[C_NEXT] = step + every
    ctrl[C_SAMPLES] += 1


@njit
def close_open(lg):
    """End every open contact (the log stops): its row ends at the last sample."""
    every = lg.ctrl[C_EVERY]
    for a in range(lg.ctrl[C_NOPEN]):
        if lg.open_count[a] > 0:
            _emit(lg, lg.open_key[a], lg.open_start[a], lg.open_count[a], lg.open_sum[a], every)
    lg.ctrl[C_NOPEN] = 0


class ContactLog:
    """A finished contact log (see the module docstring): rows and particle data.

    Attributes
    ----------
    pp_i, pp_j : (r,) int32
        Particle-particle rows: particle indices (rows of ``ids``), pp_i < pp_j.
    pp_start, pp_dur : (r,) int
        Start (steps after t0) and duration m (steps).
    pp_size : (r,) float32
        Mean contact size (m for ``area``/``radius``, 1 for ``constant``).
    pw_i, pw_wall, pw_tri, pw_start, pw_dur, pw_size : (w,)
        Particle-wall rows: particle index, wall (planes first, in the order added, then
        mesh walls), triangle within a mesh wall (-1 for a plane), start, duration, size.
    ids : (N,) int64
        Particle ids, sorted.
    x0, x1 : (N, 3) float64
        Positions at t0 and t1 (m).
    T0, T1 : (N,) float64
        Temperatures at t0 and t1.
    heat_capacity : (N,) float64
        m c_p (J/K).
    type : (N,) int32
        Material index.
    coef : (ntype, ntype) float64
        Conductance factor c of each material pair, H = c s (W/(m K); W/K for
        ``constant``).
    wall_type : (nwall,) int32; wall_T : (nwall,) float64; wall_has_T : (nwall,) bool
        Wall material, temperature (plane: its value at t0; mesh: the mean of its vertex
        temperatures at t0), and whether it has one (else adiabatic).
    dt, t0, t1 : float
        DEM step and the log's ends (s).
    every : int
        Sampling factor n (steps).
    split : int
        Delta t_c^max in steps (0: rows are not split).
    model : str
        Heat model the sizes belong to ("area", "radius", "constant").
    samples : int
        Number of samples taken.
    """

    ROWS = ("pp_i", "pp_j", "pp_start", "pp_dur", "pp_size", "pw_i", "pw_wall", "pw_tri",
            "pw_start", "pw_dur", "pw_size")
    PARTICLES = ("ids", "x0", "x1", "T0", "T1", "heat_capacity", "type")
    WALLS = ("coef", "wall_type", "wall_T", "wall_has_T")
    SCALARS = ("dt", "t0", "t1", "every", "split", "model", "samples")

    def __init__(self, **fields):
        for k in self.ROWS + self.PARTICLES + self.WALLS + self.SCALARS:
            setattr(self, k, fields[k])

    # ------------------------------------------------------------------ sizes
    @property
    def n_particles(self) -> int:
        return len(self.ids)

    @property
    def n_collisions(self) -> int:
        """Rows (particle-particle and particle-wall)."""
        return len(self.pp_i) + len(self.pw_i)

    @property
    def period(self) -> float:
        """t1 - t0 (s)."""
        return self.t1 - self.t0

    def row_bytes(self) -> int:
        """Bytes of the row arrays (as stored in the file, uncompressed)."""
        return sum(getattr(self, k).nbytes for k in self.ROWS)

    def bytes_per_collision(self) -> float:
        """Row bytes per row (the particle data at t0 and t1 not counted)."""
        return self.row_bytes() / max(self.n_collisions, 1)

    @property
    def pp_duration(self) -> np.ndarray:
        """Durations m of the particle-particle rows (s)."""
        return self.pp_dur * self.dt

    def index(self, ids) -> np.ndarray:
        """Log indices of particle ids."""
        ids = np.asarray(ids, np.int64)
        k = np.searchsorted(self.ids, ids)
        k = np.minimum(k, len(self.ids) - 1)
        if not (self.ids[k] == ids).all():
            raise GsiInputError("contact log: some ids are not particles of the log")
        return k

    # ------------------------------------------------------------------ file
    def save(self, path) -> int:
        """Write an ``.npz`` (uncompressed); returns its size in bytes."""
        path = pathlib.Path(path)
        d = {k: getattr(self, k) for k in self.ROWS + self.PARTICLES + self.WALLS}
        d.update({k: np.asarray(getattr(self, k)) for k in self.SCALARS})
        np.savez(path, **d)
        if path.suffix != ".npz":
            path = path.with_name(path.name + ".npz")
        return path.stat().st_size

    @classmethod
    def load(cls, path) -> "ContactLog":
        """Read a file written by :meth:`save`."""
        try:
            with np.load(path) as f:
                d = {k: f[k] for k in f.files}
        except (OSError, ValueError) as exc:
            raise GsiInputError(f"contact log file {str(path)!r}: cannot read it ({exc})") \
                from None
        missing = [k for k in cls.ROWS + cls.PARTICLES + cls.WALLS + cls.SCALARS
                   if k not in d]
        if missing:
            raise GsiInputError(f"contact log file {str(path)!r}: not a contact log (no "
                                f"{', '.join(missing[:3])})")
        for k in ("dt", "t0", "t1"):
            d[k] = float(d[k])
        for k in ("every", "split", "samples"):
            d[k] = int(d[k])
        d["model"] = str(d["model"])
        return cls(**d)

    # ------------------------------------------------------------------ building
    @classmethod
    def from_rows(cls, lg, *, ids, x0, x1, T0, T1, heat_capacity, type_,
                  coef, wall_type, wall_T, wall_has_T, tri_wall, tri_first, n_planes, dt,
                  t0, t1, model):
        """The finished log from the rows of a :data:`LogState` (open contacts closed)
        and the particle data at both ends (rows of ``ids`` order)."""
        nr = int(lg.ctrl[C_NROWS])
        key = lg.row_key[:nr]
        start = lg.row_start[:nr]
        dur = lg.row_dur[:nr]
        size = lg.row_size[:nr]
        lo = key >> 32
        other = key & 0xFFFFFFFF
        wall = other >= WALL_BASE
        order = np.lexsort((other, lo, start))          # by start, then the pair
        lo, other, wall = lo[order], other[order], wall[order]
        start, dur, size = start[order], dur[order], size[order]
        n = len(ids)

        def idx(a):
            k = np.minimum(np.searchsorted(ids, a), n - 1)
            if len(a) and not (ids[k] == a).all():
                raise GsiInputError("contact log: a logged particle is not present at t1; "
                                    "no particle may be inserted or lost while logging")
            return k.astype(np.int32)

        pp = ~wall
        code = other[wall] - WALL_BASE
        is_tri = code >= TRI_BASE
        pw_wall = code.astype(np.int16)
        pw_tri = np.full(len(code), -1, np.int64)
        if is_tri.any():
            t = code[is_tri] - TRI_BASE
            w = tri_wall[t]
            pw_wall[is_tri] = n_planes + w
            pw_tri[is_tri] = t - tri_first[w]
        dmax = int(dur.max()) if len(dur) else 0
        dtype = np.uint16 if dmax < 2 ** 16 else np.int32
        ctrl = lg.ctrl
        return cls(
            pp_i=idx(lo[pp]), pp_j=idx(other[pp]), pp_start=start[pp].astype(np.int32),
            pp_dur=dur[pp].astype(dtype), pp_size=size[pp].astype(np.float32),
            pw_i=idx(lo[wall]), pw_wall=pw_wall, pw_tri=pw_tri.astype(np.int32),
            pw_start=start[wall].astype(np.int32), pw_dur=dur[wall].astype(dtype),
            pw_size=size[wall].astype(np.float32),
            ids=ids, x0=x0, x1=x1, T0=T0, T1=T1, heat_capacity=heat_capacity, type=type_,
            coef=coef, wall_type=wall_type, wall_T=wall_T, wall_has_T=wall_has_T,
            dt=float(dt), t0=float(t0), t1=float(t1), every=int(ctrl[C_EVERY]),
            split=int(ctrl[C_SPLIT]) * int(ctrl[C_EVERY]), model=model,
            samples=int(ctrl[C_SAMPLES]))
