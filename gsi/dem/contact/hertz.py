"""Hertz normal contact with its viscous damping (the LIGGGHTS ``hertz`` model).

docs/design.md, "DEM physics", for overlap delta > 0:

- S_n = 2 E* sqrt(R* delta), S_t = 8 G* sqrt(R* delta)
- k_n = 4/3 E* sqrt(R* delta), gamma_n = -2 sqrt(5/6) beta sqrt(S_n m*)
- F_n = k_n delta + gamma_n v_n  (v_n > 0 approaching), along -n on particle i
- for the tangential model: k_t = S_t, gamma_t = -2 sqrt(5/6) beta sqrt(S_t m*)
  = gamma_n sqrt(S_t/S_n)
"""
import math

from gsi.jit import njit, sqrt, uint
from gsi.dem.contact.lanes import (NX, NY, NZ, DELTA, VX, VY, VZ, REFF, MEFF, FN, KT, GT,
                                   GN)
from gsi.dem.materials import P_E, P_G, P_BETA, P_ST_SN

SQRT_5_6 = math.sqrt(5.0 / 6.0)


@njit(_nrt=False)
def hertz(l0, l1, B, tab, row, dt):
    """Normal force ``FN`` and tangential coefficients ``KT``, ``GT`` of lanes l0..l1-1
    (see :mod:`gsi.dem.contact.lanes`) for pair-table row ``row``."""
    E_eff = tab[row, P_E]
    G_eff = tab[row, P_G]
    beta = tab[row, P_BETA]
    st_sn = tab[row, P_ST_SN]        # sqrt(S_t/S_n) = sqrt(4 G*/E*), one root less
    for l in range(uint(l0), uint(l1)):
        delta = B[DELTA + l]
        sqrt_Rd = sqrt(B[REFF + l] * delta)
        S_n = 2.0 * E_eff * sqrt_Rd
        k_n = 4.0 / 3.0 * E_eff * sqrt_Rd
        gamma_n = -2.0 * SQRT_5_6 * beta * sqrt(S_n * B[MEFF + l])
        v_n = B[VX + l] * B[NX + l] + B[VY + l] * B[NY + l] + B[VZ + l] * B[NZ + l]
        B[FN + l] = k_n * delta + gamma_n * v_n
        B[GN + l] = gamma_n
        B[KT + l] = 8.0 * G_eff * sqrt_Rd
        B[GT + l] = gamma_n * st_sn
