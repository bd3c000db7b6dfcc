"""Frictional heating: the power a contact dissipates (docs/design.md, "Frictional heating").

With ``dem.frictional_heating`` on, the engine runs this after the contact model; it reads
what the normal, tangential and rolling sub-models left in the lanes
(:mod:`gsi.dem.contact.lanes`) and writes the dissipated power ``QF`` (W, >= 0):

    QF = gamma_n v_n^2                                  (normal damping)
       + gamma_t |v_t|^2                                 (tangential damping, in stick)
       + k_t (1/c - 1) |xi|^2/dt - gamma_t xi . v_t/dt   (sliding, c < 1)
       - M_r . (omega_i - omega_j)                       (rolling resistance)

with v the velocity of i relative to its partner at the contact point (the velocity the
force laws use), v_n = v . n, v_t = v - v_n n, xi the spring after the step and c the
Coulomb factor of :func:`gsi.dem.contact.tangential.history` (``CT``).  Sliding is
rigid-plastic: the friction force F_t does work -F_t . s dt on the slip s dt = xi_trial -
xi of the step (the part of the spring increment the cap cut off; xi_trial = xi/c -
gamma_t v_t/k_t), and nothing else dissipates while the spring is capped (the damping
is inside the capped force).  In stick the spring is elastic: only its damping
dissipates.  A contact's elastic energies (normal overlap, tangential spring) are not
heat: :mod:`gsi.dem.energy` books them.

The engine splits QF between the two bodies in equal halves (:mod:`gsi.dem.pair_lanes`,
:mod:`gsi.dem.wall_lanes`): Blok's partition by effusivity sqrt(k rho c) describes the
flash temperature of a sliding point contact over a time much shorter than a DEM
particle's conduction time; a particle's temperature is uniform in gsi, so the split
only decides which body's mean temperature rises, and equal halves need no material
data of a wall.
"""
from gsi.jit import njit, uint
from gsi.dem.contact.lanes import (NX, NY, NZ, VX, VY, VZ, WX, WY, WZ, HX, HY, HZ, KT, GT,
                                   MX, MY, MZ, FN, FX, FY, FZ, GN, CT, QF, FDX, FDY, FDZ)


@njit(_nrt=False)
def dissipation(l0, l1, B, dt):
    """The dissipated power ``QF`` (W) of lanes l0..l1-1 (module docstring; 0 for the
    sliding part when dt = 0, a force evaluation without a step) and the dissipative
    force on i, ``FDX..FDZ``: -gamma_n v_n n, plus -gamma_t v_t in stick or the whole
    tangential force when sliding (for the engine's second-order correction)."""
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
        c = B[CT + l]
        gn_vn = B[GN + l] * v_n
        q = gn_vn * v_n
        if c == 1.0:
            q += gamma_t * (vtx * vtx + vty * vty + vtz * vtz)
            fdx = -gamma_t * vtx
            fdy = -gamma_t * vty
            fdz = -gamma_t * vtz
        else:
            F_n = B[FN + l]
            fdx = B[FX + l] + F_n * nx
            fdy = B[FY + l] + F_n * ny
            fdz = B[FZ + l] + F_n * nz
        B[FDX + l] = fdx - gn_vn * nx
        B[FDY + l] = fdy - gn_vn * ny
        B[FDZ + l] = fdz - gn_vn * nz
        if 0.0 < c < 1.0:
            xx = B[HX + l]
            xy = B[HY + l]
            xz = B[HZ + l]
            q += (B[KT + l] * (1.0 / c - 1.0) * (xx * xx + xy * xy + xz * xz)
                  - gamma_t * (xx * vtx + xy * vty + xz * vtz)) * inv_dt
        q -= B[MX + l] * B[WX + l] + B[MY + l] * B[WY + l] + B[MZ + l] * B[WZ + l]
        B[QF + l] = q
