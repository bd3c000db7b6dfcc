"""Contact conductance models of particle heat conduction (DESIGN.md "Heat in particles").

Q_ij = H_ij (T_j - T_i) with contact radius a (a^2 given, m^2):

- ``area``     H = 4 k_i k_j/(k_i + k_j) sqrt(A), A = pi a^2   (LIGGGHTS, Haydar et al.)
- ``radius``   H = 4 k_i k_j/(k_i + k_j) a                       (Batchelor & O'Brien)
- ``constant`` H = h_c                                          (teaching codes)

A model is ``H(a2, tab, row) -> W/K`` reading row ``row`` of the flattened pair table.  Keep heat terms
additive: another term (radiation) is a further sum in the engine.
"""
import math

from gsi.jit import njit
from gsi.dem.materials import P_KH, P_HC


@njit
def area(a2, tab, row):
    """H = 4 k_i k_j/(k_i + k_j) sqrt(pi a^2) (W/K)."""
    return tab[row, P_KH] * math.sqrt(math.pi * a2) if a2 > 0.0 else 0.0


@njit
def radius(a2, tab, row):
    """H = 4 k_i k_j/(k_i + k_j) a (W/K)."""
    return tab[row, P_KH] * math.sqrt(a2) if a2 > 0.0 else 0.0


@njit
def constant(a2, tab, row):
    """H = h_c (W/K) for every touching pair."""
    return tab[row, P_HC]


@njit
def none(a2, tab, row):
    """No conduction."""
    return 0.0


HEAT_MODELS = {
    None: ("gsi.dem.heat", "none"),
    "area": ("gsi.dem.heat", "area"),
    "radius": ("gsi.dem.heat", "radius"),
    "constant": ("gsi.dem.heat", "constant"),
}
