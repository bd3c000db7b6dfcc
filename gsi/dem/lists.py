"""The neighbour-list build of the DEM (kernels: :mod:`gsi.dem.neighbour`): slabs, the
half pair list, triangle and plane candidates, the tangential springs carried over from
the previous lists by particle id.

How it runs (for speed, see ``benchmarks/settle.py``):

- One engine (:mod:`gsi.dem.engine`) serves every contact model (chosen at run time),
  compiled once and cached on disk by numba (:mod:`gsi.jit`); the very first run on a
  machine compiles it in about a minute (2 cores), later runs load it in a second.
- ``sim.step(n)`` runs the n steps inside one compiled call, returning to Python only
  to rebuild the neighbour list (any particle moved more than skin/2), to delete lost
  particles or to insert particles.
- Threads: numba's (``NUMBA_NUM_THREADS``, ``numba.set_num_threads``); below
  ``parallel_min_n`` particles one thread is used.  The pair loop is parallel over
  slabs (at least one cutoff thick, a multiple of 2 x threads) in two colours (no
  atomics, no per-pair buffers), so each pair's law is evaluated once and Newton's
  third law holds exactly; each slab is integrated inside the same pass as soon as its
  forces are complete, so a step has two parallel regions.  Use at most as many
  threads as free cores: an OpenMP barrier waiting for a descheduled thread costs a
  whole scheduler time slice per parallel region.
"""
import numba
import numpy as np

from gsi.dem import cells
from gsi.dem import neighbour as nbr
from gsi.dem.state import Pairs
from gsi.dem.storage import rows_of


#: steps between list builds that the adaptive skin aims at (:func:`adaptive_skin`)
STEPS_PER_BUILD = 10

#: particles up to which two threads search the pairs in the one serial pass over half
#: the stencil (:func:`gsi.dem.neighbour.find_pairs_serial`) rather than in two parallel
#: passes over the whole stencil (count, fill): on lattice beds of 2,197 / 4,096 / 8,000
#: spheres the serial pass took 0.59 / 1.18 / 1.84 ms, the two passes 1.41 / 2.63 /
#: 3.01 ms on one thread (0.71 / 1.32 / 1.51 ms at best on two); and a serial pass never
#: waits at a barrier for a descheduled thread on a busy host
SERIAL_PAIRS_MAX_N = 4096


def adaptive_skin(skin, skin_max, dt, *velocities):
    """The skin of the next lists (m): ``skin`` if ``skin_max <= skin`` (fixed), else
    enough for the fastest particle or wall vertex (``velocities``: arrays (k, 3), m/s)
    to take :data:`STEPS_PER_BUILD` steps before it has moved half the skin,
    2 N v_max dt, within [skin, skin_max].  A larger skin lists more candidate pairs; a
    smaller one rebuilds more often (a fast, sparse flow: every 2-3 steps at 0.4 R).  The
    lists stay correct either way: a rebuild falls due when anything moved half the skin
    of the current lists."""
    if skin_max <= skin:
        return skin
    v2 = 0.0
    for a in velocities:
        if len(a):
            v2 = max(v2, float(np.max(np.einsum("ij,ij->i", a, a))))
    return float(min(skin_max, max(skin, 2.0 * STEPS_PER_BUILD * np.sqrt(v2) * dt)))


def build_lists(store, walls, old, ids_at_build, *, lo, hi, skin, parallel_min_n,
                sort_particles):
    """New :data:`gsi.dem.state.Pairs` for the particles of ``store`` (a
    :class:`gsi.dem.storage.ParticleStore`) and the mesh and planes of ``walls`` (a
    :class:`gsi.dem.wall_registry.Walls`); ``old``: the previous lists and
    ``ids_at_build`` their particle ids (None: none yet). With ``sort_particles`` the
    rows are re-ordered into the force pass's visiting order. Updates the plane
    candidates and the build positions (particles ``x0``, walls ``x0``/``point0``).
    Returns ``(pairs, ids)``: the lists and the particle ids they were built for."""
    n = store.n
    x = store.particle["x"][:n]
    r = store.particle["radius"][:n]
    rmax = float(r.max()) if n else 0.0
    b_lo, b_hi = cells.bounding_box(x) if n else (lo, hi)
    g_lo, dims, inv_cs = cells.particle_grid(b_lo, b_hi, lo, hi, 2 * rmax + skin, n)
    cell_of = np.empty(n, np.int64)
    cells.cell_index(n, x, g_lo, inv_cs, dims, cell_of)
    cell_start, cell_list = cells.bin_cells(n, cell_of, int(dims.prod()))
    # slabs along the axis where the particles spread over most cells
    spread = np.floor((b_hi - g_lo) * inv_cs) - np.floor((b_lo - g_lo) * inv_cs)
    axis = int(np.argmax(spread))
    small = n < parallel_min_n
    threads = 1 if small else numba.get_num_threads()
    s_lo, s_inv_w, nslab = nbr.slab_layout(
        x[:, axis], 2 * rmax + skin, threads,
        min_per_slab=nbr.MIN_SLAB_PARTICLES if small else 1)
    slab_of, slab_start, slab_list = nbr.slab_sort(n, x, cell_list, axis, s_lo, s_inv_w, nslab)
    # no particle added or removed since the last build: the rows are those the old lists
    # were built for, so a new row's old row is its row before the re-ordering (no search
    # of the ids, 0.85 ms a build of the 5,000-sphere drum)
    ids = store.particle["id"][:n]
    same_rows = (ids_at_build is not None and len(ids_at_build) == n
                 and np.array_equal(ids, ids_at_build))
    perm = np.arange(n, dtype=np.int64)
    if sort_particles and n:
        # rows into visiting order: row m is the m-th particle the force pass visits
        perm = slab_list
        store.permute(perm)
        new_of_old = np.empty(n, np.int64)
        new_of_old[perm] = np.arange(n)
        cell_of = cell_of[perm]
        slab_of = slab_of[perm]
        cell_list = new_of_old[cell_list].astype(cell_list.dtype)
        slab_list = np.arange(n, dtype=slab_list.dtype)
    nb_start = np.zeros(n + 1, np.int64)
    serial = threads == 1 or (threads == 2 and n <= SERIAL_PAIRS_MAX_N)
    # (x, R) in cell order, for the serial pair search and the triangle search (once)
    xs = nbr.cell_ordered(x, r, cell_list) if serial or len(walls.mesh_state.tri) else None
    if serial:
        # one pass over half the cell stencil, entries sized from the last build's list
        nb_j = nbr.find_pairs_serial(n, xs, skin, cell_of, slab_of, cell_start, cell_list,
                                     dims, nb_start, _guess(old, "j", n))
    else:
        counts = np.empty(n, np.int64)
        nbr.find_pairs(n, x, r, skin, cell_of, slab_of, cell_start, cell_list, dims, counts,
                       nb_start, np.empty(0, np.int32), False)
        np.cumsum(counts, out=nb_start[1:])
        nb_j = np.empty(int(nb_start[-1]), np.int32)
        nbr.find_pairs(n, x, r, skin, cell_of, slab_of, cell_start, cell_list, dims, counts,
                       nb_start, nb_j, True)
    nbr.sort_rows(nb_start, nb_j)         # ascending partners: one list for any search
    npair = len(nb_j)
    hist = np.zeros((npair, 3))
    pact = np.zeros(npair, np.uint8)
    # new row -> old row (through the ids at the last build if the rows changed)
    built = ids_at_build is not None
    if built and len(ids_at_build):
        old_of_new = perm if same_rows else rows_of(ids_at_build, ids)
        nbr.carry_pair_history(n, nb_start, nb_j, hist, pact, old_of_new, old.start, old.j,
                               old.hist, old.active)
    else:
        old_of_new = np.full(n, -1, np.int64)
    mc_start, mc_tri, mc_hist = _triangle_candidates(
        walls.mesh_state, xs, cell_start, cell_list, g_lo, inv_cs, dims, rmax, skin, old,
        old_of_new, built, n)
    pairs = Pairs(slab_start, slab_list, nb_start, nb_j, hist, pact, mc_start, mc_tri,
                  mc_hist)
    pl = walls.plane_state
    nbr.plane_candidates(x, r, skin, pl.point, pl.normal, store.wall["plane_cand"][:n])
    pl.point0[:] = pl.point
    store.particle["x0"][:n] = x
    return pairs, ids.copy()


def _guess(old, field, n):
    """Entries to allocate for a one-pass list: the last build's ``old.<field>`` and a
    quarter more, or 8 per particle at the first build (grown if short)."""
    last = len(getattr(old, field)) if old is not None else 0
    last = last if last else 8 * n
    return int(1.25 * last) + 64


def _triangle_candidates(M, xs, cell_start, cell_list, lo, inv_cs, dims, rmax, skin, old,
                         old_of_new, built, n):
    """Triangle candidates of each of the ``n`` particles (one pass over the triangles on
    one thread: :func:`gsi.dem.neighbour.near_triangles_by_cell`; ``xs`` their (x, R) in
    cell order), their springs carried over from ``old``."""
    if not len(M.tri):
        return np.zeros(n + 1, np.int64), np.zeros(0, np.int32), np.zeros((0, 3))
    mc_start, mc_tri = nbr.near_triangles_by_cell(xs, skin, cell_start, cell_list, lo,
                                                  inv_cs, dims, rmax + skin, M.x, M.tri)
    mc_hist = np.zeros((len(mc_tri), 3))
    if built:
        nbr.carry_tri_history(n, mc_start, mc_tri, mc_hist, old_of_new, old.tri_start,
                              old.tri, old.tri_hist)
    M.x0[:] = M.x
    return mc_start, mc_tri, mc_hist
