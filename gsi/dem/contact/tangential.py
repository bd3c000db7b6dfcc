"""Tangential history spring with Coulomb cap, shared by the contact laws.

DESIGN.md "DEM physics": the spring xi (m) of a contact is rotated into the current tangent
plane (its normal part removed, its length kept), then xi += v_t dt; the force is
F_t = -k_t xi - gamma_t v_t, capped at mu |F_n|; on the cap xi = -F_t / k_t, so that the
spring alone gives the capped force. The laws differ only in k_t and gamma_t.
"""
from gsi.jit import njit, sqrt


@njit(inline="always")   # into numba's IR: see gsi/dem/contact/__init__.py
def tangential_force(nx, ny, nz, vtx, vty, vtz, F_n, k_t, gamma_t, mu, xx, xy, xz, dt):
    """Tangential force on particle i (N) and the updated spring (m).

    Parameters
    ----------
    nx, ny, nz : float
        Unit contact normal (-).
    vtx, vty, vtz : float
        Tangential relative velocity at the contact point (m/s).
    F_n : float
        Normal force (N), for the Coulomb cap mu |F_n|.
    k_t, gamma_t : float
        Tangential stiffness (N/m) and damping coefficient (N s/m, <= 0 as beta).
    mu : float
        Friction coefficient (-).
    xx, xy, xz : float
        The spring at the last step (m).
    dt : float
        Time step (s).

    Returns
    -------
    ftx, fty, ftz, xx, xy, xz : float
        The force and the new spring; the caller stores the spring (the law touches no
        memory, so a loop of laws over a batch of contacts vectorizes).
    """
    old2 = xx * xx + xy * xy + xz * xz
    if old2 > 0.0:
        xn = xx * nx + xy * ny + xz * nz
        xx -= xn * nx
        xy -= xn * ny
        xz -= xn * nz
        new2 = xx * xx + xy * xy + xz * xz
        if new2 > 0.0:
            s = sqrt(old2 / new2)
            xx *= s
            xy *= s
            xz *= s
    xx += vtx * dt
    xy += vty * dt
    xz += vtz * dt
    ftx = -k_t * xx - gamma_t * vtx
    fty = -k_t * xy - gamma_t * vty
    ftz = -k_t * xz - gamma_t * vtz
    # |F_t| > cap compared squared: the square root only for a sliding contact (the
    # settled bed's force pass 2.3-4.4 % faster in three interleaved runs of
    # benchmarks/engine_ab.py, one thread, a shared machine); inside, ft2 > 0
    ft2 = ftx * ftx + fty * fty + ftz * ftz
    cap = mu * abs(F_n)
    if ft2 > cap * cap:
        s = cap / sqrt(ft2)
        ftx *= s
        fty *= s
        ftz *= s
        xx = -ftx / k_t
        xy = -fty / k_t
        xz = -ftz / k_t
    return ftx, fty, ftz, xx, xy, xz
