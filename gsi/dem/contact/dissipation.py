"""Frictional heating: the power a contact dissipates (docs/design.md, "Frictional heating").

With ``dem.frictional_heating`` on, the engine runs this after the contact model; it reads
what the normal, tangential and rolling sub-models left in the lanes
(:mod:`gsi.dem.contact.lanes`) and writes the dissipated power ``QF`` (W):

    QF = gamma_n v_n^2                              (normal damping)
       - F_t . v_t - (E_t - E_t,old)/dt             (the tangential spring and friction)
       - M_r . (omega_i - omega_j)                  (rolling resistance)

with v the velocity of i relative to its partner at the contact point (the velocity the
force laws use), v_n = v . n, v_t = v - v_n n, F_t the tangential force on i (spring,
damping and Coulomb cap together), E_t = 1/2 k_t |xi|^2 the spring's energy after the
step and E_t,old = 1/2 k_t,old |xi_old|^2 its energy before it (the stiffness of the
previous overlap, the spring as stored).  The tangential term is the work the bodies do
on the contact's tangential part minus the change of its stored energy: in stick with a
constant k_t it is the damping gamma_t |v_t|^2 (to time-integration error), in sliding
the friction force on the slip; it also books, as heat, every change of the spring's
energy that is not work of the tangential force on the relative tangential
displacement -- k_t changing with the overlap while xi is held (Hertz), the spring's
rotation into the new tangent plane and its truncation at the Coulomb cap (the
incremental spring is not a potential).  A spring's energy when its contact ends is
booked as heat by :mod:`gsi.dem.spring_heat`.  Nothing here changes a force.

The old energy is rebuilt from the lanes, without a stored field: |xi_old| is the
length of the rotated spring xi_r = xi_trial - v_t dt (rotation keeps the length;
xi_trial = xi in stick, xi/c - gamma_t v_t/k_t on the cap, c the Coulomb factor ``CT``
of :func:`gsi.dem.contact.tangential.history`; with c = 0, no friction, the old spring
counts as 0: exact for mu = 0, a spring held into a step of exactly zero normal force is
missed), and the previous overlap is that of the
positions one drift back, x - v dt (the integrator's drift, :mod:`gsi.dem.integrate`):
for a sphere pair |L n + u dt| with u = v_i - v_j = v - (a_i omega_i + a_j omega_j) x n,
exactly; for a wall delta - v_n dt (exact for a plane moving by its velocity; a mesh
triangle's closest point or a rotating plane make it first order in dt).

``FD`` (the dissipative force on i, for the engine's second-order correction that pairs
the heat with the full-step velocity) is the normal damping force plus the whole
tangential force: the tangential term then uses the work the integrator really gives
the bodies, so a contact's dissipated energy is the work of its forces minus the change
of its stored energy, step by step (:mod:`gsi.dem.energy`).

The engine splits QF between the two bodies in equal halves (:mod:`gsi.dem.pair_lanes`,
:mod:`gsi.dem.wall_lanes`): Blok's partition by effusivity sqrt(k rho c) describes the
flash temperature of a sliding point contact over a time much shorter than a DEM
particle's conduction time; a particle's temperature is uniform in gsi, so the split
only decides which body's mean temperature rises, and equal halves need no material
data of a wall.
"""
import math

from gsi.jit import njit, sqrt, uint
from gsi.dem.contact.lanes import (NX, NY, NZ, VX, VY, VZ, WX, WY, WZ, HX, HY, HZ, KT, GT,
                                   MX, MY, MZ, FN, FX, FY, FZ, GN, CT, QF, FDX, FDY, FDZ,
                                   DELTA, RI, RJ, AI, AJ, WIX, WIY, WIZ)


@njit(_nrt=False)
def previous_overlap(l, B, dt):
    """The overlap (m) of lane ``l`` one drift back (module docstring), not below 0."""
    nx = B[NX + l]
    ny = B[NY + l]
    nz = B[NZ + l]
    vx = B[VX + l]
    vy = B[VY + l]
    vz = B[VZ + l]
    v_n = vx * nx + vy * ny + vz * nz
    delta = B[DELTA + l]
    rj = B[RJ + l]
    if math.isinf(rj):                     # a wall
        d0 = delta - v_n * dt
    else:                                  # a sphere pair: remove the rotation's part
        a_i = B[AI + l]
        a_j = B[AJ + l]
        wix = B[WIX + l]
        wiy = B[WIY + l]
        wiz = B[WIZ + l]
        wsx = a_i * wix + a_j * (wix - B[WX + l])
        wsy = a_i * wiy + a_j * (wiy - B[WY + l])
        wsz = a_i * wiz + a_j * (wiz - B[WZ + l])
        ux = vx - v_n * nx - (wsy * nz - wsz * ny)
        uy = vy - v_n * ny - (wsz * nx - wsx * nz)
        uz = vz - v_n * nz - (wsx * ny - wsy * nx)
        L = (B[RI + l] + rj) - delta
        vn_dt = v_n * dt
        # L0 - L = (L0^2 - L^2)/(L0 + L), without cancellation
        num = 2.0 * L * vn_dt + vn_dt * vn_dt + (ux * ux + uy * uy + uz * uz) * dt * dt
        L0 = sqrt((L + vn_dt) ** 2 + (ux * ux + uy * uy + uz * uz) * dt * dt)
        d0 = delta - num / (L0 + L)
    return d0 if d0 > 0.0 else 0.0


@njit(_nrt=False)
def dissipation(l0, l1, B, dt, kt_power):
    """The dissipated power ``QF`` (W) of lanes l0..l1-1 (module docstring; its spring
    part is 0 when dt = 0, a force evaluation without a step) and the dissipative force
    on i, ``FDX..FDZ``: -gamma_n v_n n plus the tangential force.  ``kt_power``: k_t of
    the normal model grows as delta^kt_power (Hertz 0.5, linear 0)."""
    inv_dt = 1.0 / dt if dt > 0.0 else 0.0
    for l in range(uint(l0), uint(l1)):
        nx = B[NX + l]
        ny = B[NY + l]
        nz = B[NZ + l]
        vx = B[VX + l]
        vy = B[VY + l]
        vz = B[VZ + l]
        v_n = vx * nx + vy * ny + vz * nz
        vtx = vx - v_n * nx
        vty = vy - v_n * ny
        vtz = vz - v_n * nz
        gamma_t = B[GT + l]
        k_t = B[KT + l]
        c = B[CT + l]
        gn_vn = B[GN + l] * v_n
        F_n = B[FN + l]
        ftx = B[FX + l] + F_n * nx          # the tangential force on i
        fty = B[FY + l] + F_n * ny
        ftz = B[FZ + l] + F_n * nz
        B[FDX + l] = ftx - gn_vn * nx
        B[FDY + l] = fty - gn_vn * ny
        B[FDZ + l] = ftz - gn_vn * nz
        xx = B[HX + l]
        xy = B[HY + l]
        xz = B[HZ + l]
        # the rotated old spring: xi_trial - v_t dt
        if c == 0.0:         # no friction (mu |F_n| = 0): the spring was 0 before too
            rx = 0.0
            ry = 0.0
            rz = 0.0
        elif c < 1.0:
            g = gamma_t / k_t
            rx = xx / c - g * vtx - vtx * dt
            ry = xy / c - g * vty - vty * dt
            rz = xz / c - g * vtz - vtz * dt
        else:
            rx = xx - vtx * dt
            ry = xy - vty * dt
            rz = xz - vtz * dt
        k_old = k_t
        if kt_power != 0.0:
            delta = B[DELTA + l]
            k_old = k_t * (previous_overlap(l, B, dt) / delta) ** kt_power
        dE = 0.5 * (k_t * (xx * xx + xy * xy + xz * xz) - k_old * (rx * rx + ry * ry + rz * rz))
        q = gn_vn * v_n - (ftx * vtx + fty * vty + ftz * vtz) - dE * inv_dt
        q -= B[MX + l] * B[WX + l] + B[MY + l] * B[WY + l] + B[MZ + l] * B[WZ + l]
        B[QF + l] = q
