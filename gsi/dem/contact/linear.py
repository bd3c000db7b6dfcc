"""Linear spring–dashpot normal contact (the teaching-code model, LIGGGHTS ``hooke``).

For overlap delta > 0, with the simulation's normal stiffness k_n (N/m) and the pair
restitution e through beta = ln(e)/sqrt(ln(e)^2 + pi^2):

- gamma_n = -2 beta sqrt(k_n m*);  F_n = k_n delta + gamma_n v_n (v_n > 0 approaching).
  With tension allowed (as here, like LIGGGHTS), the restitution of a normal impact is
  exactly e and the contact lasts t_c = pi / sqrt(k_n/m* - (gamma_n/(2 m*))^2).
- for the tangential model: k_t = 2/7 k_n (the tangential and normal oscillation
  periods of a sphere equal), gamma_t = -2 beta sqrt(k_t m*).
"""
from gsi.jit import njit, sqrt, uint
from gsi.dem.contact.lanes import NX, NY, NZ, DELTA, VX, VY, VZ, MEFF, FN, KT, GT, GN
from gsi.dem.materials import P_BETA, P_KN

K_T_OVER_K_N = 2.0 / 7.0


@njit(_nrt=False)
def linear(l0, l1, B, tab, row, dt):
    """Normal force ``FN`` and tangential coefficients ``KT``, ``GT`` of lanes l0..l1-1
    (see :mod:`gsi.dem.contact.lanes`) for pair-table row ``row``."""
    beta = tab[row, P_BETA]
    k_n = tab[row, P_KN]
    k_t = K_T_OVER_K_N * k_n
    for l in range(uint(l0), uint(l1)):
        m_eff = B[MEFF + l]
        v_n = B[VX + l] * B[NX + l] + B[VY + l] * B[NY + l] + B[VZ + l] * B[NZ + l]
        gamma_n = -2.0 * beta * sqrt(k_n * m_eff)
        B[FN + l] = k_n * B[DELTA + l] + gamma_n * v_n
        B[GN + l] = gamma_n
        B[KT + l] = k_t
        B[GT + l] = -2.0 * beta * sqrt(k_t * m_eff)
