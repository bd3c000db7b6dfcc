"""Linear spring–dashpot contact with tangential history (teaching-code model).

For overlap delta > 0, with the simulation's normal stiffness k_n (N/m) and the pair
restitution e through beta = ln(e)/sqrt(ln(e)^2 + pi^2):

- gamma_n = -2 beta sqrt(k_n m*);  F_n = k_n delta + gamma_n v_n (v_n > 0 approaching).
  With tension allowed (as here, like LIGGGHTS), the restitution of a normal impact is
  exactly e and the contact lasts t_c = pi / sqrt(k_n/m* - (gamma_n/(2 m*))^2).
- Tangential: k_t = 2/7 k_n (the choice that makes the tangential and normal
  oscillation periods of a sphere equal), gamma_t = -2 beta sqrt(k_t m*), the same
  history spring, rotation and Coulomb cap mu |F_n| as :mod:`gsi.dem.contact.hertz`.
"""
from gsi.jit import njit, sqrt
from gsi.dem.contact.tangential import tangential_force
from gsi.dem.materials import P_BETA, P_MU, P_KN

K_T_OVER_K_N = 2.0 / 7.0


@njit(inline="always")   # into numba's IR: see gsi/dem/contact/__init__.py
def linear(nx, ny, nz, delta, vx, vy, vz, R_eff, m_eff, tab, row, hx, hy, hz, dt):
    """Force on particle i of one linear spring–dashpot contact.

    Same arguments and returns as :func:`gsi.dem.contact.hertz.hertz`.
    """
    beta = tab[row, P_BETA]
    mu = tab[row, P_MU]
    k_n = tab[row, P_KN]
    gamma_n = -2.0 * beta * sqrt(k_n * m_eff)
    v_n = vx * nx + vy * ny + vz * nz
    F_n = k_n * delta + gamma_n * v_n
    vtx = vx - v_n * nx
    vty = vy - v_n * ny
    vtz = vz - v_n * nz
    k_t = K_T_OVER_K_N * k_n
    gamma_t = -2.0 * beta * sqrt(k_t * m_eff)
    ftx, fty, ftz, hx, hy, hz = tangential_force(nx, ny, nz, vtx, vty, vtz, F_n, k_t,
                                                 gamma_t, mu, hx, hy, hz, dt)
    return (-F_n * nx + ftx, -F_n * ny + fty, -F_n * nz + ftz, F_n, hx, hy, hz)
