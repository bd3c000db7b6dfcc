"""Plane and mesh-triangle contacts in lanes: the wall path of the engine.

A wall contact's geometry (normal, overlap, lever, the wall's velocity and temperature at
the contact point) is written into a lane by :func:`gather_planes` or
:func:`gather_triangles`, with R* = R_i,
m* = m_i, I* = I_i (a wall is infinitely large and heavy); the same contact model as for
pairs runs over the lanes (:func:`gsi.dem.pair_lanes.evaluate_runs`), and
:func:`finish_walls` adds each contact to its particle and keeps the wall's share for the
wall sums and the coupling (:mod:`gsi.dem.wall_kernels`).
"""
import math

import numpy as np

from gsi.jit import njit, uint
from gsi.dem.contact.lanes import (NX, NY, NZ, DELTA, VX, VY, VZ, REFF, MEFF, IEFF, WX, WY,
                                   WZ, A2, RI, RJ, DTEMP, HX, HY, HZ, FX, FY, FZ, MX, MY, MZ,
                                   Q, AI, QF)
from gsi.dem.contact_geometry import wall_radius2, plane_distance
from gsi.dem.mesh_dedup import select_triangle_contacts
from gsi.dem.pair_lanes import evaluate_runs, dissipative_impulse
from gsi.dem.contact.model import evaluate_dissipation

#: lane kinds of the wall buffer
PLANE, TRIANGLE = 0, 1


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
def gather_planes(i, P, pl, wc, plh, W, wi, wkind, wk, wp, wrow, n, row_i):
    """The plane contacts of particle i into the wall buffer from lane ``n``: overlap
    delta = R - (x - p).N, contact normal -N, lever R - delta, wall velocity
    ``pl.velocity``; only the planes of ``wc.plane_cand[i]`` (within R + skin at the last
    neighbour build, not 0) are looked at; a contact that ends restarts its spring
    (``plh[i * npl + p]``).  Returns the next free lane.

    A function of its own, apart from :func:`gather_triangles`, with only the bundles it
    reads: small enough for LLVM to inline it into the slab task.  Together, as one
    ``gather_walls`` that took every bundle, it was not inlined: a call per particle near
    a wall with 712 scalar arguments (numba passes each array of a bundle member by
    member).  The split made the settled ``settle`` bed's step 1.18x faster on one
    thread (median of 16 paired runs, loaded host, bitwise the same trajectory;
    docs/design.md, "Arguments of the force pass's calls")."""
    ri = P.radius[i]
    Ti = P.T[i]
    xi0 = P.x[i, 0]
    xi1 = P.x[i, 1]
    xi2 = P.x[i, 2]
    cand = wc.plane_cand[i]
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
    return n


@njit(_nrt=False)
def gather_triangles(i, P, pairs, M, wc, W, wi, wkind, wk, wp, wrow, n, row_i):
    """The mesh-triangle contacts of particle i (triangle candidates or contacts at the
    last step) into the wall buffer from lane ``n``: the closest points accepted by
    :func:`gsi.dem.mesh_dedup.select_triangle_contacts`; velocity and temperature at the
    point are the barycentric means of the vertex values.  Returns the next free lane."""
    ri = P.radius[i]
    Ti = P.T[i]
    xi0 = P.x[i, 0]
    xi1 = P.x[i, 1]
    xi2 = P.x[i, 2]
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
    (force, torque lever n x F + M_r, heat), the springs stored, and the
    wall's share kept: the plane sums of slab ``sl`` in ``pl_acc[sl, p]`` (force, moment
    about the plane's point at the contact point, heat; see
    :func:`gsi.dem.wall_kernels.plane_sums`), the triangle slots in ``wc.force``,
    ``wc.heat`` (see :func:`gsi.dem.wall_kernels.mesh_scatter`); with frictional heating
    :func:`friction_walls` follows."""
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
        if heat_on:
            P.q[i] += Qw


@njit(_nrt=False)
def friction_walls(n, W, wi, wkind, wp, sl, P, wc, dt, model, pl_acc):
    """Frictional heating of a wall batch after :func:`finish_walls`: the dissipated power
    of its lanes (:func:`gsi.dem.contact.model.evaluate_dissipation`), half of it into
    the particle (``q``, ``heat_friction``), half into the wall (``pl_acc[sl, p, 7]``,
    ``wc.fheat``), and the particle's dissipative impulses.  Called by the engine only
    with frictional heating on, outside :func:`finish_walls` (see
    :func:`gsi.dem.pair_lanes.friction_pairs`)."""
    evaluate_dissipation(n, W, dt, model)
    for l in range(n):
        i = wi[l]
        Qf = 0.5 * W[QF + l]
        P.q[i] += Qf
        P.heat_friction[i] += Qf * dt
        dissipative_impulse(W, l, np.int64(i), np.int64(-1), P, dt)
        if wkind[l] == PLANE:
            pl_acc[sl, wp[l], 7] += Qf
        else:
            wc.fheat[i, wp[l]] = Qf


@njit(_nrt=False)
def plane_count(cand):
    """Number of set bits of a plane-candidate mask."""
    c = 0
    while cand != 0:
        cand &= cand - 1
        c += 1
    return c
