"""Frictional heating: a tangential spring's energy when its contact ends becomes heat.

The incremental tangential spring (:mod:`gsi.dem.contact.tangential`) is not a
potential: a contact can end with a loaded spring (the linear law allows tension; under
Hertz k_t is small but not 0 at the last overlap), and the engine then restarts the
spring from zero.  With ``dem.frictional_heating`` on, :func:`book_ended_springs` runs at
the start of each slab task of the force pass, before the contacts are gathered: for
each sphere pair and plane contact of the last step that no longer touches (the same
tests as :func:`gsi.dem.pair_lanes.gather_pairs` and
:func:`gsi.dem.wall_lanes.gather_planes`), the spring's energy 1/2 k_t |xi|^2 at the last
step's overlap (rebuilt one drift back, x - v dt, as in
:mod:`gsi.dem.contact.dissipation`) goes into heat, half into each body (a plane's half
into its ``friction_heat``).  Mesh-triangle contacts are not covered: their end is
decided inside the triangle selection (:mod:`gsi.dem.mesh_dedup`) and their spring's
energy then leaves the book (docs/design.md, "Energy audit").
"""
import math

from gsi.jit import njit
from gsi.dem.contact.model import NORMAL, K_T_OVER_K_N
from gsi.dem.contact_geometry import spheres_touch, plane_distance
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
