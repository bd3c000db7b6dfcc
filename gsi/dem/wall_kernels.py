"""Law-independent wall kernels: wall motion and the serial sums of wall loads.

Cached numba functions called by the engine (:mod:`gsi.dem.engine`); ``pl`` is the :data:`gsi.dem.state.Planes` bundle,
``M`` the :data:`gsi.dem.state.Mesh` bundle, ``wc`` the
:data:`gsi.dem.state.WallContacts` bundle.
"""
import math

from gsi.jit import njit


@njit
def move_walls(dt, pl, M):
    """Advance planes (point += v dt) and mesh vertices by one step; return the largest
    squared displacement of a plane or vertex since the last neighbour build (m^2).

    Rigid walls (``M.wall_rigid``) rotate exactly by omega dt about their centre and
    translate with ``M.wall_velocity``; their vertex velocities are
    v = vel + omega x (x - c).  Other walls move each vertex with its own velocity:
    x += v dt.
    """
    dmax = 0.0
    for p in range(pl.point.shape[0]):
        d2 = 0.0
        for d in range(3):
            pl.point[p, d] += dt * pl.velocity[p, d]
            dd = pl.point[p, d] - pl.point0[p, d]
            d2 += dd * dd
        if d2 > dmax:
            dmax = d2
    mx = M.x
    mv = M.v
    vel = M.wall_velocity
    for q in range(M.wall_rigid.shape[0]):
        if M.wall_rigid[q]:
            for d in range(3):
                M.wall_centre[q, d] += dt * vel[q, d]
    for a in range(mx.shape[0]):
        q = M.vertex_wall[a]
        if M.wall_rigid[q]:
            ox = M.wall_omega[q, 0]
            oy = M.wall_omega[q, 1]
            oz = M.wall_omega[q, 2]
            om = math.sqrt(ox * ox + oy * oy + oz * oz)
            cx = M.wall_centre[q, 0]
            cy = M.wall_centre[q, 1]
            cz = M.wall_centre[q, 2]
            # position relative to the (already moved) centre, before rotation
            rx = mx[a, 0] + dt * vel[q, 0] - cx
            ry = mx[a, 1] + dt * vel[q, 1] - cy
            rz = mx[a, 2] + dt * vel[q, 2] - cz
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
            mx[a, 0] = cx + rx
            mx[a, 1] = cy + ry
            mx[a, 2] = cz + rz
            mv[a, 0] = vel[q, 0] + oy * rz - oz * ry
            mv[a, 1] = vel[q, 1] + oz * rx - ox * rz
            mv[a, 2] = vel[q, 2] + ox * ry - oy * rx
        else:
            for d in range(3):
                mx[a, d] += dt * mv[a, d]
        d2 = 0.0
        for d in range(3):
            dd = mx[a, d] - M.x0[a, d]
            d2 += dd * dd
        if d2 > dmax:
            dmax = d2
    return dmax


@njit
def plane_sums(dt, pl_acc, pl):
    """Force and torque of the particles ON each plane (torque about the plane's point)
    from the per-slab sums ``pl_acc`` (nslab, npl, 8) of the force pass; accumulate the
    impulse on the particles (N s), the heat to them (J), the frictional heat into the
    plane (J) and the plane's work on the particles, F . v_plane dt (J); clear the sums."""
    pl.force[:] = 0.0
    pl.torque[:] = 0.0
    for s in range(pl_acc.shape[0]):
        for p in range(pl_acc.shape[1]):
            for d in range(3):
                pl.force[p, d] -= pl_acc[s, p, d]
                pl.torque[p, d] -= pl_acc[s, p, 3 + d]
                pl.impulse[p, d] += pl_acc[s, p, d] * dt
                pl.work[p] += pl_acc[s, p, d] * pl.velocity[p, d] * dt
            pl.heat[p] += pl_acc[s, p, 6] * dt
            pl.friction_heat[p] += pl_acc[s, p, 7] * dt
    pl_acc[:] = 0.0


@njit
def p2_weight(j, la, lb, lc):
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
def mesh_scatter(dt, wc, M):
    """Serial scatter of triangle contacts: wall force/torque (about the wall centre)
    and triangle forces ON the wall (this step), and the coupling accumulators
    vertex_impulse += -F N_k dt, vertex_heat += (Q_f - Q) N_k dt,
    wall_impulse += F dt, wall_heat += Q dt, wall_friction_heat += Q_f dt (Q_f the wall's
    share of the frictional heat, :mod:`gsi.dem.contact.dissipation`: it reaches the FE
    heat solve through the same nodal loads as conduction) and the wall's work on the
    particles wall_work += F . v dt (v the wall's velocity at the contact point).  N_k are
    the barycentric weights w_k of the contact point, or, for a triangle with a quadratic parent (``M.tri_p6[t, 0] >= 0``), the six P2
    basis values at the point's parent coordinates l = sum_k w_k tri_lam[t, k]."""
    M.wall_force[:] = 0.0
    M.wall_torque[:] = 0.0
    M.tri_force[:] = 0.0
    for i in range(wc.count.shape[0]):
        for s in range(wc.count[i]):
            t = wc.tri[i, s]
            wl = M.tri_wall[t]
            Fx = wc.force[i, s, 0]
            Fy = wc.force[i, s, 1]
            Fz = wc.force[i, s, 2]
            Q = wc.heat[i, s]
            Qf = wc.fheat[i, s]
            M.wall_force[wl, 0] -= Fx
            M.wall_force[wl, 1] -= Fy
            M.wall_force[wl, 2] -= Fz
            M.tri_force[t, 0] -= Fx
            M.tri_force[t, 1] -= Fy
            M.tri_force[t, 2] -= Fz
            rx = wc.point[i, s, 0] - M.wall_centre[wl, 0]
            ry = wc.point[i, s, 1] - M.wall_centre[wl, 1]
            rz = wc.point[i, s, 2] - M.wall_centre[wl, 2]
            M.wall_torque[wl, 0] -= ry * Fz - rz * Fy
            M.wall_torque[wl, 1] -= rz * Fx - rx * Fz
            M.wall_torque[wl, 2] -= rx * Fy - ry * Fx
            quad = M.tri_p6[t, 0] >= 0
            la = 0.0
            lb = 0.0
            lc = 0.0
            if quad:
                for c in range(3):
                    wk = wc.weight[i, s, c]
                    la += wk * M.tri_lam[t, c, 0]
                    lb += wk * M.tri_lam[t, c, 1]
                    lc += wk * M.tri_lam[t, c, 2]
            for j in range(6 if quad else 3):
                if quad:
                    a = M.tri_p6[t, j]
                    wk = p2_weight(j, la, lb, lc)
                else:
                    a = M.tri[t, j]
                    wk = wc.weight[i, s, j]
                M.vertex_impulse[a, 0] -= Fx * wk * dt
                M.vertex_impulse[a, 1] -= Fy * wk * dt
                M.vertex_impulse[a, 2] -= Fz * wk * dt
                M.vertex_heat[a] += (Qf - Q) * wk * dt
            vx = 0.0
            vy = 0.0
            vz = 0.0
            for j in range(3):
                a = M.tri[t, j]
                wk = wc.weight[i, s, j]
                vx += wk * M.v[a, 0]
                vy += wk * M.v[a, 1]
                vz += wk * M.v[a, 2]
            M.wall_work[wl] += (Fx * vx + Fy * vy + Fz * vz) * dt
            M.wall_friction_heat[wl] += Qf * dt
            M.wall_impulse[wl, 0] += Fx * dt
            M.wall_impulse[wl, 1] += Fy * dt
            M.wall_impulse[wl, 2] += Fz * dt
            M.wall_heat[wl] += Q * dt
