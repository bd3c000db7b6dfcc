"""Hertz–Mindlin contact with tangential history (the LIGGGHTS ``hertz`` model).

DESIGN.md "DEM physics", for overlap delta > 0:

- S_n = 2 E* sqrt(R* delta), S_t = 8 G* sqrt(R* delta)
- k_n = 4/3 E* sqrt(R* delta), gamma_n = -2 sqrt(5/6) beta sqrt(S_n m*)
- F_n = k_n delta + gamma_n v_n  (v_n > 0 approaching), along -n on particle i
- k_t = S_t, gamma_t = -2 sqrt(5/6) beta sqrt(S_t m*)
- xi (tangential spring, m): old xi rotated into the current tangent plane (its
  normal part removed, its length kept), then xi += v_t dt;
  F_t = -k_t xi - gamma_t v_t, capped at mu |F_n|; on the cap xi = -F_t/k_t so the
  spring alone gives the capped force.
"""
import math

from gsi.jit import njit, sqrt
from gsi.dem.contact.tangential import tangential_force
from gsi.dem.materials import P_E, P_G, P_BETA, P_MU, P_ST_SN

SQRT_5_6 = math.sqrt(5.0 / 6.0)


@njit(inline="always")   # into numba's IR: see gsi/dem/contact/__init__.py
def hertz(nx, ny, nz, delta, vx, vy, vz, R_eff, m_eff, tab, row, hx, hy, hz, dt):
    """Force on particle i of one Hertz–Mindlin contact.

    Parameters
    ----------
    nx, ny, nz : float
        Unit normal from particle i towards its partner (-).
    delta : float
        Overlap (m), > 0.
    vx, vy, vz : float
        Velocity of i relative to the partner at the contact point (m/s).
    R_eff, m_eff : float
        Effective radius R* (m) and mass m* (kg); a wall has R, m = infinity.
    tab, row : ndarray (ntypes^2, N_PAIR), int
        Pair table flattened over (type_i, type_j) and the row of this pair
        (see :mod:`gsi.dem.materials`); a row index instead of a row view keeps
        array reference counting out of the inner loop.
    hx, hy, hz : float
        The tangential spring (m) at the last step (0 for a new contact).
    dt : float
        Time step (s).

    Returns
    -------
    fx, fy, fz, F_n, hx, hy, hz : float
        Force on i (N), the normal force magnitude F_n (N, > 0 repulsive) and the new
        tangential spring (m), which the caller stores.
    """
    E_eff = tab[row, P_E]
    G_eff = tab[row, P_G]
    beta = tab[row, P_BETA]
    mu = tab[row, P_MU]
    sqrt_Rd = sqrt(R_eff * delta)
    S_n = 2.0 * E_eff * sqrt_Rd
    S_t = 8.0 * G_eff * sqrt_Rd
    k_n = 4.0 / 3.0 * E_eff * sqrt_Rd
    sqrt_Sn_m = sqrt(S_n * m_eff)
    gamma_n = -2.0 * SQRT_5_6 * beta * sqrt_Sn_m
    v_n = vx * nx + vy * ny + vz * nz
    F_n = k_n * delta + gamma_n * v_n
    # tangential relative velocity
    vtx = vx - v_n * nx
    vty = vy - v_n * ny
    vtz = vz - v_n * nz
    # tangential: the shared history spring with Coulomb cap (contact/tangential.py)
    k_t = S_t
    gamma_t = gamma_n * tab[row, P_ST_SN]        # sqrt(S_t m*) = sqrt(S_n m*) sqrt(4 G*/E*)
    ftx, fty, ftz, hx, hy, hz = tangential_force(nx, ny, nz, vtx, vty, vtz, F_n, k_t,
                                                 gamma_t, mu, hx, hy, hz, dt)
    return (-F_n * nx + ftx, -F_n * ny + fty, -F_n * nz + ftz, F_n, hx, hy, hz)
