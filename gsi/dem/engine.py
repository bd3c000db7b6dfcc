"""The DEM step kernels for one choice of contact law, rolling law and heat model.

This file is a template: :func:`gsi.dem.engine_factory.get_engine` writes a copy with
the block between the ``ENGINE-LAWS`` markers replaced by the chosen laws (one cached
module per combination, because numba cannot cache closures or function arguments),
so the hot loops call the law directly and never dispatch on a name.  Imported as
it is, the module uses Hertz, no rolling resistance and no heat.

One DEM step (velocity Verlet, DESIGN.md "DEM physics"):

1. v += dt/2 F/m, x += dt v, omega += dt/2 T/I, then F = m g, T = 0, Q = 0 for the
   new forces; walls move (:func:`move_walls`).
2. scan: largest displacement since the last neighbour build (rebuild when it
   exceeds skin/2), particles outside the domain, NaN or runaway velocities.
3. :func:`contact_forces` (parallel, two colours of slabs): the law of each pair once,
   added to both particles; plane and triangle contacts of each particle.
4. v += dt/2 F/m, omega += dt/2 T/I; T += dt Q/(m c_p).
5. serial sums of wall forces, torques and the coupling accumulators.

Steps 4 and the next step's 1-2 run inside :func:`contact_forces`, slab by slab as the
forces complete (:func:`_integrate_rows`), so a step has two parallel regions; only the
first step of a call to :func:`advance` drifts on its own (:func:`initial_integrate`,
:func:`scan`; :func:`clear_forces` when resuming after a rebuild).
"""
import math

import numpy as np

from gsi.jit import njit, pjit, prange
from gsi.dem.geometry import closest_point_triangle, FACE, VA, VB, VC, EAB, EBC, ECA

# <<ENGINE-LAWS (replaced by gsi.dem.engine_factory)
from gsi.dem.contact.hertz import hertz as LAW
from gsi.dem.contact.rolling import no_rolling as ROLL
from gsi.dem.heat import none as COND
ROLL_ON = False
HEAT_ON = False
# ENGINE-LAWS>>

#: wall-contact slots per particle (mesh walls); more contacts raise an overflow flag
MAX_WALL_SLOTS = 8
#: two contact points closer than this fraction of the radius are the same contact
SAME_POINT_TOL = 1e-9


@njit
def _clear_one(i, gx, gy, gz, mass, f, tq, q, ncontact):
    """F = m g, T = 0, Q = 0, contact count 0 for particle i (before contacts add up)."""
    ncontact[i] = 0
    f[i, 0] = mass[i] * gx
    f[i, 1] = mass[i] * gy
    f[i, 2] = mass[i] * gz
    for d in range(3):
        tq[i, d] = 0.0
    q[i] = 0.0


@njit
def _kick_one(i, half_dt, v, w, f, tq, mass, inertia, fixed):
    """Half kick of particle i (unless fixed): v += dt/2 F/m, omega += dt/2 T/I."""
    if not fixed[i]:
        a = half_dt / mass[i]
        b = half_dt / inertia[i]
        for d in range(3):
            v[i, d] += a * f[i, d]
            w[i, d] += b * tq[i, d]


@njit
def _drift_one(i, half_dt, dt, gx, gy, gz, x, v, w, f, tq, q, ncontact, mass, inertia,
               fixed):
    """First half kick and drift of particle i: v += dt/2 F/m, omega += dt/2 T/I,
    x += dt v; then clear it for the new forces (:func:`_clear_one`)."""
    _kick_one(i, half_dt, v, w, f, tq, mass, inertia, fixed)
    if not fixed[i]:
        for d in range(3):
            x[i, d] += dt * v[i, d]
    _clear_one(i, gx, gy, gz, mass, f, tq, q, ncontact)


@njit
def _scan_one(i, x, v, x0, lo, hi):
    """(squared displacement since build, squared speed, outside the domain) of i."""
    d2 = 0.0
    s2 = 0.0
    out = False
    for d in range(3):
        xi = x[i, d]
        dd = xi - x0[i, d]
        d2 += dd * dd
        s2 += v[i, d] * v[i, d]
        if not (lo[d] <= xi <= hi[d]):
            out = True
    return d2, s2, out


@pjit
def initial_integrate(n, x, v, w, f, tq, q, ncontact, mass, inertia, fixed, half_dt, dt,
                      gx, gy, gz):
    """First half kick and drift of every particle, then clear (:func:`_drift_one`)."""
    for i in prange(n):
        _drift_one(i, half_dt, dt, gx, gy, gz, x, v, w, f, tq, q, ncontact, mass, inertia,
                   fixed)


@njit
def scan(n, x, v, x0, lo, hi, vmax2):
    """Largest squared displacement since build (m^2), count outside domain, bad particle.

    Returns ``(max_disp2, n_out, bad)``; ``bad`` is the first particle whose velocity
    is NaN or above sqrt(vmax2), else -1.
    """
    dmax = 0.0
    nout = 0
    bad = -1
    for i in range(n):
        d2, s2, out = _scan_one(i, x, v, x0, lo, hi)
        if d2 > dmax:
            dmax = d2
        if out:
            nout += 1
        if bad < 0 and not (s2 <= vmax2):
            bad = i
    return dmax, nout, bad


@njit
def move_walls(dt, pl_p, pl_v, mv_x, mv_v, mv_x0, mv_wall, mw_rigid, mw_vel, mw_omega,
               mw_centre):
    """Advance planes (point += v dt) and mesh vertices by one step; return max vertex disp^2.

    Rigid walls (``mw_rigid``) rotate exactly by omega dt about their centre and
    translate with ``mw_vel``; their vertex velocities are v = vel + omega x (x - c).
    Other walls move each vertex with its own velocity: x += v dt.
    """
    for p in range(pl_p.shape[0]):
        for d in range(3):
            pl_p[p, d] += dt * pl_v[p, d]
    nw = mw_rigid.shape[0]
    for q in range(nw):
        if mw_rigid[q]:
            for d in range(3):
                mw_centre[q, d] += dt * mw_vel[q, d]
    dmax = 0.0
    for a in range(mv_x.shape[0]):
        q = mv_wall[a]
        if mw_rigid[q]:
            ox = mw_omega[q, 0]
            oy = mw_omega[q, 1]
            oz = mw_omega[q, 2]
            om = math.sqrt(ox * ox + oy * oy + oz * oz)
            cx = mw_centre[q, 0]
            cy = mw_centre[q, 1]
            cz = mw_centre[q, 2]
            # position relative to the (already moved) centre, before rotation
            rx = mv_x[a, 0] + dt * mw_vel[q, 0] - cx
            ry = mv_x[a, 1] + dt * mw_vel[q, 1] - cy
            rz = mv_x[a, 2] + dt * mw_vel[q, 2] - cz
            if om > 0.0:
                # Rodrigues rotation by angle om dt about unit axis k
                kx = ox / om
                ky = oy / om
                kz = oz / om
                th = om * dt
                c = math.cos(th)
                s = math.sin(th)
                kr = kx * rx + ky * ry + kz * rz
                crx = ky * rz - kz * ry
                cry = kz * rx - kx * rz
                crz = kx * ry - ky * rx
                rx, ry, rz = (rx * c + crx * s + kx * kr * (1 - c),
                              ry * c + cry * s + ky * kr * (1 - c),
                              rz * c + crz * s + kz * kr * (1 - c))
            mv_x[a, 0] = cx + rx
            mv_x[a, 1] = cy + ry
            mv_x[a, 2] = cz + rz
            mv_v[a, 0] = mw_vel[q, 0] + oy * rz - oz * ry
            mv_v[a, 1] = mw_vel[q, 1] + oz * rx - ox * rz
            mv_v[a, 2] = mw_vel[q, 2] + ox * ry - oy * rx
        else:
            for d in range(3):
                mv_x[a, d] += dt * mv_v[a, d]
        d2 = 0.0
        for d in range(3):
            dd = mv_x[a, d] - mv_x0[a, d]
            d2 += dd * dd
        if d2 > dmax:
            dmax = d2
    return dmax


@njit
def _feature(t, region, mt, mt_edge):
    """(kind, id) of a closest-point region: kind 0 face (triangle id), 1 edge, 2 vertex."""
    if region == FACE:
        return 0, t
    if region == VA:
        return 2, mt[t, 0]
    if region == VB:
        return 2, mt[t, 1]
    if region == VC:
        return 2, mt[t, 2]
    if region == EAB:
        return 1, mt_edge[t, 0]
    if region == EBC:
        return 1, mt_edge[t, 1]
    return 1, mt_edge[t, 2]


@pjit
def clear_forces(n, gx, gy, gz, mass, f, tq, q, ncontact):
    """f = m g, torque = 0, heat rate = 0, contact count = 0 (before contacts add up)."""
    for i in prange(n):
        _clear_one(i, gx, gy, gz, mass, f, tq, q, ncontact)


@njit
def _integrate_rows(m0, m1, slab_list, mode, half_dt, dt, gx, gy, gz, x, v, w, f, tq, q,
                    ncontact, mass, inertia, fixed, T, mcp_inv, x0, lo, hi, vmax2):
    """Particles ``slab_list[m0:m1]``, whose forces are complete: the second half kick
    v += dt/2 F/m, omega += dt/2 T/I and heat T += dt Q/(m c_p); with ``mode`` 2 also the
    next step's first half kick, drift and clear (:func:`_drift_one`), returning the
    scan of those particles: (max squared displacement since build, number outside the
    domain, lowest id whose speed is NaN or above sqrt(vmax2), else -1) as
    :func:`scan` does."""
    dmax = 0.0
    nout = 0
    bad = -1
    for m in range(m0, m1):
        i = slab_list[m]
        _kick_one(i, half_dt, v, w, f, tq, mass, inertia, fixed)
        if HEAT_ON:
            T[i] += dt * q[i] * mcp_inv[i]
        if mode == 2:
            _drift_one(i, half_dt, dt, gx, gy, gz, x, v, w, f, tq, q, ncontact, mass,
                       inertia, fixed)
            d2, s2, out = _scan_one(i, x, v, x0, lo, hi)
            if d2 > dmax:
                dmax = d2
            if out:
                nout += 1
            if not (s2 <= vmax2) and (bad < 0 or i < bad):
                bad = i
    return dmax, nout, bad


@njit
def _wall_contact(i, nx, ny, nz, lever, delta, wvx, wvy, wvz, v, w, ri, mi, Ii, Ti, tab,
                  row, hist, k, dt, has_T, T_w):
    """One particle-wall contact (plane or triangle), shared by both wall kinds.

    ``n`` is the unit normal from the centre of i to the contact point at distance
    ``lever``, ``delta`` the overlap, ``wv`` the wall velocity there, ``row`` the
    (particle type, wall type) row of the pair table, ``hist[k]`` the tangential spring;
    the wall counts as infinitely large and heavy (R* = R_i, m* = m_i).  Returns the
    force on i, the torque on i (lever n x F plus rolling resistance) and the heat
    rate into i (0 unless the heat model is on and the wall has a temperature ``T_w``).
    """
    vx = v[i, 0] - wvx + lever * (w[i, 1] * nz - w[i, 2] * ny)
    vy = v[i, 1] - wvy + lever * (w[i, 2] * nx - w[i, 0] * nz)
    vz = v[i, 2] - wvz + lever * (w[i, 0] * ny - w[i, 1] * nx)
    cfx, cfy, cfz, F_n = LAW(nx, ny, nz, delta, vx, vy, vz, ri, mi, tab, row, hist, k, dt)
    tx = lever * (ny * cfz - nz * cfy)
    ty = lever * (nz * cfx - nx * cfz)
    tz = lever * (nx * cfy - ny * cfx)
    if ROLL_ON:
        Mx, My, Mz = ROLL(w[i, 0], w[i, 1], w[i, 2], ri, F_n, tab, row, Ii, dt)
        tx += Mx
        ty += My
        tz += Mz
    Qw = 0.0
    if HEAT_ON and has_T:
        Qw = COND(2.0 * ri * delta - delta * delta, tab, row) * (T_w - Ti)
    return cfx, cfy, cfz, tx, ty, tz, Qw


@njit
def _slab_task(sl, colour, mode, n, nslab, dt, x, v, w, f, tq, q, radius, mass, inertia, T,
               ptype, ncontact, nt, tab, slab_start, slab_list, nb_start, nb_j, hist, pact,
               npl, pl_p, pl_n, pl_v, pl_type, pl_T, pl_hasT, plh, pl_mask, mv_x, mv_v,
               mv_T, mt, mt_edge, mt_wall, mw_type, mw_hasT, mc_start, mc_tri, mc_hist,
               wc_n, wc_tri, wc_kind, wc_fid, wc_k, wc_w, wc_f, wc_q, wc_pt, overflow,
               pl_acc, gx, gy, gz, fixed, mcp_inv, x0, lo, hi, vmax2, scan_out):
    """One task of :func:`contact_forces`: the contacts of the particles of slab
    ``sl`` (pairs, planes, triangles), then, for the second colour, the integration of
    the slabs this task completes (see :func:`contact_forces`).

    A plain (not parallel) function called from the ``prange`` loop, and the laws it
    calls are ordinary compiled functions (not inlined into numba's IR): the parfor
    passes then see one call, and each law compiles once for all engines.  With the
    body inside the ``prange`` and the laws IR-inlined, a cold compile of one engine
    took 5.5 min here (2 cores); this way 45 s.
    """
    for m in range(slab_start[sl], slab_start[sl + 1]):
        i = slab_list[m]
        mi = mass[i]
        ri = radius[i]
        row_i = ptype[i] * nt
        Ti = T[i]
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
        # ---- particle pairs
        for k in range(nb_start[i], nb_start[i + 1]):
            j = nb_j[k]
            dx = x[j, 0] - xi0
            dy = x[j, 1] - xi1
            dz = x[j, 2] - xi2
            L2 = dx * dx + dy * dy + dz * dz
            rj = radius[j]
            rs = ri + rj
            if L2 >= rs * rs or L2 == 0.0:
                if pact[k]:
                    pact[k] = 0
                    hist[k, 0] = 0.0
                    hist[k, 1] = 0.0
                    hist[k, 2] = 0.0
                continue
            pact[k] = 1
            L = math.sqrt(L2)
            inv_L = 1.0 / L
            nx = dx * inv_L
            ny = dy * inv_L
            nz = dz * inv_L
            delta = rs - L
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
            R_eff = ri * rj / rs
            mj = mass[j]
            m_eff = mi * mj / (mi + mj)
            row = row_i + ptype[j]
            cfx, cfy, cfz, F_n = LAW(nx, ny, nz, delta, vx, vy, vz, R_eff, m_eff,
                                     tab, row, hist, k, dt)
            # n x F
            cx = ny * cfz - nz * cfy
            cy = nz * cfx - nx * cfz
            cz = nx * cfy - ny * cfx
            Mx = 0.0
            My = 0.0
            Mz = 0.0
            if ROLL_ON:
                Ii = inertia[i]
                Ij = inertia[j]
                Mx, My, Mz = ROLL(w[i, 0] - w[j, 0], w[i, 1] - w[j, 1],
                                  w[i, 2] - w[j, 2], R_eff, F_n, tab, row,
                                  Ii * Ij / (Ii + Ij), dt)
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
            ncontact[j] += 1
            nc += 1
            if HEAT_ON:
                # contact radius of two spheres at centre distance L
                sc = (ri * ri - rj * rj + L2) * 0.5 * inv_L
                Qp = COND(ri * ri - sc * sc, tab, row) * (T[j] - Ti)
                qi += Qp
                q[j] -= Qp
        # ---- planes
        pmask = 0
        was = pl_mask[i]             # planes touched at the last step
        for p in range(npl):
            Nx = pl_n[p, 0]
            Ny = pl_n[p, 1]
            Nz = pl_n[p, 2]
            dist = (xi0 - pl_p[p, 0]) * Nx + (xi1 - pl_p[p, 1]) * Ny + (xi2 - pl_p[p, 2]) * Nz
            delta = ri - dist
            if delta <= 0.0:
                if (was >> p) & 1:     # contact ended: the spring restarts
                    plh[i * npl + p, 0] = 0.0
                    plh[i * npl + p, 1] = 0.0
                    plh[i * npl + p, 2] = 0.0
                continue
            nc += 1
            pmask |= 1 << p
            cfx, cfy, cfz, ctx, cty, ctz, Qw = _wall_contact(
                i, -Nx, -Ny, -Nz, dist, delta, pl_v[p, 0], pl_v[p, 1], pl_v[p, 2], v, w,
                ri, mi, inertia[i], Ti, tab, row_i + pl_type[p], plh, i * npl + p, dt,
                pl_hasT[p], pl_T[p])
            # force on the particle and its moment about the plane's point, taken
            # at the contact point (the centre projected on the plane)
            rx = xi0 - dist * Nx - pl_p[p, 0]
            ry = xi1 - dist * Ny - pl_p[p, 1]
            rz = xi2 - dist * Nz - pl_p[p, 2]
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
        pl_mask[i] = pmask
        # ---- triangle meshes
        ns = 0
        c0 = mc_start[i]
        c1 = mc_start[i + 1]
        if c1 > c0:
            r2 = ri * ri
            tol2 = (SAME_POINT_TOL * ri) ** 2
            for sweep in range(2):      # faces first, then edges and vertices
                for k in range(c0, c1):
                    t = mc_tri[k]
                    a = mt[t, 0]
                    b = mt[t, 1]
                    c = mt[t, 2]
                    qx, qy, qz, wa, wb, wcc, region = closest_point_triangle(
                        xi0, xi1, xi2, mv_x[a, 0], mv_x[a, 1], mv_x[a, 2],
                        mv_x[b, 0], mv_x[b, 1], mv_x[b, 2], mv_x[c, 0], mv_x[c, 1], mv_x[c, 2])
                    if (region == FACE) != (sweep == 0):
                        continue
                    ddx = qx - xi0
                    ddy = qy - xi1
                    ddz = qz - xi2
                    d2 = ddx * ddx + ddy * ddy + ddz * ddz
                    if d2 >= r2:
                        continue
                    kind, fid = _feature(t, region, mt, mt_edge)
                    wall = mt_wall[t]
                    keep = True
                    for s in range(ns):
                        ts = wc_tri[i, s]
                        if mt_wall[ts] != wall:
                            continue
                        ex = wc_pt[i, s, 0] - qx
                        ey = wc_pt[i, s, 1] - qy
                        ez = wc_pt[i, s, 2] - qz
                        if ex * ex + ey * ey + ez * ez <= tol2:
                            keep = False
                        elif kind != 0 and wc_kind[i, s] == kind and wc_fid[i, s] == fid:
                            keep = False
                        elif kind == 1 and wc_kind[i, s] == 0:
                            if (mt_edge[ts, 0] == fid or mt_edge[ts, 1] == fid
                                    or mt_edge[ts, 2] == fid):
                                keep = False
                        elif kind == 2 and wc_kind[i, s] == 0:
                            if mt[ts, 0] == fid or mt[ts, 1] == fid or mt[ts, 2] == fid:
                                keep = False
                        if not keep:
                            break
                    if not keep:
                        continue
                    if ns == MAX_WALL_SLOTS:
                        overflow[0] += 1   # benign race: only a flag
                        continue
                    wc_tri[i, ns] = t
                    wc_kind[i, ns] = kind
                    wc_fid[i, ns] = fid
                    wc_k[i, ns] = k
                    wc_w[i, ns, 0] = wa
                    wc_w[i, ns, 1] = wb
                    wc_w[i, ns, 2] = wcc
                    wc_pt[i, ns, 0] = qx
                    wc_pt[i, ns, 1] = qy
                    wc_pt[i, ns, 2] = qz
                    ns += 1
            # springs of candidates without an accepted contact restart from zero
            for k in range(c0, c1):
                used = False
                for s in range(ns):
                    if wc_k[i, s] == k:
                        used = True
                if not used:
                    mc_hist[k, 0] = 0.0
                    mc_hist[k, 1] = 0.0
                    mc_hist[k, 2] = 0.0
            for s in range(ns):
                t = wc_tri[i, s]
                ddx = wc_pt[i, s, 0] - xi0
                ddy = wc_pt[i, s, 1] - xi1
                ddz = wc_pt[i, s, 2] - xi2
                dist = math.sqrt(ddx * ddx + ddy * ddy + ddz * ddz)
                delta = ri - dist
                nx = ddx / dist
                ny = ddy / dist
                nz = ddz / dist
                a = mt[t, 0]
                b = mt[t, 1]
                c = mt[t, 2]
                wa = wc_w[i, s, 0]
                wb = wc_w[i, s, 1]
                wcc = wc_w[i, s, 2]
                wvx = wa * mv_v[a, 0] + wb * mv_v[b, 0] + wcc * mv_v[c, 0]
                wvy = wa * mv_v[a, 1] + wb * mv_v[b, 1] + wcc * mv_v[c, 1]
                wvz = wa * mv_v[a, 2] + wb * mv_v[b, 2] + wcc * mv_v[c, 2]
                wl = mt_wall[t]
                T_w = 0.0
                if HEAT_ON:
                    T_w = wa * mv_T[a] + wb * mv_T[b] + wcc * mv_T[c]
                cfx, cfy, cfz, ctx, cty, ctz, Qw = _wall_contact(
                    i, nx, ny, nz, dist, delta, wvx, wvy, wvz, v, w, ri, mi, inertia[i],
                    Ti, tab, row_i + mw_type[wl], mc_hist, wc_k[i, s], dt, mw_hasT[wl],
                    T_w)
                wc_f[i, s, 0] = cfx
                wc_f[i, s, 1] = cfy
                wc_f[i, s, 2] = cfz
                wc_q[i, s] = Qw
                fx += cfx
                fy += cfy
                fz += cfz
                tx += ctx
                ty += cty
                tz += ctz
                qi += Qw
                nc += 1
        wc_n[i] = ns
        ncontact[i] += nc
        f[i, 0] += fx
        f[i, 1] += fy
        f[i, 2] += fz
        tq[i, 0] += tx
        tq[i, 1] += ty
        tq[i, 2] += tz
        if HEAT_ON:
            q[i] += qi
    if colour == 1 and mode > 0:
        m0 = slab_start[0] if sl == 1 else slab_start[sl]
        m1 = slab_start[min(sl + 2, nslab)]
        dm, no, bd = _integrate_rows(m0, m1, slab_list, mode, 0.5 * dt, dt, gx, gy,
                                     gz, x, v, w, f, tq, q, ncontact, mass, inertia,
                                     fixed, T, mcp_inv, x0, lo, hi, vmax2)
        scan_out[sl, 0] = dm
        scan_out[sl, 1] = no
        scan_out[sl, 2] = bd


@pjit
def contact_forces(n, dt, x, v, w, f, tq, q, radius, mass, inertia, T, ptype, ncontact,
                   table, slab_start, slab_list, nb_start, nb_j, hist, pact,
                   pl_p, pl_n, pl_v, pl_type, pl_T, pl_hasT, pl_hist, pl_mask,
                   mv_x, mv_v, mv_T, mt, mt_edge, mt_wall, mw_type, mw_hasT,
                   mc_start, mc_tri, mc_hist, wc_n, wc_tri, wc_kind, wc_fid, wc_k, wc_w,
                   wc_f, wc_q, wc_pt, overflow, pl_acc, mode, gx, gy, gz, fixed, mcp_inv,
                   x0, lo, hi, vmax2, scan_out):
    """Add all contact forces, torques and heat rates to f, tq, q (cleared before), and
    (``mode`` 1 or 2) integrate each particle as soon as its forces are complete.

    Pairs (half list; a pair is stored at the particle of the lower slab): the law is
    evaluated once per pair and added to both particles (Newton's third law).  The
    slabs (at least one cutoff wide) are processed in two colours, even then odd, in
    parallel within a colour: a particle of slab s writes only to slabs s and s + 1,
    so no two threads write the same particle.  Pair k = (i, j), n from i to j,
    overlap delta = R_i + R_j - L, lever arms a_i = R_i - delta/2, a_j = R_j - delta/2:
    torque a_i n x F on i and a_j n x F on j (F the force on i).

    Plane contacts: overlap delta = R - (x - p).n, contact normal -n, lever R - delta,
    wall velocity ``pl_v``; each slab s sums the force on its particles, their torque
    about the plane's point and their heat into ``pl_acc[s, p]`` (see
    :func:`plane_sums`).  Triangle contacts at the closest point with duplicate
    edge/vertex contacts of one wall removed (see :mod:`gsi.dem.walls`).

    Integration in the same pass (``mode`` 0: none, the forces only; 1: the second half
    kick; 2: that kick, then the next step's kick, drift and clear, see
    :func:`_integrate_rows`): slab s receives forces only from slabs s - 1 and s, so
    once the task of odd slab s (second colour) has run, slabs s and s + 1 are complete,
    and only this task reads them in that colour; it integrates them at once (the task
    of slab 1 also slab 0).  This leaves two parallel regions per step.  ``scan_out[s]``
    gets the scan of the particles the task of slab s integrated (mode 2).
    """
    npl = pl_p.shape[0]
    nt = table.shape[0]
    tab = table.reshape((nt * nt, table.shape[2]))
    plh = pl_hist.reshape((n * npl, 3))
    nslab = slab_start.shape[0] - 1
    for colour in range(2):
        for si in prange((nslab - colour + 1) // 2):
            _slab_task(2 * si + colour, colour, mode, n, nslab, dt, x, v, w, f, tq, q,
                       radius, mass, inertia, T, ptype, ncontact, nt, tab, slab_start,
                       slab_list, nb_start, nb_j, hist, pact, npl, pl_p, pl_n, pl_v,
                       pl_type, pl_T, pl_hasT, plh, pl_mask, mv_x, mv_v, mv_T, mt, mt_edge,
                       mt_wall, mw_type, mw_hasT, mc_start, mc_tri, mc_hist, wc_n, wc_tri,
                       wc_kind, wc_fid, wc_k, wc_w, wc_f, wc_q, wc_pt, overflow, pl_acc, gx,
                       gy, gz, fixed, mcp_inv, x0, lo, hi, vmax2, scan_out)
    if nslab == 1 and mode > 0:        # no second colour: the one slab is complete now
        dm, no, bd = _integrate_rows(0, n, slab_list, mode, 0.5 * dt, dt, gx, gy, gz, x, v,
                                     w, f, tq, q, ncontact, mass, inertia, fixed, T,
                                     mcp_inv, x0, lo, hi, vmax2)
        scan_out[0, 0] = dm
        scan_out[0, 1] = no
        scan_out[0, 2] = bd


@njit
def plane_sums(dt, pl_acc, pl_force, pl_torque, pl_imp, pl_heat):
    """Force and torque of the particles ON each plane (torque about the plane's point)
    from the per-slab sums of :func:`contact_forces`; accumulate the impulse on the
    particles (N s) and the heat to them (J); clear the sums for the next step."""
    pl_force[:] = 0.0
    pl_torque[:] = 0.0
    for s in range(pl_acc.shape[0]):
        for p in range(pl_acc.shape[1]):
            for d in range(3):
                pl_force[p, d] -= pl_acc[s, p, d]
                pl_torque[p, d] -= pl_acc[s, p, 3 + d]
                pl_imp[p, d] += pl_acc[s, p, d] * dt
            pl_heat[p] += pl_acc[s, p, 6] * dt
    pl_acc[:] = 0.0


@njit
def _p2_weight(j, la, lb, lc):
    """P2 basis function j of a six-node triangle (vertices a, b, c, then midpoints ab,
    bc, ca) at barycentric coordinates (la, lb, lc)."""
    if j == 0:
        return la * (2.0 * la - 1.0)
    if j == 1:
        return lb * (2.0 * lb - 1.0)
    if j == 2:
        return lc * (2.0 * lc - 1.0)
    if j == 3:
        return 4.0 * la * lb
    if j == 4:
        return 4.0 * lb * lc
    return 4.0 * lc * la


@njit
def mesh_scatter(n, dt, wc_n, wc_tri, wc_w, wc_f, wc_q, wc_pt, mt, mt_wall, mw_centre,
                 mw_force, mw_torque, mt_force, mv_imp, mv_heat, mw_imp_p, mw_heat_p,
                 mt_p6, mt_lam):
    """Serial scatter of triangle contacts: wall force/torque (about ``mw_centre``) and
    triangle forces ON the wall (this step), and the coupling accumulators
    vertex_impulse += -F N_k dt, vertex_heat += -Q N_k dt, impulse_on_particles += F dt,
    heat_to_particles += Q dt.  N_k are the barycentric weights w_k of the contact point,
    or, for a triangle with a quadratic parent (``mt_p6[t, 0] >= 0``), the six P2 basis
    values at the point's parent coordinates l = sum_k w_k mt_lam[t, k]."""
    mw_force[:] = 0.0
    mw_torque[:] = 0.0
    mt_force[:] = 0.0
    for i in range(n):
        for s in range(wc_n[i]):
            t = wc_tri[i, s]
            wl = mt_wall[t]
            Fx = wc_f[i, s, 0]
            Fy = wc_f[i, s, 1]
            Fz = wc_f[i, s, 2]
            Q = wc_q[i, s]
            mw_force[wl, 0] -= Fx
            mw_force[wl, 1] -= Fy
            mw_force[wl, 2] -= Fz
            mt_force[t, 0] -= Fx
            mt_force[t, 1] -= Fy
            mt_force[t, 2] -= Fz
            rx = wc_pt[i, s, 0] - mw_centre[wl, 0]
            ry = wc_pt[i, s, 1] - mw_centre[wl, 1]
            rz = wc_pt[i, s, 2] - mw_centre[wl, 2]
            mw_torque[wl, 0] -= ry * Fz - rz * Fy
            mw_torque[wl, 1] -= rz * Fx - rx * Fz
            mw_torque[wl, 2] -= rx * Fy - ry * Fx
            quad = mt_p6[t, 0] >= 0
            la = 0.0
            lb = 0.0
            lc = 0.0
            if quad:
                for c in range(3):
                    wk = wc_w[i, s, c]
                    la += wk * mt_lam[t, c, 0]
                    lb += wk * mt_lam[t, c, 1]
                    lc += wk * mt_lam[t, c, 2]
            for j in range(6 if quad else 3):
                if quad:
                    a = mt_p6[t, j]
                    wk = _p2_weight(j, la, lb, lc)
                else:
                    a = mt[t, j]
                    wk = wc_w[i, s, j]
                mv_imp[a, 0] -= Fx * wk * dt
                mv_imp[a, 1] -= Fy * wk * dt
                mv_imp[a, 2] -= Fz * wk * dt
                mv_heat[a] -= Q * wk * dt
            mw_imp_p[wl, 0] += Fx * dt
            mw_imp_p[wl, 1] += Fy * dt
            mw_imp_p[wl, 2] += Fz * dt
            mw_heat_p[wl] += Q * dt


@njit
def advance(nsteps, skip_first_drift, dt, g, half_skin2, vmax2, lo, hi, *arrays):
    """Run up to ``nsteps`` steps; stop early when the caller must act.

    ``arrays``: the particle, pair-list, plane and mesh arrays in the order unpacked
    below (flat, so that numba's fast argument dispatch applies).

    Each step is the force pass (:func:`contact_forces`, which also ends this step and,
    unless it is the last one, starts the next: kick, drift, clear, scan), then the
    serial wall sums and the wall motion.

    Returns ``(steps_done, code, info)``: code 0 all done; 1 a rebuild is needed
    (the step ``steps_done`` has drifted; resume it with ``skip_first_drift``);
    2 ``info`` particles left the domain (same resume); 3 particle ``info`` blew up
    (NaN or speed above sqrt(vmax2)) at step ``steps_done``.
    """
    (x, v, w, f, tq, q, radius, mass, inertia, T, mcp_inv, ptype, fixed, ncontact, x0,
     table,
     slab_start, slab_list, nb_start, nb_j, hist, pact,
     pl_p, pl_n, pl_v, pl_type, pl_T, pl_hasT, pl_hist, pl_mask, pl_force,
     pl_torque, pl_imp, pl_heat,
     mv_x, mv_v, mv_T, mv_x0, mv_wall, mt, mt_edge, mt_wall, mw_type, mw_hasT, mw_rigid,
     mw_vel, mw_omega, mw_centre, mc_start, mc_tri, mc_hist, wc_n, wc_tri, wc_kind,
     wc_fid, wc_k, wc_w, wc_f, wc_q, wc_pt, overflow, mw_force, mw_torque, mt_force,
     mv_imp, mv_heat, mw_imp_p, mw_heat_p, mt_p6, mt_lam) = arrays
    n = x.shape[0]
    half_dt = 0.5 * dt
    npl = pl_p.shape[0]
    nv = mv_x.shape[0]
    nslab = slab_start.shape[0] - 1
    pl_acc = np.zeros((nslab, npl, 7))
    scan_out = np.zeros((nslab, 3))
    if skip_first_drift:
        clear_forces(n, g[0], g[1], g[2], mass, f, tq, q, ncontact)
    else:
        initial_integrate(n, x, v, w, f, tq, q, ncontact, mass, inertia, fixed, half_dt,
                          dt, g[0], g[1], g[2])
        wd2 = move_walls(dt, pl_p, pl_v, mv_x, mv_v, mv_x0, mv_wall, mw_rigid, mw_vel,
                         mw_omega, mw_centre)
        d2, nout, bad = scan(n, x, v, x0, lo, hi, vmax2)
        code, info = _verdict(d2, wd2, nout, bad, half_skin2)
        if code != 0:
            return 0, code, info
    for s in range(nsteps):
        mode = 1 if s == nsteps - 1 else 2
        scan_out[:, 0] = 0.0
        scan_out[:, 1] = 0.0
        scan_out[:, 2] = -1.0
        contact_forces(n, dt, x, v, w, f, tq, q, radius, mass, inertia, T, ptype, ncontact,
                       table, slab_start, slab_list, nb_start, nb_j, hist, pact,
                       pl_p, pl_n, pl_v, pl_type, pl_T, pl_hasT, pl_hist, pl_mask,
                       mv_x, mv_v, mv_T, mt, mt_edge, mt_wall, mw_type, mw_hasT,
                       mc_start, mc_tri, mc_hist, wc_n, wc_tri, wc_kind, wc_fid, wc_k, wc_w,
                       wc_f, wc_q, wc_pt, overflow, pl_acc, mode, g[0], g[1], g[2], fixed,
                       mcp_inv, x0, lo, hi, vmax2, scan_out)
        if npl > 0:
            plane_sums(dt, pl_acc, pl_force, pl_torque, pl_imp, pl_heat)
        if nv > 0:
            mesh_scatter(n, dt, wc_n, wc_tri, wc_w, wc_f, wc_q, wc_pt, mt, mt_wall,
                         mw_centre, mw_force, mw_torque, mt_force, mv_imp, mv_heat,
                         mw_imp_p, mw_heat_p, mt_p6, mt_lam)
        if mode == 2:
            # the next step has drifted: its walls move, then the scan decides
            wd2 = move_walls(dt, pl_p, pl_v, mv_x, mv_v, mv_x0, mv_wall, mw_rigid, mw_vel,
                             mw_omega, mw_centre)
            d2 = 0.0
            nout = 0
            bad = -1
            for k in range(nslab):
                d2 = max(d2, scan_out[k, 0])
                nout += int(scan_out[k, 1])
                b = int(scan_out[k, 2])
                if b >= 0 and (bad < 0 or b < bad):
                    bad = b
            code, info = _verdict(d2, wd2, nout, bad, half_skin2)
            if code != 0:
                return s + 1, code, info
    return nsteps, 0, 0


@njit
def _verdict(d2, wd2, nout, bad, half_skin2):
    """(code, info) of :func:`advance` from a scan after a drift."""
    if bad >= 0:
        return 3, bad
    if nout > 0:
        return 2, nout
    if d2 > half_skin2 or wd2 > half_skin2:
        return 1, 0
    return 0, 0


@njit
def compute_forces(g, *arrays):
    """Forces, torques and contact springs' rotation at the current state, no motion,
    no heat update (dt = 0): the start of a run and after external changes."""
    (x, v, w, f, tq, q, radius, mass, inertia, T, mcp_inv, ptype, fixed, ncontact, x0,
     table,
     slab_start, slab_list, nb_start, nb_j, hist, pact,
     pl_p, pl_n, pl_v, pl_type, pl_T, pl_hasT, pl_hist, pl_mask, pl_force,
     pl_torque, pl_imp, pl_heat,
     mv_x, mv_v, mv_T, mv_x0, mv_wall, mt, mt_edge, mt_wall, mw_type, mw_hasT, mw_rigid,
     mw_vel, mw_omega, mw_centre, mc_start, mc_tri, mc_hist, wc_n, wc_tri, wc_kind,
     wc_fid, wc_k, wc_w, wc_f, wc_q, wc_pt, overflow, mw_force, mw_torque, mt_force,
     mv_imp, mv_heat, mw_imp_p, mw_heat_p, mt_p6, mt_lam) = arrays
    n = x.shape[0]
    nslab = slab_start.shape[0] - 1
    clear_forces(n, g[0], g[1], g[2], mass, f, tq, q, ncontact)
    contact_forces(n, 0.0, x, v, w, f, tq, q, radius, mass, inertia, T, ptype, ncontact,
                   table, slab_start, slab_list, nb_start, nb_j, hist, pact,
                   pl_p, pl_n, pl_v, pl_type, pl_T, pl_hasT, pl_hist, pl_mask,
                   mv_x, mv_v, mv_T, mt, mt_edge, mt_wall, mw_type, mw_hasT,
                   mc_start, mc_tri, mc_hist, wc_n, wc_tri, wc_kind, wc_fid, wc_k, wc_w,
                   wc_f, wc_q, wc_pt, overflow, np.zeros((nslab, pl_p.shape[0], 7)), 0,
                   g[0], g[1], g[2], fixed, mcp_inv, x0, g, g, 0.0,
                   np.zeros((nslab, 3)))


@njit
def heat_conductance_sum(*arrays):
    """Per particle sum_j H_ij (W/K) over touching pairs and walls with a temperature
    (triangle contacts as found at the last step)."""
    (x, v, w, f, tq, q, radius, mass, inertia, T, mcp_inv, ptype, fixed, ncontact, x0,
     table,
     slab_start, slab_list, nb_start, nb_j, hist, pact,
     pl_p, pl_n, pl_v, pl_type, pl_T, pl_hasT, pl_hist, pl_mask, pl_force,
     pl_torque, pl_imp, pl_heat,
     mv_x, mv_v, mv_T, mv_x0, mv_wall, mt, mt_edge, mt_wall, mw_type, mw_hasT, mw_rigid,
     mw_vel, mw_omega, mw_centre, mc_start, mc_tri, mc_hist, wc_n, wc_tri, wc_kind,
     wc_fid, wc_k, wc_w, wc_f, wc_q, wc_pt, overflow, mw_force, mw_torque, mt_force,
     mv_imp, mv_heat, mw_imp_p, mw_heat_p, mt_p6, mt_lam) = arrays
    n = x.shape[0]
    nt = table.shape[0]
    tab = table.reshape((nt * nt, table.shape[2]))
    Hs = np.zeros(n)
    for i in range(n):
        ri = radius[i]
        for k in range(nb_start[i], nb_start[i + 1]):
            j = nb_j[k]
            rj = radius[j]
            L2 = 0.0
            for d in range(3):
                L2 += (x[j, d] - x[i, d]) ** 2
            if L2 >= (ri + rj) ** 2 or L2 == 0.0:
                continue
            L = math.sqrt(L2)
            s = (ri * ri - rj * rj + L2) / (2.0 * L)
            H = COND(ri * ri - s * s, tab, ptype[i] * nt + ptype[j])
            Hs[i] += H
            Hs[j] += H
        for p in range(pl_p.shape[0]):
            if not pl_hasT[p]:
                continue
            dist = 0.0
            for d in range(3):
                dist += (x[i, d] - pl_p[p, d]) * pl_n[p, d]
            delta = ri - dist
            if delta > 0.0:
                Hs[i] += COND(2.0 * ri * delta - delta * delta, tab, ptype[i] * nt + pl_type[p])
        for s in range(wc_n[i]):
            wl = mt_wall[wc_tri[i, s]]
            if not mw_hasT[wl]:
                continue
            dist = 0.0
            for d in range(3):
                dist += (wc_pt[i, s, d] - x[i, d]) ** 2
            delta = ri - math.sqrt(dist)
            if delta > 0.0:
                Hs[i] += COND(2.0 * ri * delta - delta * delta, tab, ptype[i] * nt + mw_type[wl])
    return Hs
