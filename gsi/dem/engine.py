"""Template of the law-dependent DEM kernels (not importable as it is).

:func:`gsi.dem.engine_factory.get_engine` writes a copy of this file with the block
between the ``ENGINE-LAWS`` markers replaced by the chosen contact law, rolling law
and heat model (one cached module per combination, because numba cannot cache
closures or function arguments), so the hot loops call the laws directly.  Only the
functions that call a law live here; integration (:mod:`gsi.dem.integrate`), wall
motion and wall sums (:mod:`gsi.dem.wall_kernels`), the mesh-contact de-duplication
(:mod:`gsi.dem.mesh_dedup`) and the contact geometry (:mod:`gsi.dem.contact_geometry`)
are ordinary cached numba modules compiled once for all engines.

Arguments: the state bundles of :mod:`gsi.dem.state` -- ``P`` particles, ``pairs``
neighbour lists, ``pl`` planes, ``M`` mesh walls, ``wc`` wall contacts -- and the pair
table ``tab`` flattened over (type_i, type_j) (see :mod:`gsi.dem.materials`).

One DEM step (velocity Verlet, DESIGN.md "DEM physics"):

1. v += dt/2 F/m, x += dt v, omega += dt/2 T/I, then F = m g, T = 0, Q = 0 for the
   new forces; walls move.
2. scan: largest displacement since the last neighbour build (rebuild when it
   exceeds skin/2), particles outside the domain, NaN or runaway velocities.
3. :func:`contact_forces` (parallel, two colours of slabs): the law of each pair once,
   added to both particles, the laws of a slab's touching pairs in vectorized batches
   (:func:`batch_laws`, the same bits as :func:`pair_contacts` one pair at a time);
   plane contacts (:func:`plane_contacts`) and triangle contacts
   (:func:`triangle_contacts`) of each particle.
4. v += dt/2 F/m, omega += dt/2 T/I; T += dt Q/(m c_p).
5. serial sums of wall forces, torques and the coupling accumulators.

Steps 4 and the next step's 1-2 run inside :func:`contact_forces`, slab by slab as the
forces complete, so a step has two parallel regions; only the first step of a call to
:func:`advance` drifts on its own.

The contact log (:mod:`gsi.dem.contact_log`) is compiled in only when ``LOG_ON`` (the
engine variant ``log=True``; numba removes the branches otherwise): a sampled step
ends before the next one drifts (same arithmetic, not fused), and the log samples the
contacts of its force pass.
"""
import math

import numpy as np

from gsi.jit import njit, pjit, prange, trailing_zeros, uint
from gsi.dem.contact_geometry import (sphere_pair, spheres_touch, touching_pair, pair_radius2,
                                     wall_radius2, plane_distance)
from gsi.dem.contact_log import C_NEXT, C_STEP, has_room, sample
from gsi.dem.integrate import (clear_forces, initial_integrate, scan, integrate_rows,
                               reduce_scans, verdict)
from gsi.dem.mesh_dedup import select_triangle_contacts
from gsi.dem.state import Particles, Pairs, Planes, Mesh, WallContacts, as_tuple
from gsi.dem.wall_kernels import move_walls, plane_sums, mesh_scatter

# <<ENGINE-LAWS (replaced by gsi.dem.engine_factory)
raise ImportError(
    "gsi.dem.engine is the template of the generated engines, not an engine: use "
    "gsi.dem.engine_factory.get_engine(contact, rolling, heat, log)")
# ENGINE-LAWS>>


@njit(_nrt=False)
def wall_contact(i, nx, ny, nz, lever, delta, wvx, wvy, wvz, P, ri, Ti, tab, row, hist, k,
                 dt, has_T, T_w):
    """One particle-wall contact (plane or triangle), shared by both wall kinds.

    ``n`` is the unit normal from the centre of i to the contact point at distance
    ``lever``, ``delta`` the overlap, ``wv`` the wall velocity there, ``row`` the
    (particle type, wall type) row of the pair table, ``hist[k]`` the tangential spring;
    the wall counts as infinitely large and heavy (R* = R_i, m* = m_i).  Returns the
    force on i, the torque on i (lever n x F plus rolling resistance) and the heat
    rate into i (0 unless the heat model is on and the wall has a temperature ``T_w``).
    """
    w = P.omega
    vx = P.v[i, 0] - wvx + lever * (w[i, 1] * nz - w[i, 2] * ny)
    vy = P.v[i, 1] - wvy + lever * (w[i, 2] * nx - w[i, 0] * nz)
    vz = P.v[i, 2] - wvz + lever * (w[i, 0] * ny - w[i, 1] * nx)
    cfx, cfy, cfz, F_n, hx, hy, hz = LAW(nx, ny, nz, delta, vx, vy, vz, ri, P.mass[i], tab,
                                         row, hist[k, 0], hist[k, 1], hist[k, 2], dt)
    hist[k, 0] = hx
    hist[k, 1] = hy
    hist[k, 2] = hz
    tx = lever * (ny * cfz - nz * cfy)
    ty = lever * (nz * cfx - nx * cfz)
    tz = lever * (nx * cfy - ny * cfx)
    if ROLL_ON:
        Mx, My, Mz = ROLL(w[i, 0], w[i, 1], w[i, 2], ri, F_n, tab, row, P.inertia[i], dt)
        tx += Mx
        ty += My
        tz += Mz
    Qw = 0.0
    if HEAT_ON and has_T:
        Qw = COND(wall_radius2(ri, delta), ri, math.inf, tab, row) * (T_w - Ti)
    return cfx, cfy, cfz, tx, ty, tz, Qw


@njit(_nrt=False)
def pair_contacts(i, P, pairs, tab, row_i, dt):
    """The pair contacts stored at particle i (half list): each law once, the force and
    torque of the partner j added to j here, those of i returned.

    Pair k = (i, j), n from i to j, overlap delta = R_i + R_j - L, lever arms
    a_i = R_i - delta/2, a_j = R_j - delta/2: torque a_i n x F on i and a_j n x F on j
    (F the force on i).  A pair that stops touching restarts its spring from zero.
    Returns ``(fx, fy, fz, tx, ty, tz, q, n_contacts)`` of i.
    """
    x = P.x
    v = P.v
    w = P.omega
    f = P.force
    tq = P.torque
    hist = pairs.hist
    pact = pairs.active
    mi = P.mass[i]
    ri = P.radius[i]
    Ti = P.T[i]
    xi0 = x[i, 0]
    xi1 = x[i, 1]
    xi2 = x[i, 2]
    fx = 0.0
    fy = 0.0
    fz = 0.0
    tx = 0.0
    ty = 0.0
    tz = 0.0
    qi = 0.0
    nc = 0
    # Two passes over each run of up to 64 candidates, in list order: the first tests
    # every candidate for contact without a branch (about half of a dense bed's candidates
    # touch, at random: a coin flip for the branch predictor) into a bit mask, and marks
    # the pair active, restarting the spring of one that stopped touching; the second
    # visits the touching ones, in the same order, so the sums are bitwise those of one
    # pass.  Indices are unsigned: numba tests a signed index for wrap-around (negative
    # counts from the end) at every access, which LLVM cannot hoist when the index is
    # loaded (j), nor a shift by a signed amount.  The settled bed's force pass 2.35 ->
    # 2.10 ms (benchmarks/engine_ab.py, one thread, 2026-12-03).
    k_end = np.uint64(pairs.start[i + 1])
    c0 = np.uint64(pairs.start[i])
    while c0 < k_end:
        c1 = min(c0 + np.uint64(64), k_end)
        mask = np.uint64(0)
        for k in range(c0, c1):
            j = np.uint64(pairs.j[k])
            dx = x[j, 0] - xi0
            dy = x[j, 1] - xi1
            dz = x[j, 2] - xi2
            L2 = dx * dx + dy * dy + dz * dz
            t = np.uint8(spheres_touch(L2, ri + P.radius[j]))
            mask |= np.uint64(t) << np.uint64(k - c0)
            was = pact[k]
            pact[k] = t
            if was > t:
                hist[k, 0] = 0.0
                hist[k, 1] = 0.0
                hist[k, 2] = 0.0
        base = c0
        c0 = c1
        while mask != np.uint64(0):
            k = base + np.uint64(trailing_zeros(mask))
            mask &= mask - np.uint64(1)
            j = np.uint64(pairs.j[k])
            rj = P.radius[j]
            touch, L2, inv_L, nx, ny, nz, delta = sphere_pair(x[j, 0] - xi0, x[j, 1] - xi1,
                                                              x[j, 2] - xi2, ri, rj)
            a_i = ri - 0.5 * delta
            a_j = rj - 0.5 * delta
            # velocity of i relative to j at the contact point:
            # v_i + w_i x (a_i n) - v_j - w_j x (-a_j n)
            wsx = a_i * w[i, 0] + a_j * w[j, 0]
            wsy = a_i * w[i, 1] + a_j * w[j, 1]
            wsz = a_i * w[i, 2] + a_j * w[j, 2]
            vx = v[i, 0] - v[j, 0] + wsy * nz - wsz * ny
            vy = v[i, 1] - v[j, 1] + wsz * nx - wsx * nz
            vz = v[i, 2] - v[j, 2] + wsx * ny - wsy * nx
            R_eff = ri * rj / (ri + rj)
            mj = P.mass[j]
            m_eff = mi * mj / (mi + mj)
            row = row_i + P.type[j]
            cfx, cfy, cfz, F_n, hx, hy, hz = LAW(nx, ny, nz, delta, vx, vy, vz, R_eff, m_eff,
                                                 tab, row, hist[k, 0], hist[k, 1], hist[k, 2],
                                                 dt)
            hist[k, 0] = hx
            hist[k, 1] = hy
            hist[k, 2] = hz
            # n x F
            cx = ny * cfz - nz * cfy
            cy = nz * cfx - nx * cfz
            cz = nx * cfy - ny * cfx
            Mx = 0.0
            My = 0.0
            Mz = 0.0
            if ROLL_ON:
                Ii = P.inertia[i]
                Ij = P.inertia[j]
                Mx, My, Mz = ROLL(w[i, 0] - w[j, 0], w[i, 1] - w[j, 1], w[i, 2] - w[j, 2],
                                  R_eff, F_n, tab, row, Ii * Ij / (Ii + Ij), dt)
            fx += cfx
            fy += cfy
            fz += cfz
            tx += a_i * cx + Mx
            ty += a_i * cy + My
            tz += a_i * cz + Mz
            f[j, 0] -= cfx
            f[j, 1] -= cfy
            f[j, 2] -= cfz
            tq[j, 0] += a_j * cx - Mx
            tq[j, 1] += a_j * cy - My
            tq[j, 2] += a_j * cz - Mz
            P.ncontact[j] += 1
            nc += 1
            if HEAT_ON:
                Qp = COND(pair_radius2(ri, rj, L2, inv_L), ri, rj, tab, row) * (P.T[j] - Ti)
                qi += Qp
                P.q[j] -= Qp
    return fx, fy, fz, tx, ty, tz, qi, nc


@njit(_nrt=False)
def plane_contacts(i, sl, P, pl, wc, plh, tab, row_i, dt, pl_acc):
    """The plane contacts of particle i: overlap delta = R - (x - p).n, contact normal
    -n, lever R - delta, wall velocity ``pl.velocity``.  Slab ``sl`` sums the force on
    its particles, their torque about the plane's point and their heat into
    ``pl_acc[sl, p]`` (see :func:`gsi.dem.wall_kernels.plane_sums`).  The springs are
    ``plh[i * npl + p]`` (``wc.plane_hist`` flattened once per pass: a row view per
    particle would count references in the hot loop); a contact that ends restarts
    its spring.  Only the planes of ``wc.plane_cand[i]`` (within R + skin at the last
    neighbour build) are looked at: most particles touch none.
    Returns ``(fx, fy, fz, tx, ty, tz, q, n_contacts)``."""
    fx = 0.0
    fy = 0.0
    fz = 0.0
    tx = 0.0
    ty = 0.0
    tz = 0.0
    qi = 0.0
    nc = 0
    cand = wc.plane_cand[i]
    if cand == 0:
        return fx, fy, fz, tx, ty, tz, qi, nc
    npl = pl.point.shape[0]
    ri = P.radius[i]
    Ti = P.T[i]
    xi0 = P.x[i, 0]
    xi1 = P.x[i, 1]
    xi2 = P.x[i, 2]
    base = i * npl
    pmask = 0
    was = wc.plane_mask[i]             # planes touched at the last step
    for p in range(npl):
        if not (cand >> p) & 1:
            continue
        Nx = pl.normal[p, 0]
        Ny = pl.normal[p, 1]
        Nz = pl.normal[p, 2]
        dist = plane_distance(xi0, xi1, xi2, pl.point[p, 0], pl.point[p, 1],
                              pl.point[p, 2], Nx, Ny, Nz)
        delta = ri - dist
        if delta <= 0.0:
            if (was >> p) & 1:     # contact ended: the spring restarts
                plh[base + p, 0] = 0.0
                plh[base + p, 1] = 0.0
                plh[base + p, 2] = 0.0
            continue
        nc += 1
        pmask |= 1 << p
        cfx, cfy, cfz, ctx, cty, ctz, Qw = wall_contact(
            i, -Nx, -Ny, -Nz, dist, delta, pl.velocity[p, 0], pl.velocity[p, 1],
            pl.velocity[p, 2], P, ri, Ti, tab, row_i + pl.type[p], plh, base + p, dt,
            pl.has_T[p], pl.T[p])
        # force on the particle and its moment about the plane's point, taken
        # at the contact point (the centre projected on the plane)
        rx = xi0 - dist * Nx - pl.point[p, 0]
        ry = xi1 - dist * Ny - pl.point[p, 1]
        rz = xi2 - dist * Nz - pl.point[p, 2]
        pl_acc[sl, p, 0] += cfx
        pl_acc[sl, p, 1] += cfy
        pl_acc[sl, p, 2] += cfz
        pl_acc[sl, p, 3] += ry * cfz - rz * cfy
        pl_acc[sl, p, 4] += rz * cfx - rx * cfz
        pl_acc[sl, p, 5] += rx * cfy - ry * cfx
        pl_acc[sl, p, 6] += Qw
        fx += cfx
        fy += cfy
        fz += cfz
        tx += ctx
        ty += cty
        tz += ctz
        qi += Qw
    wc.plane_mask[i] = pmask
    return fx, fy, fz, tx, ty, tz, qi, nc


@njit(_nrt=False)
def triangle_contacts(i, P, pairs, M, wc, tab, row_i, dt):
    """The triangle contacts of particle i at the closest points accepted by
    :func:`gsi.dem.mesh_dedup.select_triangle_contacts`; the wall velocity and
    temperature at the point are the barycentric means of the vertex values.  Each
    slot keeps the force and heat on i for :func:`gsi.dem.wall_kernels.mesh_scatter`.
    Returns ``(fx, fy, fz, tx, ty, tz, q, n_contacts)``."""
    fx = 0.0
    fy = 0.0
    fz = 0.0
    tx = 0.0
    ty = 0.0
    tz = 0.0
    qi = 0.0
    xi0 = P.x[i, 0]
    xi1 = P.x[i, 1]
    xi2 = P.x[i, 2]
    ri = P.radius[i]
    ns = select_triangle_contacts(i, xi0, xi1, xi2, ri, pairs, M, wc)
    wc.count[i] = ns
    Ti = P.T[i]
    mv = M.v
    for s in range(ns):
        t = wc.tri[i, s]
        ddx = wc.point[i, s, 0] - xi0
        ddy = wc.point[i, s, 1] - xi1
        ddz = wc.point[i, s, 2] - xi2
        dist = math.sqrt(ddx * ddx + ddy * ddy + ddz * ddz)
        delta = ri - dist
        nx = ddx / dist
        ny = ddy / dist
        nz = ddz / dist
        a = M.tri[t, 0]
        b = M.tri[t, 1]
        c = M.tri[t, 2]
        wa = wc.weight[i, s, 0]
        wb = wc.weight[i, s, 1]
        wcc = wc.weight[i, s, 2]
        wvx = wa * mv[a, 0] + wb * mv[b, 0] + wcc * mv[c, 0]
        wvy = wa * mv[a, 1] + wb * mv[b, 1] + wcc * mv[c, 1]
        wvz = wa * mv[a, 2] + wb * mv[b, 2] + wcc * mv[c, 2]
        wl = M.tri_wall[t]
        T_w = 0.0
        if HEAT_ON:
            T_w = wa * M.T[a] + wb * M.T[b] + wcc * M.T[c]
        cfx, cfy, cfz, ctx, cty, ctz, Qw = wall_contact(
            i, nx, ny, nz, dist, delta, wvx, wvy, wvz, P, ri, Ti, tab,
            row_i + M.wall_type[wl], pairs.tri_hist, wc.cand[i, s], dt, M.wall_has_T[wl],
            T_w)
        wc.force[i, s, 0] = cfx
        wc.force[i, s, 1] = cfy
        wc.force[i, s, 2] = cfz
        wc.heat[i, s] = Qw
        fx += cfx
        fy += cfy
        fz += cfz
        tx += ctx
        ty += cty
        tz += ctz
        qi += Qw
    return fx, fy, fz, tx, ty, tz, qi, ns


# ---- pair contacts in batches ----------------------------------------------------------
# The pair laws of a slab run in batches: the touching pairs of consecutive rows are
# compacted into the lanes of a buffer (gather_row), one loop evaluates the law of every
# lane (batch_laws: no memory access but the buffer, so LLVM vectorizes it, 4 lanes per
# ymm instruction here, the square roots and divisions included), then the rows are finished
# in order (finish_batch): each pair's force, torque and heat added to both particles in
# the order of pair_contacts, so the sums are bitwise those of the one-pair-at-a-time
# loop (the vector instructions round as the scalar ones; no FMA contraction).
# The settled bed's force pass 2.15 ms one pair at a time -> 1.80 ms batched
# (benchmarks/engine_ab.py, one thread, best of 7).  The row helpers are compiled
# forceinline: a call passes the five bundles by value (about 600 words), which per row
# made the pass 5.05 ms instead of 2.95.

#: lanes (pair contacts) per batch: 40, 72, 136 and 264 timed the same (engine_ab);
#: 33 fields x 72 lanes x 8 bytes = 19 kB stay in the L1 cache
CH = 72
#: fields of the batch buffer, CH lanes each: inputs (offset x_j - x_i, radii, masses,
#: v_i - v_j, omega_i, omega_j, inertias, temperatures), the tangential spring (read and
#: written), outputs (force on i, torques on i and j, heat into i)
(O_DX, O_DY, O_DZ, O_RI, O_RJ, O_MI, O_MJ, O_DVX, O_DVY, O_DVZ, O_WIX, O_WIY, O_WIZ, O_WJX,
 O_WJY, O_WJZ, O_II, O_IJ, O_TI, O_TJ, O_HX, O_HY, O_HZ, O_FX, O_FY, O_FZ, O_TIX, O_TIY,
 O_TIZ, O_TJX, O_TJY, O_TJZ, O_Q) = [uint(f * CH) for f in range(33)]
NB = 33
# Offsets and lanes are unsigned: numba tests a signed index for wrap-around, a select
# that hides the address from LLVM's loop vectorizer.


@njit(_nrt=False)
def batch_laws(l0, l1, B, tab, row, dt):
    """The contact laws of lanes l0 .. l1-1 of the batch buffer ``B``, all of pair-table
    row ``row`` (a loop-invariant row keeps the table reads out of the vectorizer's way);
    the arithmetic of :func:`pair_contacts`."""
    for l in range(uint(l0), uint(l1)):
        dx = B[O_DX + l]
        dy = B[O_DY + l]
        dz = B[O_DZ + l]
        ri = B[O_RI + l]
        rj = B[O_RJ + l]
        L2, inv_L, nx, ny, nz, delta = touching_pair(dx, dy, dz, ri, rj)
        a_i = ri - 0.5 * delta
        a_j = rj - 0.5 * delta
        wix = B[O_WIX + l]
        wiy = B[O_WIY + l]
        wiz = B[O_WIZ + l]
        wjx = B[O_WJX + l]
        wjy = B[O_WJY + l]
        wjz = B[O_WJZ + l]
        wsx = a_i * wix + a_j * wjx
        wsy = a_i * wiy + a_j * wjy
        wsz = a_i * wiz + a_j * wjz
        vx = B[O_DVX + l] + wsy * nz - wsz * ny
        vy = B[O_DVY + l] + wsz * nx - wsx * nz
        vz = B[O_DVZ + l] + wsx * ny - wsy * nx
        R_eff = ri * rj / (ri + rj)
        mi = B[O_MI + l]
        mj = B[O_MJ + l]
        m_eff = mi * mj / (mi + mj)
        cfx, cfy, cfz, F_n, hx, hy, hz = LAW(nx, ny, nz, delta, vx, vy, vz, R_eff, m_eff,
                                             tab, row, B[O_HX + l], B[O_HY + l],
                                             B[O_HZ + l], dt)
        B[O_HX + l] = hx
        B[O_HY + l] = hy
        B[O_HZ + l] = hz
        cx = ny * cfz - nz * cfy
        cy = nz * cfx - nx * cfz
        cz = nx * cfy - ny * cfx
        Mx = 0.0
        My = 0.0
        Mz = 0.0
        if ROLL_ON:
            Ii = B[O_II + l]
            Ij = B[O_IJ + l]
            Mx, My, Mz = ROLL(wix - wjx, wiy - wjy, wiz - wjz, R_eff, F_n, tab, row,
                              Ii * Ij / (Ii + Ij), dt)
        B[O_FX + l] = cfx
        B[O_FY + l] = cfy
        B[O_FZ + l] = cfz
        B[O_TIX + l] = a_i * cx + Mx
        B[O_TIY + l] = a_i * cy + My
        B[O_TIZ + l] = a_i * cz + Mz
        B[O_TJX + l] = a_j * cx - Mx
        B[O_TJY + l] = a_j * cy - My
        B[O_TJZ + l] = a_j * cz - Mz
        if HEAT_ON:
            B[O_Q + l] = (COND(pair_radius2(ri, rj, L2, inv_L), ri, rj, tab, row)
                          * (B[O_TJ + l] - B[O_TI + l]))


@njit(_nrt=False, forceinline=True)
def gather_row(i, row_i, P, pairs, B, lk, lj, lrow, n):
    """The pair candidates of row i into the batch from lane ``n`` on: the contact test
    (``pairs.active``; the spring of a contact that ended restarts), the touching pairs
    compacted without a branch (every candidate is written at lane n, which advances
    only for a touching one: about half of a dense bed's candidates touch, at random, a
    coin flip for a branch), then the inputs of the new lanes gathered.  Returns the next
    free lane; the caller leaves room for all candidates of the row."""
    x = P.x
    v = P.v
    w = P.omega
    hist = pairs.hist
    pact = pairs.active
    ri = P.radius[i]
    xi0 = x[i, 0]
    xi1 = x[i, 1]
    xi2 = x[i, 2]
    l0 = n
    for k in range(uint(pairs.start[i]), uint(pairs.start[i + 1])):
        j = uint(pairs.j[k])
        dx = x[j, 0] - xi0
        dy = x[j, 1] - xi1
        dz = x[j, 2] - xi2
        t = np.uint8(spheres_touch(dx * dx + dy * dy + dz * dz, ri + P.radius[j]))
        was = pact[k]
        pact[k] = t
        if was > t:
            hist[k, 0] = 0.0
            hist[k, 1] = 0.0
            hist[k, 2] = 0.0
        B[O_DX + n] = dx
        B[O_DY + n] = dy
        B[O_DZ + n] = dz
        lk[n] = k
        lj[n] = j
        n += uint(t)
    mi = P.mass[i]
    for l in range(l0, n):
        j = lj[l]
        k = lk[l]
        lrow[l] = row_i + P.type[j]
        B[O_RI + l] = ri
        B[O_RJ + l] = P.radius[j]
        B[O_MI + l] = mi
        B[O_MJ + l] = P.mass[j]
        B[O_DVX + l] = v[i, 0] - v[j, 0]
        B[O_DVY + l] = v[i, 1] - v[j, 1]
        B[O_DVZ + l] = v[i, 2] - v[j, 2]
        B[O_WIX + l] = w[i, 0]
        B[O_WIY + l] = w[i, 1]
        B[O_WIZ + l] = w[i, 2]
        B[O_WJX + l] = w[j, 0]
        B[O_WJY + l] = w[j, 1]
        B[O_WJZ + l] = w[j, 2]
        B[O_HX + l] = hist[k, 0]
        B[O_HY + l] = hist[k, 1]
        B[O_HZ + l] = hist[k, 2]
        if ROLL_ON:
            B[O_II + l] = P.inertia[i]
            B[O_IJ + l] = P.inertia[j]
        if HEAT_ON:
            B[O_TI + l] = P.T[i]
            B[O_TJ + l] = P.T[j]
    return n


@njit(_nrt=False, forceinline=True)
def finish_row(i, sl, fx, fy, fz, tx, ty, tz, qi, nc, P, pairs, pl, M, wc, plh, tab, row_i,
               dt, pl_acc):
    """The wall contacts of row i after its pair contacts (sums ``fx`` .. ``nc``), then
    all its sums added to the particle."""
    # most particles have no plane and no triangle candidate: the calls are made only
    # for those that have one (with the reference counts numba kept in these calls
    # before they were compiled _nrt=False, the unguarded plane call cost 2.45 ms
    # per pass on the 5,000-particle drum with no plane at all, 1 thread; 0.64 ms
    # guarded)
    if wc.plane_cand[i] != 0:
        px, py, pz, ptx, pty, ptz, pq, pn = plane_contacts(i, sl, P, pl, wc, plh, tab,
                                                           row_i, dt, pl_acc)
        fx += px
        fy += py
        fz += pz
        tx += ptx
        ty += pty
        tz += ptz
        qi += pq
        nc += pn
    if pairs.tri_start[i + 1] > pairs.tri_start[i] or wc.count[i] > 0:
        px, py, pz, ptx, pty, ptz, pq, pn = triangle_contacts(i, P, pairs, M, wc, tab,
                                                              row_i, dt)
        fx += px
        fy += py
        fz += pz
        tx += ptx
        ty += pty
        tz += ptz
        qi += pq
        nc += pn
    P.ncontact[i] += nc
    P.force[i, 0] += fx
    P.force[i, 1] += fy
    P.force[i, 2] += fz
    P.torque[i, 0] += tx
    P.torque[i, 1] += ty
    P.torque[i, 2] += tz
    if HEAT_ON:
        P.q[i] += qi


@njit(_nrt=False, forceinline=True)
def finish_batch(nrow, brow, blane, n, B, lk, lj, lrow, sl, P, pairs, pl, M, wc, plh, tab,
                 nt, dt, pl_acc):
    """The laws of the batch's ``n`` lanes (runs of one pair-table row each), then its
    ``nrow`` rows in order: each pair added to both particles as in :func:`pair_contacts`,
    its spring stored, then :func:`finish_row`."""
    # Two call sites of batch_laws (the first run, then the others), so that LLVM does
    # not inline it here: inlined, the force pass was 2.86 ms instead of 2.11 (engine_ab,
    # one thread).  A one-type simulation has one run.
    l1 = uint(1)
    while l1 < n and lrow[l1] == lrow[0]:
        l1 += uint(1)
    if n > 0:
        batch_laws(uint(0), l1, B, tab, lrow[0], dt)
    l0 = l1
    while l0 < n:
        l1 = l0 + uint(1)
        while l1 < n and lrow[l1] == lrow[l0]:
            l1 += uint(1)
        batch_laws(l0, l1, B, tab, lrow[l0], dt)
        l0 = l1
    f = P.force
    tq = P.torque
    hist = pairs.hist
    for b in range(nrow):
        i = brow[b]
        fx = 0.0
        fy = 0.0
        fz = 0.0
        tx = 0.0
        ty = 0.0
        tz = 0.0
        qi = 0.0
        nc = 0
        for l in range(blane[b], blane[b + 1]):
            j = lj[l]
            k = lk[l]
            cfx = B[O_FX + l]
            cfy = B[O_FY + l]
            cfz = B[O_FZ + l]
            fx += cfx
            fy += cfy
            fz += cfz
            tx += B[O_TIX + l]
            ty += B[O_TIY + l]
            tz += B[O_TIZ + l]
            f[j, 0] -= cfx
            f[j, 1] -= cfy
            f[j, 2] -= cfz
            tq[j, 0] += B[O_TJX + l]
            tq[j, 1] += B[O_TJY + l]
            tq[j, 2] += B[O_TJZ + l]
            P.ncontact[j] += 1
            nc += 1
            hist[k, 0] = B[O_HX + l]
            hist[k, 1] = B[O_HY + l]
            hist[k, 2] = B[O_HZ + l]
            if HEAT_ON:
                Qp = B[O_Q + l]
                qi += Qp
                P.q[j] -= Qp
        finish_row(i, sl, fx, fy, fz, tx, ty, tz, qi, nc, P, pairs, pl, M, wc, plh, tab,
                   P.type[i] * nt, dt, pl_acc)


@njit
def slab_task(sl, colour, mode, dt, Pt, pairst, plt, Mt, wct, plh, tab, nt, pl_acc, gx, gy,
              gz, lo, hi, vmax2, scan_out):
    """One task of :func:`contact_forces`: the contacts of the particles of slab
    ``sl`` (pairs, planes, triangles), then, for the second colour, the integration of
    the slabs this task completes (see :func:`contact_forces`).

    The pair contacts run in batches of up to :data:`CH` lanes (:func:`gather_row`,
    :func:`batch_laws`, :func:`finish_batch`); a row with more than CH candidates (a
    large sphere among small ones) runs :func:`pair_contacts` on its own.

    A plain (not parallel) function called from the ``prange`` loop: the parfor passes
    then see one call.  The bundles arrive as plain tuples (see :mod:`gsi.dem.state`)
    and are named here.
    """
    P = Particles(*Pt)
    pairs = Pairs(*pairst)
    pl = Planes(*plt)
    M = Mesh(*Mt)
    wc = WallContacts(*wct)
    B = np.empty(NB * CH)
    lk = np.empty(CH, np.uint64)        # lane -> pair row (pairs.j, pairs.hist)
    lj = np.empty(CH, np.uint64)        # lane -> partner j
    lrow = np.empty(CH, np.int64)       # lane -> pair-table row
    brow = np.empty(CH, np.int64)       # batch row -> particle i
    blane = np.zeros(CH + 1, np.uint64)  # batch row -> its first lane
    n = uint(0)
    nrow = 0
    for m in range(pairs.slab_start[sl], pairs.slab_start[sl + 1]):
        i = pairs.slab_list[m]
        ncand = uint(pairs.start[i + 1] - pairs.start[i])
        if n + ncand > CH or nrow == CH:
            finish_batch(nrow, brow, blane, n, B, lk, lj, lrow, sl, P, pairs, pl, M, wc,
                         plh, tab, nt, dt, pl_acc)
            n = uint(0)
            nrow = 0
        row_i = P.type[i] * nt
        if ncand > CH:
            fx, fy, fz, tx, ty, tz, qi, nc = pair_contacts(i, P, pairs, tab, row_i, dt)
            finish_row(i, sl, fx, fy, fz, tx, ty, tz, qi, nc, P, pairs, pl, M, wc, plh,
                       tab, row_i, dt, pl_acc)
            continue
        n = gather_row(i, row_i, P, pairs, B, lk, lj, lrow, n)
        brow[nrow] = i
        nrow += 1
        blane[nrow] = n
    finish_batch(nrow, brow, blane, n, B, lk, lj, lrow, sl, P, pairs, pl, M, wc, plh, tab,
                 nt, dt, pl_acc)
    if colour == 1 and mode > 0:
        nslab = pairs.slab_start.shape[0] - 1
        m0 = pairs.slab_start[0] if sl == 1 else pairs.slab_start[sl]
        m1 = pairs.slab_start[min(sl + 2, nslab)]
        dm, no, bd = integrate_rows(m0, m1, pairs.slab_list, mode, HEAT_ON, 0.5 * dt, dt,
                                    gx, gy, gz, P, lo, hi, vmax2)
        scan_out[sl, 0] = dm
        scan_out[sl, 1] = no
        scan_out[sl, 2] = bd


@pjit
def contact_forces(mode, dt, P, pairs, pl, M, wc, table, pl_acc, gx, gy, gz, lo, hi, vmax2,
                   scan_out):
    """Add all contact forces, torques and heat rates to P.force, P.torque, P.q (cleared
    before), and (``mode`` 1 or 2) integrate each particle as soon as its forces are
    complete.

    Pairs (half list; a pair is stored at the particle of the lower slab): the law is
    evaluated once per pair and added to both particles (Newton's third law).  The
    slabs (at least one cutoff wide) are processed in two colours, even then odd, in
    parallel within a colour: a particle of slab s writes only to slabs s and s + 1,
    so no two threads write the same particle.

    Integration in the same pass (``mode`` 0: none, the forces only; 1: the second half
    kick; 2: that kick, then the next step's kick, drift and clear, see
    :func:`gsi.dem.integrate.integrate_rows`): slab s receives forces only from slabs
    s - 1 and s, so once the task of odd slab s (second colour) has run, slabs s and
    s + 1 are complete, and only this task reads them in that colour; it integrates
    them at once (the task of slab 1 also slab 0).  This leaves two parallel regions
    per step.  ``scan_out[s]`` gets the scan of the particles the task of slab s
    integrated (mode 2).
    """
    nt = table.shape[0]
    tab = table.reshape((nt * nt, table.shape[2]))
    plh = wc.plane_hist.reshape((P.x.shape[0] * pl.point.shape[0], 3))
    nslab = pairs.slab_start.shape[0] - 1
    # the bundles cross the prange as plain tuples (see gsi.dem.state)
    Pt = as_tuple(P)
    pairst = as_tuple(pairs)
    plt = as_tuple(pl)
    Mt = as_tuple(M)
    wct = as_tuple(wc)
    for colour in range(2):
        for si in prange((nslab - colour + 1) // 2):
            slab_task(2 * si + colour, colour, mode, dt, Pt, pairst, plt, Mt, wct, plh, tab,
                      nt, pl_acc, gx, gy, gz, lo, hi, vmax2, scan_out)
    if nslab == 1 and mode > 0:        # no second colour: the one slab is complete now
        dm, no, bd = integrate_rows(0, P.x.shape[0], pairs.slab_list, mode, HEAT_ON,
                                    0.5 * dt, dt, gx, gy, gz, P, lo, hi, vmax2)
        scan_out[0, 0] = dm
        scan_out[0, 1] = no
        scan_out[0, 2] = bd


@njit
def advance(nsteps, skip_first_drift, dt, g, half_skin2, vmax2, lo, hi, P, pairs, pl, M, wc,
            table, lg):
    """Run up to ``nsteps`` steps; stop early when the caller must act.

    Each step is the force pass (:func:`contact_forces`, which also ends this step and,
    unless it is the last one, starts the next: kick, drift, clear, scan), then the
    serial wall sums and the wall motion.  ``lg`` is the contact log's
    :data:`gsi.dem.contact_log.LogState` (read only by a ``LOG_ON`` engine: the step
    ``lg.ctrl[C_STEP] + s + 1 == lg.ctrl[C_NEXT]`` is sampled).

    Returns ``(steps_done, code, info)``: code 0 all done; 1 a rebuild is needed
    (the step ``steps_done`` has drifted; resume it with ``skip_first_drift``);
    2 ``info`` particles left the domain (same resume); 3 particle ``info`` blew up
    (NaN or speed above sqrt(vmax2)) at step ``steps_done``; 4 (``LOG_ON``) the log has
    no room for the sample of step ``steps_done``, which is complete and not drifted:
    grow the log, sample, resume without ``skip_first_drift``.
    """
    half_dt = 0.5 * dt
    npl = pl.point.shape[0]
    nv = M.x.shape[0]
    nslab = pairs.slab_start.shape[0] - 1
    pl_acc = np.zeros((nslab, npl, 7))
    scan_out = np.zeros((nslab, 3))
    if skip_first_drift:
        clear_forces(P, g[0], g[1], g[2])
    else:
        initial_integrate(P, half_dt, dt, g[0], g[1], g[2])
        wd2 = move_walls(dt, pl, M)
        d2, nout, bad = scan(P, lo, hi, vmax2)
        code, info = verdict(d2, wd2, nout, bad, half_skin2)
        if code != 0:
            return 0, code, info
    for s in range(nsteps):
        mode = 1 if s == nsteps - 1 else 2
        sampled = False
        if LOG_ON:
            if lg.ctrl[C_STEP] + s + 1 == lg.ctrl[C_NEXT]:
                sampled = True
                mode = 1
        scan_out[:, 0] = 0.0
        scan_out[:, 1] = 0.0
        scan_out[:, 2] = -1.0
        contact_forces(mode, dt, P, pairs, pl, M, wc, table, pl_acc, g[0], g[1], g[2], lo,
                       hi, vmax2, scan_out)
        if npl > 0:
            plane_sums(dt, pl_acc, pl)
        if nv > 0:
            mesh_scatter(dt, wc, M)
        if LOG_ON:
            if sampled:
                if not has_room(P, pairs, wc, lg):
                    return s + 1, 4, 0
                sample(P, pairs, pl, M, wc, lg)
                if s < nsteps - 1:
                    # the next step's drift, as at the start of a call
                    initial_integrate(P, half_dt, dt, g[0], g[1], g[2])
                    wd2 = move_walls(dt, pl, M)
                    d2, nout, bad = scan(P, lo, hi, vmax2)
                    code, info = verdict(d2, wd2, nout, bad, half_skin2)
                    if code != 0:
                        return s + 1, code, info
                continue
        if mode == 2:
            # the next step has drifted: its walls move, then the scan decides
            wd2 = move_walls(dt, pl, M)
            d2, nout, bad = reduce_scans(scan_out)
            code, info = verdict(d2, wd2, nout, bad, half_skin2)
            if code != 0:
                return s + 1, code, info
    return nsteps, 0, 0


@njit
def compute_forces(g, P, pairs, pl, M, wc, table):
    """Forces, torques and contact springs' rotation at the current state, no motion,
    no heat update (dt = 0): the start of a run and after external changes."""
    nslab = pairs.slab_start.shape[0] - 1
    clear_forces(P, g[0], g[1], g[2])
    contact_forces(0, 0.0, P, pairs, pl, M, wc, table, np.zeros((nslab, pl.point.shape[0], 7)),
                   g[0], g[1], g[2], g, g, 0.0, np.zeros((nslab, 3)))


@njit
def heat_conductance_sum(P, pairs, pl, M, wc, table):
    """Per particle sum_j H_ij (W/K) over touching pairs and walls with a temperature
    (triangle contacts as found at the last step), with the contact radius of
    :mod:`gsi.dem.contact_geometry`."""
    x = P.x
    n = x.shape[0]
    nt = table.shape[0]
    tab = table.reshape((nt * nt, table.shape[2]))
    Hs = np.zeros(n)
    for i in range(n):
        ri = P.radius[i]
        row_i = P.type[i] * nt
        for k in range(pairs.start[i], pairs.start[i + 1]):
            j = pairs.j[k]
            rj = P.radius[j]
            touch, L2, inv_L, nx, ny, nz, delta = sphere_pair(
                x[j, 0] - x[i, 0], x[j, 1] - x[i, 1], x[j, 2] - x[i, 2], ri, rj)
            if not touch:
                continue
            H = COND(pair_radius2(ri, rj, L2, inv_L), ri, rj, tab, row_i + P.type[j])
            Hs[i] += H
            Hs[j] += H
        for p in range(pl.point.shape[0]):
            if not pl.has_T[p]:
                continue
            dist = plane_distance(x[i, 0], x[i, 1], x[i, 2], pl.point[p, 0], pl.point[p, 1],
                                  pl.point[p, 2], pl.normal[p, 0], pl.normal[p, 1],
                                  pl.normal[p, 2])
            delta = ri - dist
            if delta > 0.0:
                Hs[i] += COND(wall_radius2(ri, delta), ri, math.inf, tab, row_i + pl.type[p])
        for s in range(wc.count[i]):
            wl = M.tri_wall[wc.tri[i, s]]
            if not M.wall_has_T[wl]:
                continue
            d2 = 0.0
            for d in range(3):
                d2 += (wc.point[i, s, d] - x[i, d]) ** 2
            delta = ri - math.sqrt(d2)
            if delta > 0.0:
                Hs[i] += COND(wall_radius2(ri, delta), ri, math.inf, tab, row_i + M.wall_type[wl])
    return Hs
