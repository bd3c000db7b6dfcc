"""Sphere-pair contacts in lanes: gather, geometry, the contact model, Newton's third law.

The pair path of the engine (:mod:`gsi.dem.engine`): the touching candidates of a slab's
rows are compacted into the lanes of a buffer (:func:`gather_pairs`), their geometry is
computed in one vectorized loop (:func:`pair_geometry`), the contact model runs over runs
of lanes of one pair-table row (:func:`evaluate_runs`, the one call of
:func:`gsi.dem.contact.model.evaluate` for every kind of contact), and each pair is added
to both particles (:func:`finish_pairs`).  Buffer fields: :mod:`gsi.dem.contact.lanes`.
Ahead of the gather, :func:`prefetch_ahead` asks for the rows that a particle a few rows
further on will touch first (large beds: docs/design.md, "The large beds").
"""
import numpy as np

from gsi.jit import njit, prefetch, prefetch_w, sqrt, uint
from gsi.dem.contact.lanes import (
    NX, NY, NZ, DELTA, VX, VY, VZ, REFF, MEFF, IEFF, WX, WY, WZ, A2, RI, RJ, DTEMP,
    HX, HY, HZ, FX, FY, FZ, MX, MY, MZ, Q, AI, AJ, MI, MJ, II, IJ, WIX, WIY, WIZ, TIX, TIY,
    TIZ, TJX, TJY, TJZ, QF, FDX, FDY, FDZ)
from gsi.dem.contact.model import evaluate, evaluate_dissipation, M_ROLLING
from gsi.dem.contact_geometry import spheres_touch


#: particles ahead (in the visiting order) whose first-touched rows the force pass
#: prefetches (:func:`prefetch_ahead`); 12 measured alike at 197,730 particles, 16 (in a
#: variant without the springs' middle line) no faster
PREFETCH_AHEAD = 8


@njit(_nrt=False)
def prefetch_ahead(u, P, pairs):
    """Prefetch the rows the force pass will touch first at particle ``u``: its last
    partner's position, radius, velocities, mass (read) and force and torque (written),
    and the lines of its springs ``pairs.hist`` (first, middle, last).

    Rows are in visiting order (slabs along one axis, cells inside a slab) and partners
    ascend (:func:`gsi.dem.neighbour.sort_rows`), so a particle's last partner usually
    lies in the next slab: the leading edge of what the pass touches, which in a bed
    far larger than the last-level cache comes from memory in an order the hardware
    prefetchers do not follow; the springs are a stream of their own, read and written.
    On the settled ``settle`` bed tiled 5 x 2 (197,730 particles), one thread,
    interleaved runs: 27.2-28.6 ms a step without, 23.5-24.3 with; 988,650 particles
    143-145 -> 129-132 ms; 19,773 particles, in cache, 1.87-1.90 -> 1.90-1.95 ms.  The
    partner's rows without the springs gained nothing; every partner's rows, not only
    the last, cost 11-17 % at 19,773 particles (docs/design.md, "The large beds")."""
    ua = uint(u)
    ka = uint(pairs.start[ua])
    kb = uint(pairs.start[ua + uint(1)])
    if kb > ka:
        j = uint(pairs.j[kb - uint(1)])
        prefetch(P.x, j)
        prefetch(P.radius, j)
        prefetch(P.v, j)
        prefetch(P.omega, j)
        prefetch(P.mass, j)
        prefetch_w(P.force, j)
        prefetch_w(P.torque, j)
        prefetch_w(pairs.hist, ka)
        prefetch_w(pairs.hist, (ka + kb) >> uint(1))
        prefetch_w(pairs.hist, kb - uint(1))


@njit(_nrt=False)
def gather_pairs(i, k0, k1, row_i, P, pairs, B, lk, lj, lrow, n, roll_on, heat_on, multi):
    """Candidates k0..k1-1 of particle i into the batch from lane ``n`` on.

    The contact test (``pairs.active``; the spring of a contact that ended restarts), the
    touching pairs compacted without a branch (every candidate is written at lane n,
    which advances only for a touching one: about half of a dense bed's candidates
    touch, at random, a coin flip for a branch), then the inputs of the new lanes
    gathered (inertias only for a rolling model, temperatures only for a heat model,
    the table rows only with more than one material type, ``multi``).
    Returns the next free lane; the caller leaves room for all candidates."""
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
    # i's velocities in locals: LLVM cannot keep them in registers itself (a store to B
    # might alias v or omega, so it would load them again for every lane)
    vi0 = v[i, 0]
    vi1 = v[i, 1]
    vi2 = v[i, 2]
    wi0 = w[i, 0]
    wi1 = w[i, 1]
    wi2 = w[i, 2]
    for l in range(l0, n):
        j = lj[l]
        k = lk[l]
        if multi:
            lrow[l] = row_i + P.type[j]
        B[RI + l] = ri
        B[RJ + l] = P.radius[j]
        B[MI + l] = mi
        B[MJ + l] = P.mass[j]
        if roll_on:
            B[II + l] = Ii
            B[IJ + l] = P.inertia[j]
        B[VX + l] = vi0 - v[j, 0]
        B[VY + l] = vi1 - v[j, 1]
        B[VZ + l] = vi2 - v[j, 2]
        B[WIX + l] = wi0
        B[WIY + l] = wi1
        B[WIZ + l] = wi2
        B[WX + l] = w[j, 0]
        B[WY + l] = w[j, 1]
        B[WZ + l] = w[j, 2]
        if heat_on:
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
    v_i + omega_i x (a_i n) - v_j - omega_j x (-a_j n), R*, m* and omega_i - omega_j
    (I* and a^2 only where a sub-model needs them: :func:`pair_inertia`,
    :func:`pair_contact_radius`)."""
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
        # R* = R_i R_j/(R_i + R_j) and m* = m_i m_j/(m_i + m_j) by one division
        mi = B[MI + l]
        mj = B[MJ + l]
        rs = ri + rj
        ms = mi + mj
        inv = 1.0 / (rs * ms)
        B[REFF + l] = ri * rj * ms * inv
        B[MEFF + l] = mi * mj * rs * inv


@njit(_nrt=False)
def pair_inertia(n, B):
    """I* = I_i I_j/(I_i + I_j) of lanes 0..n-1 (for the rolling model)."""
    for l in range(uint(0), uint(n)):
        Ii = B[II + l]
        Ij = B[IJ + l]
        B[IEFF + l] = Ii * Ij / (Ii + Ij)


@njit(_nrt=False)
def pair_contact_radius(n, B):
    """The squared contact radius a^2 = R_i^2 - ((R_i^2 - R_j^2 + L^2)/(2L))^2 of lanes
    0..n-1, L = R_i + R_j - delta (for the heat model; docs/design.md "Contact geometry")."""
    for l in range(uint(0), uint(n)):
        ri = B[RI + l]
        rj = B[RJ + l]
        L = (ri + rj) - B[DELTA + l]
        s = (ri * ri - rj * rj + L * L) * 0.5 / L
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
def dissipative_impulse(B, l, i, j, P, dt):
    """Add the dissipative force of lane ``l`` times dt to ``P.fd`` of i (and -F_d to j,
    if j >= 0) and its torques a_i n x F_d + M_r, a_j n x F_d - M_r times dt to ``P.td``
    (see :func:`gsi.dem.integrate.integrate_rows`: the second-order correction of the
    frictional heat)."""
    nx = B[NX + l]
    ny = B[NY + l]
    nz = B[NZ + l]
    fx = B[FDX + l] * dt
    fy = B[FDY + l] * dt
    fz = B[FDZ + l] * dt
    cx = ny * fz - nz * fy
    cy = nz * fx - nx * fz
    cz = nx * fy - ny * fx
    mx = B[MX + l] * dt
    my = B[MY + l] * dt
    mz = B[MZ + l] * dt
    a_i = B[AI + l]
    P.fd[i, 0] += fx
    P.fd[i, 1] += fy
    P.fd[i, 2] += fz
    P.td[i, 0] += a_i * cx + mx
    P.td[i, 1] += a_i * cy + my
    P.td[i, 2] += a_i * cz + mz
    if j >= 0:
        a_j = B[AJ + l]
        P.fd[j, 0] -= fx
        P.fd[j, 1] -= fy
        P.fd[j, 2] -= fz
        P.td[j, 0] += a_j * cx - mx
        P.td[j, 1] += a_j * cy - my
        P.td[j, 2] += a_j * cz - mz


@njit(_nrt=False)
def evaluate_runs(n, B, lrow, tab, dt, model):
    """:func:`gsi.dem.contact.model.evaluate` over lanes 0..n-1, one call per run of lanes
    that share a pair-table row (a loop-invariant row keeps the table reads out of the
    vectorizer's way); with one material type (a 1 x 1 table) one call, row 0, and
    ``lrow`` is not read (:func:`gather_pairs` did not write it)."""
    if tab.shape[0] == 1:
        evaluate(uint(0), n, B, tab, np.int64(0), dt, model)
        return
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
    its pairs added to both particles (Newton's third law), the springs stored (with
    frictional heating, ``heat_on`` is set too, and :func:`friction_pairs` follows)."""
    pair_geometry(n, B)
    if model[M_ROLLING] != 0:
        pair_inertia(n, B)
    if heat_on:
        pair_contact_radius(n, B)
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
            hist[k, 0] = B[HX + l]
            hist[k, 1] = B[HY + l]
            hist[k, 2] = B[HZ + l]
            if heat_on:
                Qp = B[Q + l]
                qi += Qp
                P.q[j] -= Qp
        f[i, 0] += fx
        f[i, 1] += fy
        f[i, 2] += fz
        tq[i, 0] += tx
        tq[i, 1] += ty
        tq[i, 2] += tz
        if heat_on:
            P.q[i] += qi


@njit(_nrt=False)
def friction_pairs(nrow, brow, blane, n, B, lj, P, dt, model):
    """Frictional heating of a pair batch after :func:`finish_pairs`: the dissipated power
    of its lanes (:func:`gsi.dem.contact.model.evaluate_dissipation`; it reads only lanes
    that :func:`finish_pairs` left as the contact model wrote them), half of it into each
    particle (``q``, and ``heat_friction`` += QF/2 dt), and the dissipative impulses.

    Called by the engine only with frictional heating on, and not from inside
    :func:`finish_pairs`: with these lines in it (behind a run-time switch) the engine
    ran 6-13 % slower with the switch off (docs/design.md, "Frictional heating")."""
    evaluate_dissipation(n, B, dt, model)
    for b in range(nrow):
        i = brow[b]
        for l in range(blane[b], blane[b + 1]):
            j = lj[l]
            h = 0.5 * B[QF + l]
            P.q[i] += h
            P.q[j] += h
            P.heat_friction[i] += h * dt
            P.heat_friction[j] += h * dt
            dissipative_impulse(B, l, np.int64(i), np.int64(j), P, dt)
