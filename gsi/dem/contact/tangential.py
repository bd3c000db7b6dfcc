"""Tangential history spring with Coulomb cap (the LIGGGHTS ``tangential history``).

docs/design.md, "DEM physics": the spring xi (m) of a contact is rotated into the current
tangent plane (its normal part removed, its length kept), then xi += v_t dt; the force is
F_t = -k_t xi - gamma_t v_t, capped at mu |F_n|; on the cap xi = -F_t / k_t, so that the
spring alone gives the capped force (the factor of the cap, exactly 1 in stick, goes to
``CT`` for :mod:`gsi.dem.contact.dissipation`).  k_t and gamma_t come from the normal model
(fields ``KT``, ``GT``); the total force F = -F_n n + F_t is written to ``FX..FZ``.
"""
from gsi.jit import njit, sqrt, uint
from gsi.dem.contact.lanes import (NX, NY, NZ, VX, VY, VZ, HX, HY, HZ, FN, KT, GT, FX, FY,
                                   FZ, CT)
from gsi.dem.materials import P_MU


@njit(_nrt=False)
def history(l0, l1, B, tab, row, dt):
    """The total force ``FX..FZ`` on i and the new spring ``HX..HZ`` of lanes l0..l1-1."""
    mu = tab[row, P_MU]
    for l in range(uint(l0), uint(l1)):
        nx = B[NX + l]
        ny = B[NY + l]
        nz = B[NZ + l]
        vx = B[VX + l]
        vy = B[VY + l]
        vz = B[VZ + l]
        F_n = B[FN + l]
        k_t = B[KT + l]
        gamma_t = B[GT + l]
        v_n = vx * nx + vy * ny + vz * nz
        vtx = vx - v_n * nx
        vty = vy - v_n * ny
        vtz = vz - v_n * nz
        xx = B[HX + l]
        xy = B[HY + l]
        xz = B[HZ + l]
        # rotate the old spring into the tangent plane, keeping its length
        old2 = xx * xx + xy * xy + xz * xz
        xn = xx * nx + xy * ny + xz * nz
        xx -= xn * nx
        xy -= xn * ny
        xz -= xn * nz
        new2 = xx * xx + xy * xy + xz * xz
        s = sqrt(old2 / new2) if new2 > 0.0 else 1.0
        xx = xx * s + vtx * dt
        xy = xy * s + vty * dt
        xz = xz * s + vtz * dt
        ftx = -k_t * xx - gamma_t * vtx
        fty = -k_t * xy - gamma_t * vty
        ftz = -k_t * xz - gamma_t * vtz
        # Coulomb cap, compared squared; on the cap the spring alone gives the force
        ft2 = ftx * ftx + fty * fty + ftz * ftz
        cap = mu * abs(F_n)
        slide = ft2 > cap * cap
        c = cap / sqrt(ft2) if slide else 1.0
        ftx *= c
        fty *= c
        ftz *= c
        if slide:               # one division, not three (a loop of lanes computes both
            r = -1.0 / k_t      # sides of the select)
            xx = ftx * r
            xy = fty * r
            xz = ftz * r
        B[CT + l] = c
        B[HX + l] = xx
        B[HY + l] = xy
        B[HZ + l] = xz
        B[FX + l] = -F_n * nx + ftx
        B[FY + l] = -F_n * ny + fty
        B[FZ + l] = -F_n * nz + ftz
