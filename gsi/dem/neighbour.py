"""Neighbour search: cell-linked list and half Verlet list with skin; triangle candidates.

- The domain box is cut into cells no smaller than 2 R_max + skin, so the 27 cells
  around a particle hold all its possible partners (the grid and its walk:
  :mod:`gsi.dem.cells`).
- Half list: pair (i, j) is stored once when |x_i - x_j| < R_i + R_j + skin, by the
  particle in the lower *slab* (slabs: layers at least one cutoff thick along the axis
  where the particles spread most, see :func:`slab_layout`; ties by the smaller
  index).  The force kernel then writes
  only to its own slab and the next one, so slabs of one parity run in parallel
  without races (see the force pass of :func:`gsi.dem.engine.advance`).
- The list is rebuilt when any particle (or wall vertex) has moved more than skin/2
  since the last build.  Tangential springs survive a rebuild: each new pair looks
  its partners up in the old list through ``old_of_new`` (new index -> old index,
  -1 for new particles) and copies the spring (negated if the pair is stored the
  other way round).
- Plane candidates: the planes within R_i + skin of particle i (a bit mask); planes
  moving more than skin/2 since the build also trigger a rebuild.
- Triangle candidates: the triangles closer than R_i + skin to particle i, found by
  each triangle among the particles of the cells near it (:func:`near_triangles_by_cell`).
  Triangle bins (each cell's triangles, :func:`bin_triangles`) serve the radiation's
  view search.
"""
import math

import numpy as np

from gsi.jit import njit, pjit, prange
from gsi.dem.geometry import closest_point_triangle, triangle_normal
from gsi.dem.contact_geometry import plane_distance
from gsi.dem.cells import bin_cells, cell_coords, neighbour_cell
from gsi.dem.wall_lanes import plane_count


@njit
def _partners(i, x, radius, skin, cell_of, slab_of, cell_start, cell_list, dims, nb_j, pos,
              fill):
    """The half-list partners of particle i (within R_i + R_j + skin, in a higher slab,
    or in the same slab with a higher index), found in the 27 cells around it: their
    number, and with ``fill`` each written to ``nb_j[pos], nb_j[pos + 1], ...`` while
    that lies inside ``nb_j`` (the count goes on past its end)."""
    cap = nb_j.shape[0]
    cx, cy, cz = cell_coords(cell_of[i], dims)
    cnt = 0
    ri = radius[i]
    si = slab_of[i]
    for k in range(27):
        c2 = neighbour_cell(cx, cy, cz, k, dims)
        if c2 >= 0:
            for m in range(cell_start[c2], cell_start[c2 + 1]):
                j = cell_list[m]
                sj = slab_of[j]
                if sj < si or (sj == si and j <= i):
                    continue
                rc = ri + radius[j] + skin
                d2 = ((x[j, 0] - x[i, 0]) ** 2 + (x[j, 1] - x[i, 1]) ** 2
                      + (x[j, 2] - x[i, 2]) ** 2)
                if d2 < rc * rc:
                    if fill and pos + cnt < cap:
                        nb_j[pos + cnt] = j
                    cnt += 1
    return cnt


@pjit
def find_pairs(n, x, radius, skin, cell_of, slab_of, cell_start, cell_list, dims, counts,
               nb_start, nb_j, fill):
    """Half-list partners of each particle (:func:`_partners`): their number into
    ``counts``, and with ``fill`` the partners into ``nb_j[nb_start[i]:nb_start[i+1]]``.
    One function for both passes (count, then fill): a parallel loop costs seconds to
    compile, and this one is compiled once."""
    for i in prange(n):
        counts[i] = _partners(i, x, radius, skin, cell_of, slab_of, cell_start, cell_list,
                              dims, nb_j, nb_start[i] if fill else 0, fill)


@njit
def cell_ordered(x, radius, cell_list):
    """(x, R) of the particles in cell order, one row of 4 per particle (row p: particle
    ``cell_list[p]``): the searches then read the partners of a cell from consecutive
    rows instead of from rows scattered over the arrays (unsorted particle rows)."""
    xs = np.empty((cell_list.shape[0], 4))
    for p in range(cell_list.shape[0]):
        i = cell_list[p]
        xs[p, 0] = x[i, 0]
        xs[p, 1] = x[i, 1]
        xs[p, 2] = x[i, 2]
        xs[p, 3] = radius[i]
    return xs


@njit
def find_pairs_serial(n, xs, skin, cell_of, slab_of, cell_start, cell_list, dims, nb_start,
                      cap):
    """The half list of :func:`find_pairs` in one serial pass over half the cell stencil
    (a small system on one thread): each cell meets its own particles after it and the
    13 cells after it in the walk of :func:`gsi.dem.cells.neighbour_cell`, so every pair
    within R_i + R_j + skin is tested once (the distance test is symmetric in i and j:
    the same pairs as :func:`_partners`).  The pair is stored by its particle in the
    lower slab (ties: the smaller index), through (owner, partner) entries and a stable
    counting sort by owner (:func:`gsi.dem.cells.bin_cells`); a row lists its partners
    in the order found (:func:`sort_rows` orders them).  ``cap``: entries to allocate at
    first (grown by doubling).  Fills ``nb_start`` (n + 1); returns ``nb_j``.  Positions
    and radii are read from ``xs``, their copy in cell order (:func:`cell_ordered`: the
    same values, so the same pairs bit for bit; a 5,000-sphere drum's rebuild spent most
    of its time here, in reads of partners scattered over x), made once per build for
    this search and :func:`near_triangles_by_cell`."""
    ent_i = np.empty(cap, np.int64)
    ent_j = np.empty(cap, np.int32)
    m = 0
    ncell = cell_start.shape[0] - 1
    for c in range(ncell):
        c0 = cell_start[c]
        c1 = cell_start[c + 1]
        if c0 == c1:
            continue
        cx, cy, cz = cell_coords(c, dims)
        for k in range(13, 27):          # the cell itself (k = 13) and the 13 after it
            c2 = neighbour_cell(cx, cy, cz, k, dims)
            if c2 < 0:
                continue
            for p in range(c0, c1):
                i = cell_list[p]
                ri = xs[p, 3]
                for q in range(p + 1 if k == 13 else cell_start[c2], cell_start[c2 + 1]):
                    rc = ri + xs[q, 3] + skin
                    d2 = ((xs[q, 0] - xs[p, 0]) ** 2 + (xs[q, 1] - xs[p, 1]) ** 2
                          + (xs[q, 2] - xs[p, 2]) ** 2)
                    if d2 < rc * rc:
                        j = cell_list[q]
                        if m == cap:                  # grow the entry buffers
                            cap *= 2
                            ni = np.empty(cap, np.int64)
                            nj = np.empty(cap, np.int32)
                            ni[:m] = ent_i[:m]
                            nj[:m] = ent_j[:m]
                            ent_i, ent_j = ni, nj
                        si = slab_of[i]
                        sj = slab_of[j]
                        if sj > si or (sj == si and j > i):
                            ent_i[m] = i
                            ent_j[m] = j
                        else:
                            ent_i[m] = j
                            ent_j[m] = i
                        m += 1
    start, order = bin_cells(m, ent_i, n)
    nb_start[:] = start
    return ent_j[order]


@pjit
def sort_rows(start, j):
    """Each row ``j[start[i]:start[i+1]]`` into ascending order (insertion sort: a row
    holds a few partners), so that the half list does not depend on how it was found
    (:func:`find_pairs_serial` or :func:`find_pairs`, the cell grid): the force pass then
    sums each particle's contacts in one order whatever the thread count."""
    for i in prange(start.shape[0] - 1):
        for k in range(start[i] + 1, start[i + 1]):
            v = j[k]
            m = k - 1
            while m >= start[i] and j[m] > v:
                j[m + 1] = j[m]
                m -= 1
            j[m + 1] = v


#: particles per slab at least (on average) in a serial run of a small system: a slab
#: task has a fixed cost of a few microseconds (a 336-particle drum in 22 slabs spent
#: more time in it than in its pair contacts), small beside 256 particles' contacts
MIN_SLAB_PARTICLES = 256


def slab_layout(coord, cutoff, nthreads, min_per_slab=1):
    """Slabs along one axis: ``(lo, inv_width, nslab)`` for particle coordinates ``coord``.

    Slabs are at least ``cutoff`` wide (so pair partners sit in the same or adjacent
    slabs) and as many as fit over the particles' extent, at most one per
    ``min_per_slab`` particles (:data:`MIN_SLAB_PARTICLES` for a system too small to
    run in parallel), rounded down to a multiple of 2 x ``nthreads`` when there are
    that many: each colour of the force pass of :func:`gsi.dem.engine.advance` then splits evenly
    over the threads.
    """
    if len(coord) == 0:
        return 0.0, 0.0, 1
    lo = float(coord.min())
    ext = float(coord.max()) - lo
    nmax = max(1, int(ext / cutoff)) if cutoff > 0 else 1
    nmax = min(nmax, max(1, len(coord) // max(1, int(min_per_slab))))
    g = 2 * max(1, int(nthreads))
    nslab = (nmax // g) * g if nmax >= g else nmax
    # widen by a hair so the highest particle falls in the last slab
    inv_w = nslab / (ext * (1.0 + 1e-9) + 1e-300)
    return lo, inv_w, nslab


@njit
def slab_sort(n, x, cell_list, axis, lo, inv_w, nslab):
    """Slab of each particle along ``axis``: ``(slab_of (n), slab_start (nslab+1),
    slab_list (n))``, particles of a slab in cell order (locality)."""
    slab_of = np.empty(n, np.int64)
    for i in range(n):
        s = int((x[i, axis] - lo) * inv_w)
        slab_of[i] = min(max(s, 0), nslab - 1)
    slab_start = np.zeros(nslab + 1, np.int64)
    for i in range(n):
        slab_start[slab_of[i] + 1] += 1
    for s in range(nslab):
        slab_start[s + 1] += slab_start[s]
    fill = slab_start[:-1].copy()
    slab_list = np.empty(n, np.int64)
    for m in range(n):
        i = cell_list[m]
        s = slab_of[i]
        slab_list[fill[s]] = i
        fill[s] += 1
    return slab_of, slab_start, slab_list


@pjit
def carry_pair_history(n, nb_start, nb_j, hist, pact, old_of_new, old_start, old_j,
                       old_hist, old_pact):
    """Copy each surviving pair's spring and contact flag from the old half list."""
    n_old = old_start.shape[0] - 1
    for i in prange(n):
        oi = old_of_new[i]
        if oi < 0 or oi >= n_old:
            continue
        for k in range(nb_start[i], nb_start[i + 1]):
            oj = old_of_new[nb_j[k]]
            if oj < 0 or oj >= n_old:
                continue
            found = False
            for ko in range(old_start[oi], old_start[oi + 1]):
                if old_j[ko] == oj:
                    hist[k, 0] = old_hist[ko, 0]
                    hist[k, 1] = old_hist[ko, 1]
                    hist[k, 2] = old_hist[ko, 2]
                    pact[k] = old_pact[ko]
                    found = True
                    break
            if not found:
                for ko in range(old_start[oj], old_start[oj + 1]):
                    if old_j[ko] == oi:
                        hist[k, 0] = -old_hist[ko, 0]
                        hist[k, 1] = -old_hist[ko, 1]
                        hist[k, 2] = -old_hist[ko, 2]
                        pact[k] = old_pact[ko]
                        break


@pjit
def plane_candidates(x, radius, skin, point, normal, plane_cand):
    """Bit p of ``plane_cand[i]`` set when plane p (``point``, unit ``normal``) lies
    within R_i + skin of particle i.

    Until the next build a particle and a plane each move less than skin/2 (planes
    count in the rebuild criterion), so no other plane can touch the particle."""
    npl = point.shape[0]
    for i in prange(x.shape[0]):
        m = 0
        for p in range(npl):
            dist = plane_distance(x[i, 0], x[i, 1], x[i, 2], point[p, 0], point[p, 1],
                                  point[p, 2], normal[p, 0], normal[p, 1], normal[p, 2])
            if dist < radius[i] + skin:
                m |= 1 << p
        plane_cand[i] = m


@njit(inline="always")
def _span(mn, mx, inflate, lo, inv_cs, dim):
    """First and last cell along one axis of the interval [mn, mx] inflated by
    ``inflate`` (m), clamped into the grid's ``dim`` cells."""
    return (max(0, int(math.floor((mn - inflate - lo) * inv_cs))),
            min(dim - 1, int(math.floor((mx + inflate - lo) * inv_cs))))


@njit
def _triangle(mv_x, mt, t):
    """The corners a, b, c of triangle t and its (unnormalised) normal N = (b-a) x (c-a)."""
    a = mt[t, 0]
    b = mt[t, 1]
    c = mt[t, 2]
    ax, ay, az = mv_x[a, 0], mv_x[a, 1], mv_x[a, 2]
    bx, by, bz = mv_x[b, 0], mv_x[b, 1], mv_x[b, 2]
    cx, cy, cz = mv_x[c, 0], mv_x[c, 1], mv_x[c, 2]
    Nx, Ny, Nz = triangle_normal(ax, ay, az, bx, by, bz, cx, cy, cz)
    return ax, ay, az, bx, by, bz, cx, cy, cz, Nx, Ny, Nz


@njit
def _push(ent_a, ent_t, m, a, t):
    """Entry m = (a, t) of the two entry buffers of a triangle search, which double when
    full; returns them."""
    if m == ent_a.shape[0]:
        na = np.empty(max(2 * m, 64), ent_a.dtype)
        nt = np.empty(max(2 * m, 64), ent_t.dtype)
        na[:m] = ent_a[:m]
        nt[:m] = ent_t[:m]
        ent_a, ent_t = na, nt
    ent_a[m] = a
    ent_t[m] = t
    return ent_a, ent_t


@njit
def bin_triangles(mv_x, mt, lo, inv_cs, dims, inflate):
    """Triangles per cell: each triangle goes into the cells of its bounding box
    (inflated by ``inflate``, m) whose centre lies within half a cell diagonal plus
    ``inflate`` of the triangle.  Returns ``(tcell_start, tcell_list)``, each cell's
    triangles in ascending order.

    One pass over the triangles writes the (cell, triangle) entries, then the counting
    sort by cell of :func:`gsi.dem.cells.bin_cells`.  A cell centre farther from the
    triangle's plane than the reach (with a margin of 1e-9 of it, so that round-off never
    drops a cell the exact test keeps) is skipped before its closest point is sought:
    the plane distance is a lower bound of the distance to the triangle."""
    nt = mt.shape[0]
    ncell = dims[0] * dims[1] * dims[2]
    cs = 1.0 / inv_cs
    half_diag = 0.5 * math.sqrt(cs[0] ** 2 + cs[1] ** 2 + cs[2] ** 2)
    reach2 = (half_diag + inflate) ** 2
    plane_reach2 = reach2 * (1.0 + 1e-9)
    cap = 8 * nt + 64
    ent_cell = np.empty(cap, np.int64)
    ent_tri = np.empty(cap, np.int32)
    m = 0
    for t in range(nt):
        (ax_, ay_, az_, bx_, by_, bz_, cx_, cy_, cz_,
         Nx, Ny, Nz) = _triangle(mv_x, mt, t)
        N2 = Nx * Nx + Ny * Ny + Nz * Nz
        k0, k1 = _span(min(ax_, bx_, cx_), max(ax_, bx_, cx_), inflate, lo[0], inv_cs[0],
                       dims[0])
        l0, l1 = _span(min(ay_, by_, cy_), max(ay_, by_, cy_), inflate, lo[1], inv_cs[1],
                       dims[1])
        m0, m1 = _span(min(az_, bz_, cz_), max(az_, bz_, cz_), inflate, lo[2], inv_cs[2],
                       dims[2])
        for ax in range(k0, k1 + 1):
            px = lo[0] + (ax + 0.5) * cs[0]
            for ay in range(l0, l1 + 1):
                py = lo[1] + (ay + 0.5) * cs[1]
                for az in range(m0, m1 + 1):
                    pz = lo[2] + (az + 0.5) * cs[2]
                    h = (px - ax_) * Nx + (py - ay_) * Ny + (pz - az_) * Nz
                    if h * h > plane_reach2 * N2:
                        continue
                    qx, qy, qz, wa, wb, wc, reg = closest_point_triangle(
                        px, py, pz, ax_, ay_, az_, bx_, by_, bz_, cx_, cy_, cz_)
                    if (qx - px) ** 2 + (qy - py) ** 2 + (qz - pz) ** 2 > reach2:
                        continue
                    ent_cell, ent_tri = _push(ent_cell, ent_tri, m,
                                              (ax * dims[1] + ay) * dims[2] + az, t)
                    m += 1
    counts, order = bin_cells(m, ent_cell, ncell)  # stable: ascending triangles per cell
    return counts, ent_tri[order]


@pjit
def carry_tri_history(n, mc_start, mc_tri, mc_hist, old_of_new, old_start, old_tri,
                      old_hist):
    """Copy each surviving (particle, triangle) spring from the old candidate list."""
    n_old = old_start.shape[0] - 1
    for i in prange(n):
        oi = old_of_new[i]
        if oi < 0 or oi >= n_old:
            continue
        for k in range(mc_start[i], mc_start[i + 1]):
            t = mc_tri[k]
            for ko in range(old_start[oi], old_start[oi + 1]):
                if old_tri[ko] == t:
                    mc_hist[k, 0] = old_hist[ko, 0]
                    mc_hist[k, 1] = old_hist[ko, 1]
                    mc_hist[k, 2] = old_hist[ko, 2]
                    break


@njit
def near_triangles_by_cell(xs, skin, cell_start, cell_list, lo, inv_cs, dims, inflate, mv_x,
                           mt):
    """The triangle candidates of every particle in one pass over the triangles: triangle t
    is a candidate of particle i when it lies closer than R_i + skin (the test of
    :func:`_near_triangles`, so the same sets).  Returns ``(mc_start (n+1), mc_tri)``,
    each particle's triangles in ascending order (the lists of :func:`tri_candidates`).

    Each triangle visits the cells of its bounding box inflated by ``inflate`` (R_max +
    skin), skips the empty ones and those whose centre lies farther from its plane than
    half a cell diagonal plus ``inflate`` (with the margin of :func:`bin_triangles`), and
    tests the particles of the rest (the triangle's bounding box inflated by R_i + skin,
    with a relative margin of 1e-9 so round-off never drops a candidate; the plane; then
    the closest point).  A counting
    sort by particle (:func:`gsi.dem.cells.bin_cells`, stable) follows.  No triangle bins
    are built, and a particle meets only the triangles near its own cell's particles;
    every particle must lie inside its cell (:func:`gsi.dem.cells.particle_grid`).  ``xs``:
    the particles' (x, R) in cell order (:func:`cell_ordered`)."""
    n = xs.shape[0]
    nt = mt.shape[0]
    cs = 1.0 / inv_cs
    half_diag = 0.5 * math.sqrt(cs[0] ** 2 + cs[1] ** 2 + cs[2] ** 2)
    plane_reach2 = (half_diag + inflate) ** 2 * (1.0 + 1e-9)
    cap = 4 * n + 64
    ent_i = np.empty(cap, np.int64)
    ent_t = np.empty(cap, np.int32)
    m = 0
    for t in range(nt):
        (ax_, ay_, az_, bx_, by_, bz_, cx_, cy_, cz_,
         Nx, Ny, Nz) = _triangle(mv_x, mt, t)
        N2 = Nx * Nx + Ny * Ny + Nz * Nz
        x_lo, x_hi = min(ax_, bx_, cx_), max(ax_, bx_, cx_)
        y_lo, y_hi = min(ay_, by_, cy_), max(ay_, by_, cy_)
        z_lo, z_hi = min(az_, bz_, cz_), max(az_, bz_, cz_)
        k0, k1 = _span(x_lo, x_hi, inflate, lo[0], inv_cs[0], dims[0])
        l0, l1 = _span(y_lo, y_hi, inflate, lo[1], inv_cs[1], dims[1])
        m0, m1 = _span(z_lo, z_hi, inflate, lo[2], inv_cs[2], dims[2])
        for kx in range(k0, k1 + 1):
            px = lo[0] + (kx + 0.5) * cs[0]
            for ky in range(l0, l1 + 1):
                py = lo[1] + (ky + 0.5) * cs[1]
                for kz in range(m0, m1 + 1):
                    c = (kx * dims[1] + ky) * dims[2] + kz
                    if cell_start[c] == cell_start[c + 1]:
                        continue
                    pz = lo[2] + (kz + 0.5) * cs[2]
                    h = (px - ax_) * Nx + (py - ay_) * Ny + (pz - az_) * Nz
                    if h * h > plane_reach2 * N2:
                        continue
                    for q in range(cell_start[c], cell_start[c + 1]):
                        px_ = xs[q, 0]
                        py_ = xs[q, 1]
                        pz_ = xs[q, 2]
                        rc = xs[q, 3] + skin
                        rb = rc * (1.0 + 1e-9)        # the box test never drops a candidate
                        if (px_ < x_lo - rb or px_ > x_hi + rb
                                or py_ < y_lo - rb or py_ > y_hi + rb
                                or pz_ < z_lo - rb or pz_ > z_hi + rb):
                            continue
                        rc2 = rc * rc
                        h = (px_ - ax_) * Nx + (py_ - ay_) * Ny + (pz_ - az_) * Nz
                        if h * h >= rc2 * N2:
                            continue
                        qx, qy, qz, wa, wb, wc, reg = closest_point_triangle(
                            px_, py_, pz_, ax_, ay_, az_, bx_, by_, bz_, cx_, cy_, cz_)
                        d2 = (qx - px_) ** 2 + (qy - py_) ** 2 + (qz - pz_) ** 2
                        if not d2 < rc2:
                            continue
                        i = cell_list[q]
                        ent_i, ent_t = _push(ent_i, ent_t, m, i, t)
                        m += 1
    mc_start, order = bin_cells(m, ent_i, n)      # stable: ascending triangles per particle
    return mc_start, ent_t[order]


@njit
def count_contacts(start, j, active, with_pairs, plane_mask, tri_count, out):
    """Contacts per particle at the last force pass into ``out`` (n,): the touching pairs
    (``active`` flags of the half list, counted at both particles, if ``with_pairs``), the
    touched planes (bits of ``plane_mask``) and the accepted triangle contacts
    (``tri_count``): what the force pass evaluated."""
    n = out.shape[0]
    for i in range(n):
        out[i] = tri_count[i] + plane_count(plane_mask[i])
    if with_pairs:
        for i in range(n):
            for k in range(start[i], start[i + 1]):
                if active[k] != 0:
                    out[i] += 1
                    out[j[k]] += 1
