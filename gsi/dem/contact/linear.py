"""Linear spring–dashpot normal contact (the teaching-code model, LIGGGHTS ``hooke``).

For overlap delta > 0, with the simulation's normal stiffness k_n (N/m) and the pair
restitution e through beta = ln(e)/sqrt(ln(e)^2 + pi^2):

- gamma_n = -2 beta sqrt(k_n m*);  F_n = k_n delta + gamma_n v_n (v_n > 0 approaching).
  With tension allowed (as here, like LIGGGHTS), the restitution of a normal impact is
  exactly e and the contact lasts t_c = pi / sqrt(k_n/m* - (gamma_n/(2 m*))^2).
- for the tangential model: k_t = 2/7 k_n (the tangential and normal oscillation
  periods of a sphere equal), gamma_t = -2 beta sqrt(k_t m*).
"""
from gsi.jit import njit, sqrt
from gsi.dem.contact.lanes import NX, NY, NZ, DELTA, VX, VY, VZ, MEFF, FN, KT, GT, GN
from gsi.dem.materials import P_BETA, P_KN

K_T_OVER_K_N = 2.0 / 7.0


@njit(_nrt=False)
def params(tab, row):
    """The constants of pair-table row ``row``: beta, k_n, k_t."""
    k_n = tab[row, P_KN]
    return tab[row, P_BETA], k_n, K_T_OVER_K_N * k_n


@njit(_nrt=False, inline="always")   # numba-inlined: the fused loop vectorizes
def lane(B, l, p):
    """Normal force ``FN`` (also ``GN``, ``KT``, ``GT``) of lane ``l`` (see
    :mod:`gsi.dem.contact.lanes`); returns F_n, k_t, gamma_t for the tangential model."""
    beta, k_n, k_t = p
    m_eff = B[MEFF + l]
    v_n = B[VX + l] * B[NX + l] + B[VY + l] * B[NY + l] + B[VZ + l] * B[NZ + l]
    gamma_n = -2.0 * beta * sqrt(k_n * m_eff)
    F_n = k_n * B[DELTA + l] + gamma_n * v_n
    gamma_t = -2.0 * beta * sqrt(k_t * m_eff)
    B[FN + l] = F_n
    B[GN + l] = gamma_n
    B[KT + l] = k_t
    B[GT + l] = gamma_t
    return F_n, k_t, gamma_t


#: the sub-model (:mod:`gsi.dem.contact.model`): its table constants and its lane
linear = (params, lane)
