"""Frictional heating: a tangential spring's energy when its contact ends becomes heat.

The incremental tangential spring (:mod:`gsi.dem.contact.tangential`) is not a
potential: a contact can end with a loaded spring (the linear law allows tension; under
Hertz k_t is small but not 0 at the last overlap), and the engine then restarts the
spring from zero.  With ``dem.frictional_heating`` on, :func:`book_ended_springs` runs at
the start of each slab task of the force pass, before the contacts are gathered: for
each sphere pair and plane contact of the last step that no longer touches (the same
tests as :func:`gsi.dem.pair_lanes.gather_pairs` and
:func:`gsi.dem.wall_lanes.gather_walls`), the spring's energy 1/2 k_t |xi|^2 at the last
step's overlap (rebuilt one drift back, x - v dt, as in
:mod:`gsi.dem.contact.dissipation`) goes into heat, half into each body (a plane's half
into its ``friction_heat``).

A mesh-triangle contact ends inside the triangle selection
(:func:`gsi.dem.mesh_dedup.select_triangle_contacts`: the triangle no longer touches, or
a neighbouring triangle of the same surface takes the contact over, as when a sphere
slides across an edge); the selection calls :func:`book_ended_triangle` before it
restarts the spring.  Its overlap one drift back is that of the triangle's closest point
to x - v dt, the vertices also one drift back (X - V dt): exact to round-off for a
standing or translating wall, first order in dt for a rotating one or one whose vertices
are set between steps (a coupled structure).  All of its energy heats the particle: the
wall's half has no slot to go through (the slots are this step's contacts, and the
particle's selection runs in parallel with the others', so it cannot add to the wall's
accumulators).
"""
import math

from gsi.jit import njit
from gsi.dem.contact.model import NORMAL, K_T_OVER_K_N
from gsi.dem.contact_geometry import spheres_touch, plane_distance
from gsi.dem.geometry import closest_point_triangle
from gsi.dem.materials import P_G, P_KN

#: the index of the Hertz law in the normal registry
HERTZ = list(NORMAL).index("hertz")


@njit
def spring_energy(normal, tab, row, R_eff, delta, h0, h1, h2):
    """1/2 k_t |xi|^2 (J) of a spring xi = (h0, h1, h2) at overlap ``delta`` (m) with the
    normal law ``normal`` (its index in :data:`gsi.dem.contact.model.NORMAL`)."""
    if normal == HERTZ:
        k_t = 8.0 * tab[row, P_G] * math.sqrt(R_eff * max(delta, 0.0))
    else:
        k_t = K_T_OVER_K_N * tab[row, P_KN]
    return 0.5 * k_t * (h0 * h0 + h1 * h1 + h2 * h2)


@njit
def book_ended_springs(sl, P, pairs, pl, wc, plh, tab, nt, dt, normal, pl_acc):
    """The springs of the contacts of slab ``sl``'s particles that ended at this step into
    heat (module docstring): ``P.q`` += E/(2 dt) and ``P.heat_friction`` += E/2 for
    each particle, ``pl_acc[sl, p, 7]`` += E/(2 dt) for plane p.  A pair is stored at
    the particle of the lower slab, so its partner is in slab ``sl`` or ``sl + 1``."""
    x = P.x
    v = P.v
    npl = pl.point.shape[0]
    half_rate = 0.5 / dt
    for m in range(pairs.slab_start[sl], pairs.slab_start[sl + 1]):
        i = pairs.slab_list[m]
        ri = P.radius[i]
        row_i = P.type[i] * nt
        for k in range(pairs.start[i], pairs.start[i + 1]):
            if pairs.active[k] == 0:
                continue
            j = pairs.j[k]
            rj = P.radius[j]
            dx = x[j, 0] - x[i, 0]
            dy = x[j, 1] - x[i, 1]
            dz = x[j, 2] - x[i, 2]
            if spheres_touch(dx * dx + dy * dy + dz * dz, ri + rj):
                continue
            # the offset one drift back: d - (v_j - v_i) dt
            ex = dx - (v[j, 0] - v[i, 0]) * dt
            ey = dy - (v[j, 1] - v[i, 1]) * dt
            ez = dz - (v[j, 2] - v[i, 2]) * dt
            delta = ri + rj - math.sqrt(ex * ex + ey * ey + ez * ez)
            h = pairs.hist[k]
            E = spring_energy(normal, tab, row_i + P.type[j], ri * rj / (ri + rj), delta,
                              h[0], h[1], h[2])
            P.q[i] += E * half_rate
            P.q[j] += E * half_rate
            P.heat_friction[i] += 0.5 * E
            P.heat_friction[j] += 0.5 * E
        ended = wc.plane_mask[i] & wc.plane_cand[i]
        if ended == 0:
            continue
        for p in range(npl):
            if not (ended >> p) & 1:
                continue
            Nx = pl.normal[p, 0]
            Ny = pl.normal[p, 1]
            Nz = pl.normal[p, 2]
            dist = plane_distance(x[i, 0], x[i, 1], x[i, 2], pl.point[p, 0], pl.point[p, 1],
                                  pl.point[p, 2], Nx, Ny, Nz)
            if ri - dist > 0.0:
                continue
            # one drift back: delta + (v_i - v_plane) . N dt
            vN = ((v[i, 0] - pl.velocity[p, 0]) * Nx + (v[i, 1] - pl.velocity[p, 1]) * Ny
                  + (v[i, 2] - pl.velocity[p, 2]) * Nz)
            h = plh[i * npl + p]
            E = spring_energy(normal, tab, row_i + pl.type[p], ri, ri - dist + vN * dt,
                              h[0], h[1], h[2])
            P.q[i] += E * half_rate
            P.heat_friction[i] += 0.5 * E
            pl_acc[sl, p, 7] += E * half_rate


@njit
def book_ended_triangle(i, k, P, pairs, M, tab, row_i, dt, normal):
    """The spring ``pairs.tri_hist[k]`` of particle i's triangle candidate k, whose
    contact ended at this step, into the particle's heat (module docstring):
    ``P.q[i]`` += E/dt, ``P.heat_friction[i]`` += E with E = 1/2 k_t |xi|^2 at the last
    step's overlap.  A zero spring (no contact at the last step) books nothing."""
    h = pairs.tri_hist[k]
    if h[0] == 0.0 and h[1] == 0.0 and h[2] == 0.0:
        return
    t = pairs.tri[k]
    a = M.tri[t, 0]
    b = M.tri[t, 1]
    c = M.tri[t, 2]
    X = M.x
    V = M.v
    px = P.x[i, 0] - P.v[i, 0] * dt
    py = P.x[i, 1] - P.v[i, 1] * dt
    pz = P.x[i, 2] - P.v[i, 2] * dt
    qx, qy, qz, _, _, _, _ = closest_point_triangle(
        px, py, pz, X[a, 0] - V[a, 0] * dt, X[a, 1] - V[a, 1] * dt, X[a, 2] - V[a, 2] * dt,
        X[b, 0] - V[b, 0] * dt, X[b, 1] - V[b, 1] * dt, X[b, 2] - V[b, 2] * dt,
        X[c, 0] - V[c, 0] * dt, X[c, 1] - V[c, 1] * dt, X[c, 2] - V[c, 2] * dt)
    ri = P.radius[i]
    delta = ri - math.sqrt((qx - px) ** 2 + (qy - py) ** 2 + (qz - pz) ** 2)
    E = spring_energy(normal, tab, row_i + M.wall_type[M.tri_wall[t]], ri, delta,
                      h[0], h[1], h[2])
    P.q[i] += E / dt
    P.heat_friction[i] += E
