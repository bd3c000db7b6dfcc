"""The DEM step engine: one compiled module for every contact model.

The contact model is chosen at run time (:mod:`gsi.dem.contact.model`: a small integer
array names the normal, tangential, rolling and heat sub-models and the contact-log
switch), so the engine compiles once, is cached by numba like any module, and lives in
the repository.  :func:`get_engine` returns an :class:`Engine` bound to one model.

Every contact -- sphere pair, plane, mesh triangle -- goes through the same path:
its geometry is written into a lane of a buffer (:mod:`gsi.dem.contact.lanes`) by
:func:`gather_pairs` + :func:`pair_geometry` (pairs) or :func:`gather_walls` (planes and
triangles), then :func:`gsi.dem.contact.model.evaluate` runs the sub-models over the
lanes, then the results are added to the bodies (:func:`finish_pairs`,
:func:`finish_walls`).  There is one law evaluation per contact and no second path.

Arguments: the state bundles of :mod:`gsi.dem.state` -- ``P`` particles, ``pairs``
neighbour lists, ``pl`` planes, ``M`` mesh walls, ``wc`` wall contacts -- the pair table
``table`` (ntypes, ntypes, N_PAIR) (see :mod:`gsi.dem.materials`) and ``model``.

One DEM step (velocity Verlet, docs/design.md "DEM physics"):

1. v += dt/2 F/m, x += dt v, omega += dt/2 T/I, then F = m g, T = 0, Q = 0 for the
   new forces; walls move.
2. scan: largest displacement since the last neighbour build (rebuild when it
   exceeds skin/2), particles outside the domain, NaN or runaway velocities.
3. :func:`contact_forces` (parallel, two colours of slabs): every contact once, added to
   both bodies.
4. v += dt/2 F/m, omega += dt/2 T/I; T += dt Q/(m c_p).
5. serial sums of wall forces, torques and the coupling accumulators.

Steps 4 and the next step's 1-2 run inside :func:`contact_forces`, slab by slab as the
forces complete, so a step has two parallel regions; only the first step of a call to
:func:`advance` drifts on its own.  With the contact log on, a sampled step ends before
the next one drifts (same arithmetic, not fused) and the log samples its contacts.
"""
import math

import numpy as np

from gsi.jit import njit, pjit, prange, sqrt, uint
from gsi.dem.contact.lanes import (
    CH, NB, NX, NY, NZ, DELTA, VX, VY, VZ, REFF, MEFF, IEFF, WX, WY, WZ, A2, RI, RJ, DTEMP,
    HX, HY, HZ, FX, FY, FZ, MX, MY, MZ, Q, AI, AJ, MI, MJ, II, IJ, WIX, WIY, WIZ, TIX, TIY,
    TIZ, TJX, TJY, TJZ)
from gsi.dem.contact.model import (evaluate, evaluate_heat, model_ids, M_HEAT, M_LOG,
                                   NORMAL, ROLLING, HEAT)
from gsi.dem.contact_geometry import spheres_touch, wall_radius2, plane_distance
from gsi.dem.contact_log import C_NEXT, C_STEP, has_room, sample
from gsi.dem.integrate import (clear_forces, initial_integrate, scan, integrate_rows,
                               reduce_scans, verdict)
from gsi.dem.mesh_dedup import select_triangle_contacts
from gsi.dem.state import (Particles, Pairs, Planes, Mesh, WallContacts, as_tuple,
                           MAX_WALL_SLOTS)
from gsi.dem.wall_kernels import move_walls, plane_sums, mesh_scatter
from gsi.errors import GsiInputError

#: lane kinds of the wall buffer
PLANE, TRIANGLE = 0, 1


# ---- sphere pairs ----------------------------------------------------------------------

@njit(_nrt=False)
def gather_pairs(i, k0, k1, row_i, P, pairs, B, lk, lj, lrow, n):
    """Candidates k0..k1-1 of particle i into the batch from lane ``n`` on.

    The contact test (``pairs.active``; the spring of a contact that ended restarts), the
    touching pairs compacted without a branch (every candidate is written at lane n,
    which advances only for a touching one: about half of a dense bed's candidates
    touch, at random, a coin flip for a branch), then the inputs of the new lanes
    gathered.  Returns the next free lane; the caller leaves room for all candidates."""
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
    for k in range(uint(k0), uint(k1)):
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
        B[NX + n] = dx
        B[NY + n] = dy
        B[NZ + n] = dz
        lk[n] = k
        lj[n] = j
        n += uint(t)
    mi = P.mass[i]
    Ii = P.inertia[i]
    Ti = P.T[i]
    for l in range(l0, n):
        j = lj[l]
        k = lk[l]
        lrow[l] = row_i + P.type[j]
        B[RI + l] = ri
        B[RJ + l] = P.radius[j]
        B[MI + l] = mi
        B[MJ + l] = P.mass[j]
        B[II + l] = Ii
        B[IJ + l] = P.inertia[j]
        B[VX + l] = v[i, 0] - v[j, 0]
        B[VY + l] = v[i, 1] - v[j, 1]
        B[VZ + l] = v[i, 2] - v[j, 2]
        B[WIX + l] = w[i, 0]
        B[WIY + l] = w[i, 1]
        B[WIZ + l] = w[i, 2]
        B[WX + l] = w[j, 0]
        B[WY + l] = w[j, 1]
        B[WZ + l] = w[j, 2]
        B[DTEMP + l] = P.T[j] - Ti
        B[HX + l] = hist[k, 0]
        B[HY + l] = hist[k, 1]
        B[HZ + l] = hist[k, 2]
    return n


@njit(_nrt=False)
def pair_geometry(n, B):
    """The contact geometry of lanes 0..n-1 of touching sphere pairs, in place.

    In: the centre offset d = x_j - x_i (in ``NX..NZ``), radii, masses, inertias, v_i - v_j
    (in ``VX..VZ``), omega_i (``WIX..``), omega_j (in ``WX..``).  Out: the unit normal n
    from i to j, the overlap delta = R_i + R_j - L, the lever arms a_i = R_i - delta/2,
    a_j = R_j - delta/2, the velocity of i relative to j at the contact point
    v_i + omega_i x (a_i n) - v_j - omega_j x (-a_j n), R*, m*, I*, omega_i - omega_j and
    the squared contact radius a^2 = R_i^2 - ((R_i^2 - R_j^2 + L^2)/(2L))^2."""
    for l in range(uint(0), uint(n)):
        dx = B[NX + l]
        dy = B[NY + l]
        dz = B[NZ + l]
        ri = B[RI + l]
        rj = B[RJ + l]
        L2 = dx * dx + dy * dy + dz * dz
        L = sqrt(L2)
        inv_L = 1.0 / L
        nx = dx * inv_L
        ny = dy * inv_L
        nz = dz * inv_L
        delta = (ri + rj) - L
        a_i = ri - 0.5 * delta
        a_j = rj - 0.5 * delta
        wix = B[WIX + l]
        wiy = B[WIY + l]
        wiz = B[WIZ + l]
        wjx = B[WX + l]
        wjy = B[WY + l]
        wjz = B[WZ + l]
        wsx = a_i * wix + a_j * wjx
        wsy = a_i * wiy + a_j * wjy
        wsz = a_i * wiz + a_j * wjz
        B[VX + l] += wsy * nz - wsz * ny
        B[VY + l] += wsz * nx - wsx * nz
        B[VZ + l] += wsx * ny - wsy * nx
        B[WX + l] = wix - wjx
        B[WY + l] = wiy - wjy
        B[WZ + l] = wiz - wjz
        B[NX + l] = nx
        B[NY + l] = ny
        B[NZ + l] = nz
        B[DELTA + l] = delta
        B[AI + l] = a_i
        B[AJ + l] = a_j
        B[REFF + l] = ri * rj / (ri + rj)
        mi = B[MI + l]
        mj = B[MJ + l]
        B[MEFF + l] = mi * mj / (mi + mj)
        Ii = B[II + l]
        Ij = B[IJ + l]
        B[IEFF + l] = Ii * Ij / (Ii + Ij)
        s = (ri * ri - rj * rj + L2) * 0.5 * inv_L
        B[A2 + l] = ri * ri - s * s


@njit(_nrt=False)
def pair_torques(n, B):
    """Torques of lanes 0..n-1: a_i n x F + M_r on i, a_j n x F - M_r on j (F, M_r on i)."""
    for l in range(uint(0), uint(n)):
        nx = B[NX + l]
        ny = B[NY + l]
        nz = B[NZ + l]
        fx = B[FX + l]
        fy = B[FY + l]
        fz = B[FZ + l]
        cx = ny * fz - nz * fy
        cy = nz * fx - nx * fz
        cz = nx * fy - ny * fx
        a_i = B[AI + l]
        a_j = B[AJ + l]
        B[TIX + l] = a_i * cx + B[MX + l]
        B[TIY + l] = a_i * cy + B[MY + l]
        B[TIZ + l] = a_i * cz + B[MZ + l]
        B[TJX + l] = a_j * cx - B[MX + l]
        B[TJY + l] = a_j * cy - B[MY + l]
        B[TJZ + l] = a_j * cz - B[MZ + l]


@njit(_nrt=False)
def evaluate_runs(n, B, lrow, tab, dt, model):
    """:func:`gsi.dem.contact.model.evaluate` over lanes 0..n-1, one call per run of lanes
    that share a pair-table row (a loop-invariant row keeps the table reads out of the
    vectorizer's way; a one-type simulation has one run)."""
    l0 = uint(0)
    while l0 < n:
        l1 = l0 + uint(1)
        while l1 < n and lrow[l1] == lrow[l0]:
            l1 += uint(1)
        evaluate(l0, l1, B, tab, lrow[l0], dt, model)
        l0 = l1


@njit(_nrt=False)
def finish_pairs(nrow, brow, blane, n, B, lk, lj, lrow, P, pairs, tab, dt, model, heat_on):
    """The contact model over the batch's ``n`` pair lanes, then each of its ``nrow`` rows:
    its pairs added to both particles (Newton's third law), the springs stored."""
    pair_geometry(n, B)
    evaluate_runs(n, B, lrow, tab, dt, model)
    pair_torques(n, B)
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
        for l in range(blane[b], blane[b + 1]):
            j = lj[l]
            k = lk[l]
            cfx = B[FX + l]
            cfy = B[FY + l]
            cfz = B[FZ + l]
            fx += cfx
            fy += cfy
            fz += cfz
            tx += B[TIX + l]
            ty += B[TIY + l]
            tz += B[TIZ + l]
            f[j, 0] -= cfx
            f[j, 1] -= cfy
            f[j, 2] -= cfz
            tq[j, 0] += B[TJX + l]
            tq[j, 1] += B[TJY + l]
            tq[j, 2] += B[TJZ + l]
            P.ncontact[j] += 1
            hist[k, 0] = B[HX + l]
            hist[k, 1] = B[HY + l]
            hist[k, 2] = B[HZ + l]
            if heat_on:
                Qp = B[Q + l]
                qi += Qp
                P.q[j] -= Qp
        P.ncontact[i] += np.int32(blane[b + 1] - blane[b])
        f[i, 0] += fx
        f[i, 1] += fy
        f[i, 2] += fz
        tq[i, 0] += tx
        tq[i, 1] += ty
        tq[i, 2] += tz
        if heat_on:
            P.q[i] += qi


# ---- walls: planes and mesh triangles ----------------------------------------------------

@njit(_nrt=False)
def wall_lane(W, n, i, P, nx, ny, nz, lever, delta, wvx, wvy, wvz, dtemp, hx, hy, hz):
    """Write one particle-wall contact into lane ``n`` of the wall buffer: ``n`` the unit
    normal from the centre of i to the contact point at distance ``lever``, ``delta`` the
    overlap, ``wv`` the wall velocity there, ``dtemp`` = T_wall - T_i; the wall counts as
    infinitely large and heavy (R* = R_i, m* = m_i, I* = I_i, its rotation not included)."""
    ri = P.radius[i]
    w = P.omega
    W[NX + n] = nx
    W[NY + n] = ny
    W[NZ + n] = nz
    W[DELTA + n] = delta
    W[VX + n] = P.v[i, 0] - wvx + lever * (w[i, 1] * nz - w[i, 2] * ny)
    W[VY + n] = P.v[i, 1] - wvy + lever * (w[i, 2] * nx - w[i, 0] * nz)
    W[VZ + n] = P.v[i, 2] - wvz + lever * (w[i, 0] * ny - w[i, 1] * nx)
    W[REFF + n] = ri
    W[MEFF + n] = P.mass[i]
    W[IEFF + n] = P.inertia[i]
    W[WX + n] = w[i, 0]
    W[WY + n] = w[i, 1]
    W[WZ + n] = w[i, 2]
    W[A2 + n] = wall_radius2(ri, delta)
    W[RI + n] = ri
    W[RJ + n] = math.inf
    W[DTEMP + n] = dtemp
    W[HX + n] = hx
    W[HY + n] = hy
    W[HZ + n] = hz
    W[AI + n] = lever


@njit(_nrt=False)
def gather_walls(i, P, pairs, pl, M, wc, plh, W, wi, wkind, wk, wp, wrow, n, row_i):
    """The plane and triangle contacts of particle i into the wall buffer from lane ``n``.

    Planes: overlap delta = R - (x - p).N, contact normal -N, lever R - delta, wall
    velocity ``pl.velocity``; only the planes of ``wc.plane_cand[i]`` (within R + skin at
    the last neighbour build) are looked at; a contact that ends restarts its spring
    (``plh[i * npl + p]``).  Triangles: the closest points accepted by
    :func:`gsi.dem.mesh_dedup.select_triangle_contacts`; velocity and temperature at the
    point are the barycentric means of the vertex values.  Returns the next free lane."""
    ri = P.radius[i]
    Ti = P.T[i]
    xi0 = P.x[i, 0]
    xi1 = P.x[i, 1]
    xi2 = P.x[i, 2]
    cand = wc.plane_cand[i]
    if cand != 0:
        npl = pl.point.shape[0]
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
            pmask |= 1 << p
            dtemp = pl.T[p] - Ti if pl.has_T[p] else 0.0
            wall_lane(W, n, i, P, -Nx, -Ny, -Nz, dist, delta, pl.velocity[p, 0],
                      pl.velocity[p, 1], pl.velocity[p, 2], dtemp, plh[base + p, 0],
                      plh[base + p, 1], plh[base + p, 2])
            wi[n] = i
            wkind[n] = PLANE
            wk[n] = base + p
            wp[n] = p
            wrow[n] = row_i + pl.type[p]
            n += uint(1)
        wc.plane_mask[i] = pmask
    if pairs.tri_start[i + 1] > pairs.tri_start[i] or wc.count[i] > 0:
        ns = select_triangle_contacts(i, xi0, xi1, xi2, ri, pairs, M, wc)
        wc.count[i] = ns
        mv = M.v
        for s in range(ns):
            t = wc.tri[i, s]
            ddx = wc.point[i, s, 0] - xi0
            ddy = wc.point[i, s, 1] - xi1
            ddz = wc.point[i, s, 2] - xi2
            dist = math.sqrt(ddx * ddx + ddy * ddy + ddz * ddz)
            a = M.tri[t, 0]
            b = M.tri[t, 1]
            c = M.tri[t, 2]
            wa = wc.weight[i, s, 0]
            wb = wc.weight[i, s, 1]
            wcc = wc.weight[i, s, 2]
            wl = M.tri_wall[t]
            dtemp = 0.0
            if M.wall_has_T[wl]:
                dtemp = wa * M.T[a] + wb * M.T[b] + wcc * M.T[c] - Ti
            k = wc.cand[i, s]
            wall_lane(W, n, i, P, ddx / dist, ddy / dist, ddz / dist, dist, ri - dist,
                      wa * mv[a, 0] + wb * mv[b, 0] + wcc * mv[c, 0],
                      wa * mv[a, 1] + wb * mv[b, 1] + wcc * mv[c, 1],
                      wa * mv[a, 2] + wb * mv[b, 2] + wcc * mv[c, 2], dtemp,
                      pairs.tri_hist[k, 0], pairs.tri_hist[k, 1], pairs.tri_hist[k, 2])
            wi[n] = i
            wkind[n] = TRIANGLE
            wk[n] = k
            wp[n] = s
            wrow[n] = row_i + M.wall_type[wl]
            n += uint(1)
    return n


@njit(_nrt=False)
def finish_walls(n, W, wi, wkind, wk, wp, wrow, sl, P, pairs, pl, M, wc, plh, tab, dt, model,
                 heat_on, pl_acc):
    """The contact model over the ``n`` wall lanes, then each contact added to its particle
    (force, torque lever n x F + M_r, heat, contact count), the springs stored, and the
    wall's share kept: the plane sums of slab ``sl`` in ``pl_acc[sl, p]`` (force, moment
    about the plane's point at the contact point, heat; see
    :func:`gsi.dem.wall_kernels.plane_sums`), the triangle slots in ``wc.force``,
    ``wc.heat`` (see :func:`gsi.dem.wall_kernels.mesh_scatter`)."""
    evaluate_runs(n, W, wrow, tab, dt, model)
    for l in range(n):
        i = wi[l]
        nx = W[NX + l]
        ny = W[NY + l]
        nz = W[NZ + l]
        fx = W[FX + l]
        fy = W[FY + l]
        fz = W[FZ + l]
        lever = W[AI + l]
        k = wk[l]
        p = wp[l]
        Qw = 0.0
        if heat_on:
            Qw = W[Q + l]
        if wkind[l] == PLANE:
            plh[k, 0] = W[HX + l]
            plh[k, 1] = W[HY + l]
            plh[k, 2] = W[HZ + l]
            if not pl.has_T[p]:
                Qw = 0.0
            rx = P.x[i, 0] + lever * nx - pl.point[p, 0]
            ry = P.x[i, 1] + lever * ny - pl.point[p, 1]
            rz = P.x[i, 2] + lever * nz - pl.point[p, 2]
            pl_acc[sl, p, 0] += fx
            pl_acc[sl, p, 1] += fy
            pl_acc[sl, p, 2] += fz
            pl_acc[sl, p, 3] += ry * fz - rz * fy
            pl_acc[sl, p, 4] += rz * fx - rx * fz
            pl_acc[sl, p, 5] += rx * fy - ry * fx
            pl_acc[sl, p, 6] += Qw
        else:
            pairs.tri_hist[k, 0] = W[HX + l]
            pairs.tri_hist[k, 1] = W[HY + l]
            pairs.tri_hist[k, 2] = W[HZ + l]
            if not M.wall_has_T[M.tri_wall[wc.tri[i, p]]]:
                Qw = 0.0
            wc.force[i, p, 0] = fx
            wc.force[i, p, 1] = fy
            wc.force[i, p, 2] = fz
            wc.heat[i, p] = Qw
        P.force[i, 0] += fx
        P.force[i, 1] += fy
        P.force[i, 2] += fz
        P.torque[i, 0] += lever * (ny * fz - nz * fy) + W[MX + l]
        P.torque[i, 1] += lever * (nz * fx - nx * fz) + W[MY + l]
        P.torque[i, 2] += lever * (nx * fy - ny * fx) + W[MZ + l]
        P.ncontact[i] += 1
        if heat_on:
            P.q[i] += Qw


@njit(_nrt=False)
def plane_count(cand):
    """Number of set bits of a plane-candidate mask."""
    c = 0
    while cand != 0:
        cand &= cand - 1
        c += 1
    return c


# ---- the force pass ----------------------------------------------------------------------

@njit
def slab_task(sl, colour, mode, dt, Pt, pairst, plt, Mt, wct, plh, tab, nt, model, pl_acc,
              gx, gy, gz, lo, hi, vmax2, scan_out):
    """One task of :func:`contact_forces`: the contacts of the particles of slab ``sl``
    (pairs, planes, triangles) in batches of up to :data:`CH` lanes, then, for the second
    colour, the integration of the slabs this task completes (see :func:`contact_forces`).

    A plain (not parallel) function called from the ``prange`` loop; the bundles arrive
    as plain tuples (see :mod:`gsi.dem.state`) and are named here."""
    P = Particles(*Pt)
    pairs = Pairs(*pairst)
    pl = Planes(*plt)
    M = Mesh(*Mt)
    wc = WallContacts(*wct)
    heat_on = model[M_HEAT] != 0
    # pair batch: lanes, lane -> pair row, partner, table row; batch rows and their lanes
    B = np.empty(NB * CH)
    lk = np.empty(CH, np.uint64)
    lj = np.empty(CH, np.uint64)
    lrow = np.empty(CH, np.int64)
    brow = np.empty(CH, np.int64)
    blane = np.zeros(CH + 1, np.uint64)
    # wall batch: lanes, lane -> particle, kind, spring row, plane or slot, table row
    W = np.empty(NB * CH)
    wi = np.empty(CH, np.int64)
    wkind = np.empty(CH, np.int64)
    wk = np.empty(CH, np.int64)
    wp = np.empty(CH, np.int64)
    wrow = np.empty(CH, np.int64)
    n = uint(0)
    nrow = 0
    nw = uint(0)
    for m in range(pairs.slab_start[sl], pairs.slab_start[sl + 1]):
        i = pairs.slab_list[m]
        row_i = P.type[i] * nt
        k0 = uint(pairs.start[i])
        k_end = uint(pairs.start[i + 1])
        while k0 < k_end:              # a row longer than the room left spans batches
            if n == uint(CH) or nrow == CH:
                finish_pairs(nrow, brow, blane, n, B, lk, lj, lrow, P, pairs, tab, dt,
                             model, heat_on)
                n = uint(0)
                nrow = 0
            k1 = min(k_end, k0 + (uint(CH) - n))
            n = gather_pairs(i, k0, k1, row_i, P, pairs, B, lk, lj, lrow, n)
            brow[nrow] = i
            nrow += 1
            blane[nrow] = n
            k0 = k1
        if wc.plane_cand[i] != 0 or pairs.tri_start[i + 1] > pairs.tri_start[i] \
                or wc.count[i] > 0:
            if nw + uint(plane_count(wc.plane_cand[i]) + MAX_WALL_SLOTS) > uint(CH):
                finish_walls(nw, W, wi, wkind, wk, wp, wrow, sl, P, pairs, pl, M, wc, plh,
                             tab, dt, model, heat_on, pl_acc)
                nw = uint(0)
            nw = gather_walls(i, P, pairs, pl, M, wc, plh, W, wi, wkind, wk, wp, wrow, nw,
                              row_i)
    finish_pairs(nrow, brow, blane, n, B, lk, lj, lrow, P, pairs, tab, dt, model, heat_on)
    finish_walls(nw, W, wi, wkind, wk, wp, wrow, sl, P, pairs, pl, M, wc, plh, tab, dt, model,
                 heat_on, pl_acc)
    if colour == 1 and mode > 0:
        nslab = pairs.slab_start.shape[0] - 1
        m0 = pairs.slab_start[0] if sl == 1 else pairs.slab_start[sl]
        m1 = pairs.slab_start[min(sl + 2, nslab)]
        dm, no, bd = integrate_rows(m0, m1, pairs.slab_list, mode, heat_on, 0.5 * dt, dt,
                                    gx, gy, gz, P, lo, hi, vmax2)
        scan_out[sl, 0] = dm
        scan_out[sl, 1] = no
        scan_out[sl, 2] = bd


@pjit
def contact_forces(mode, dt, P, pairs, pl, M, wc, table, model, pl_acc, gx, gy, gz, lo, hi,
                   vmax2, scan_out):
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
                      nt, model, pl_acc, gx, gy, gz, lo, hi, vmax2, scan_out)
    if nslab == 1 and mode > 0:        # no second colour: the one slab is complete now
        dm, no, bd = integrate_rows(pairs.slab_start[0], P.x.shape[0], pairs.slab_list, mode,
                                    model[M_HEAT] != 0, 0.5 * dt, dt, gx, gy, gz, P, lo, hi,
                                    vmax2)
        scan_out[0, 0] = dm
        scan_out[0, 1] = no
        scan_out[0, 2] = bd


@njit
def advance(nsteps, skip_first_drift, dt, g, half_skin2, vmax2, lo, hi, P, pairs, pl, M, wc,
            table, lg, model):
    """Run up to ``nsteps`` steps; stop early when the caller must act.

    Each step is the force pass (:func:`contact_forces`, which also ends this step and,
    unless it is the last one, starts the next: kick, drift, clear, scan), then the
    serial wall sums and the wall motion.  ``lg`` is the contact log's
    :data:`gsi.dem.contact_log.LogState` (read only when the model's log switch is on:
    the step ``lg.ctrl[C_STEP] + s + 1 == lg.ctrl[C_NEXT]`` is sampled).

    Returns ``(steps_done, code, info)``: code 0 all done; 1 a rebuild is needed
    (the step ``steps_done`` has drifted; resume it with ``skip_first_drift``);
    2 ``info`` particles left the domain (same resume); 3 particle ``info`` blew up
    (NaN or speed above sqrt(vmax2)) at step ``steps_done``; 4 (log on) the log has
    no room for the sample of step ``steps_done``, which is complete and not drifted:
    grow the log, sample, resume without ``skip_first_drift``.
    """
    half_dt = 0.5 * dt
    log_on = model[M_LOG] != 0
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
        if log_on:
            if lg.ctrl[C_STEP] + s + 1 == lg.ctrl[C_NEXT]:
                sampled = True
                mode = 1
        scan_out[:, 0] = 0.0
        scan_out[:, 1] = 0.0
        scan_out[:, 2] = -1.0
        contact_forces(mode, dt, P, pairs, pl, M, wc, table, model, pl_acc, g[0], g[1], g[2],
                       lo, hi, vmax2, scan_out)
        if npl > 0:
            plane_sums(dt, pl_acc, pl)
        if nv > 0:
            mesh_scatter(dt, wc, M)
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
def compute_forces(g, P, pairs, pl, M, wc, table, model):
    """Forces, torques and contact springs' rotation at the current state, no motion,
    no heat update (dt = 0): the start of a run and after external changes."""
    nslab = pairs.slab_start.shape[0] - 1
    clear_forces(P, g[0], g[1], g[2])
    # mode 0 as a run-time value: a literal 0 would compile a second copy of the force
    # pass (numba specializes a callee on literal arguments)
    mode = pairs.slab_start[0]
    contact_forces(mode, 0.0, P, pairs, pl, M, wc, table, model,
                   np.zeros((nslab, pl.point.shape[0], 7)), g[0], g[1], g[2], g, g, 0.0,
                   np.zeros((nslab, 3)))


@njit
def heat_conductance_sum(P, pairs, pl, M, wc, table, model):
    """Per particle sum_j H_ij (W/K) over touching pairs and walls with a temperature
    (triangle contacts as found at the last step): the heat sub-model of the contact
    model over lanes of the same geometry as the force pass (``DTEMP`` = 1 K)."""
    x = P.x
    n = x.shape[0]
    nt = table.shape[0]
    tab = table.reshape((nt * nt, table.shape[2]))
    Hs = np.zeros(n)
    B = np.zeros(NB * CH)
    lj = np.empty(CH, np.int64)
    for i in range(n):
        ri = P.radius[i]
        row_i = P.type[i] * nt
        for k0 in range(pairs.start[i], pairs.start[i + 1], CH):
            k1 = min(k0 + CH, pairs.start[i + 1])
            m = 0
            for k in range(k0, k1):
                j = pairs.j[k]
                rj = P.radius[j]
                dx = x[j, 0] - x[i, 0]
                dy = x[j, 1] - x[i, 1]
                dz = x[j, 2] - x[i, 2]
                L2 = dx * dx + dy * dy + dz * dz
                if not spheres_touch(L2, ri + rj):
                    continue
                inv_L = 1.0 / math.sqrt(L2)
                s = (ri * ri - rj * rj + L2) * 0.5 * inv_L
                B[A2 + m] = ri * ri - s * s
                B[RI + m] = ri
                B[RJ + m] = rj
                B[DTEMP + m] = 1.0
                lj[m] = j
                m += 1
            # runs of one table row
            l0 = 0
            while l0 < m:
                row = row_i + P.type[lj[l0]]
                l1 = l0 + 1
                while l1 < m and row_i + P.type[lj[l1]] == row:
                    l1 += 1
                evaluate_heat(l0, l1, B, tab, row, model)
                l0 = l1
            for l in range(m):
                Hs[i] += B[Q + l]
                Hs[lj[l]] += B[Q + l]
        for p in range(pl.point.shape[0]):
            if not pl.has_T[p]:
                continue
            dist = plane_distance(x[i, 0], x[i, 1], x[i, 2], pl.point[p, 0], pl.point[p, 1],
                                  pl.point[p, 2], pl.normal[p, 0], pl.normal[p, 1],
                                  pl.normal[p, 2])
            delta = ri - dist
            if delta > 0.0:
                Hs[i] += _wall_conductance(B, ri, delta, tab, row_i + pl.type[p], model)
        for s in range(wc.count[i]):
            wl = M.tri_wall[wc.tri[i, s]]
            if not M.wall_has_T[wl]:
                continue
            d2 = 0.0
            for d in range(3):
                d2 += (wc.point[i, s, d] - x[i, d]) ** 2
            delta = ri - math.sqrt(d2)
            if delta > 0.0:
                Hs[i] += _wall_conductance(B, ri, delta, tab, row_i + M.wall_type[wl], model)
    return Hs


@njit
def _wall_conductance(B, ri, delta, tab, row, model):
    """H (W/K) of one sphere-wall contact by the model's heat sub-model (lane 0 of B)."""
    B[A2] = wall_radius2(ri, delta)
    B[RI] = ri
    B[RJ] = math.inf
    B[DTEMP] = 1.0
    evaluate_heat(0, 1, B, tab, row, model)
    return B[Q]


# ---- the engine object ----------------------------------------------------------------------

class Engine:
    """The compiled engine bound to one contact model (:func:`get_engine`).

    Its methods take the same arguments as the kernels :func:`advance`,
    :func:`compute_forces` and :func:`heat_conductance_sum`, without ``model``.
    """

    def __init__(self, model):
        self.model = model
        self.heat_on = bool(model[M_HEAT] != 0)

    def advance(self, nsteps, skip_first_drift, dt, g, half_skin2, vmax2, lo, hi, P, pairs,
                pl, M, wc, table, lg):
        """Run up to ``nsteps`` steps (see :func:`advance`)."""
        return advance(nsteps, skip_first_drift, dt, g, half_skin2, vmax2, lo, hi, P, pairs,
                       pl, M, wc, table, lg, self.model)

    def compute_forces(self, g, P, pairs, pl, M, wc, table):
        """Forces at the current state (see :func:`compute_forces`)."""
        compute_forces(g, P, pairs, pl, M, wc, table, self.model)

    def heat_conductance_sum(self, P, pairs, pl, M, wc, table):
        """Per-particle conductance sums (see :func:`heat_conductance_sum`)."""
        return heat_conductance_sum(P, pairs, pl, M, wc, table, self.model)


def get_engine(contact="hertz", rolling=False, heat=None, log=False):
    """The engine for a contact law, rolling law and heat model (by registry name), with
    or without the contact log: the one compiled engine bound to these sub-models.

    Parameters
    ----------
    contact : str
        Normal sub-model, a key of :data:`gsi.dem.contact.model.NORMAL` ("hertz", "linear").
    rolling : bool or str
        Rolling sub-model: False/"none", True/"cdt" (:data:`gsi.dem.contact.model.ROLLING`).
    heat : str or None
        Heat sub-model, a key of :data:`gsi.dem.contact.model.HEAT` (None, "area",
        "radius", "constant", "pipe").
    log : bool
        Sample contacts into the contact log (:mod:`gsi.dem.contact_log`).
    """
    if contact not in NORMAL:
        raise GsiInputError(f"contact = {contact!r}: must be one of {sorted(NORMAL)}")
    if rolling not in (False, True, None) and rolling not in ROLLING:
        raise GsiInputError(f"rolling = {rolling!r}: must be false, true or 'cdt'")
    if heat is not None and heat not in HEAT:
        raise GsiInputError(
            f"heat = {heat!r}: must be one of None, 'area', 'radius', 'constant', 'pipe'")
    return Engine(model_ids(contact, "history", rolling, heat, log))
