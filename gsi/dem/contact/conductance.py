"""Contact conductance models of particle heat conduction (docs/design.md, "Heat in particles").

Q_ij = H_ij (T_j - T_i) with contact radius a (a^2 given, m^2):

- ``area``     H = 4 k_i k_j/(k_i + k_j) sqrt(A), A = pi a^2   (LIGGGHTS, Haydar et al.)
- ``radius``   H = 4 k_i k_j/(k_i + k_j) a                       (Batchelor & O'Brien)
- ``constant`` H = h_c                                          (teaching codes)
- ``pipe``     H = w/(R_i + R_j + R_c*)                         (Feng et al.'s pipe network)

``pipe`` is the discrete thermal element of Feng, Han, Li and Owen (J. Comput. Phys. 227,
2008; Powder Technol. 193, 2009) as the FDEM contact-heat paper (seed 002, section 5)
states it: each particle is a long cylinder (a "pipe") of radius r and length w whose
contact is an arc of half angle alpha, sin alpha = a/r, with the thermal resistance per
unit length

    R_A = (1/(pi k_A)) (-ln alpha_A + 3/2 + alpha_A^2/36)      (K m/W),

accurate for alpha < 30 degrees; the pair adds a contact resistance R_c* (K m/W, the
``pipe_resistance``) and conducts H = w/(R_A + R_B + R_c*) through a length w
(``pipe_length``). The model is two-dimensional: it suits discs (quasi-2D runs, the
thesis's slab one diameter thick, w the slab thickness) rather than spheres. A wall has
no pipe resistance (R = 0 for an infinite radius): its conduction is the FE's.

A model is ``H(a2, ri, rj, tab, row) -> W/K`` with the radii of the two bodies (m; a wall
is ``inf``), reading row ``row`` of the flattened pair table. Keep heat terms additive:
another term (radiation) is a further sum in the engine.

Each model also has its lane loop (``<name>_lanes``, the heat sub-model of
:mod:`gsi.dem.contact.model`): Q = H (T_j - T_i) into i for the lanes of a batch
(:mod:`gsi.dem.contact.lanes`: reads ``A2``, ``RI``, ``RJ``, ``DTEMP``, writes ``Q``);
the conductance functions are plain compiled functions, which LLVM inlines (numba's
own IR inlining, ``inline="always"``, re-typed them in every caller: 7 s of compiling).
"""
import math


from gsi.jit import njit, sqrt, uint
from gsi.dem.contact.lanes import A2, RI, RJ, DTEMP, Q
from gsi.dem.materials import P_HC, P_K_I, P_K_J, P_KH, P_PIPE_R, P_PIPE_W


@njit(_nrt=False)
def area(a2, ri, rj, tab, row):
    """H = 4 k_i k_j/(k_i + k_j) sqrt(pi a^2) (W/K)."""
    return tab[row, P_KH] * sqrt(math.pi * a2) if a2 > 0.0 else 0.0


@njit(_nrt=False)
def radius(a2, ri, rj, tab, row):
    """H = 4 k_i k_j/(k_i + k_j) a (W/K)."""
    return tab[row, P_KH] * sqrt(a2) if a2 > 0.0 else 0.0


@njit(_nrt=False)
def constant(a2, ri, rj, tab, row):
    """H = h_c (W/K) for every touching pair."""
    return tab[row, P_HC]


@njit(_nrt=False)
def pipe_resistance(a, r, k):
    """Feng's pipe resistance per length (K m/W) of a cylinder of radius ``r`` (m) and
    conductivity ``k`` whose contact half-chord is ``a`` (m); 0 for r = inf (a wall)."""
    if math.isinf(r):
        return 0.0
    alpha = math.asin(min(a / r, 1.0))
    return (-math.log(alpha) + 1.5 + alpha * alpha / 36.0) / (math.pi * k)


@njit(_nrt=False)
def pipe(a2, ri, rj, tab, row):
    """H = w/(R_i + R_j + R_c*) (W/K), Feng's pipe network (module docstring)."""
    if a2 <= 0.0:
        return 0.0
    a = math.sqrt(a2)
    R = (pipe_resistance(a, ri, tab[row, P_K_I]) + pipe_resistance(a, rj, tab[row, P_K_J])
         + tab[row, P_PIPE_R])
    return tab[row, P_PIPE_W] / R


@njit(_nrt=False)
def none(a2, ri, rj, tab, row):
    """No conduction."""
    return 0.0


# ---- lane loops: one per model (the heat sub-models of gsi.dem.contact.model) ----------

@njit(_nrt=False)
def area_lanes(l0, l1, B, tab, row, dt):
    """Q = H (T_j - T_i) of lanes l0..l1-1, H of :func:`area` (the table value read once:
    read in the loop, LLVM cannot prove it apart from the buffer's stores)."""
    kh = tab[row, P_KH]
    for l in range(uint(l0), uint(l1)):
        a2 = B[A2 + l]
        B[Q + l] = (kh * sqrt(math.pi * a2) if a2 > 0.0 else 0.0) * B[DTEMP + l]


@njit(_nrt=False)
def radius_lanes(l0, l1, B, tab, row, dt):
    """Q = H (T_j - T_i) of lanes l0..l1-1, H of :func:`radius`."""
    kh = tab[row, P_KH]
    for l in range(uint(l0), uint(l1)):
        a2 = B[A2 + l]
        B[Q + l] = (kh * sqrt(a2) if a2 > 0.0 else 0.0) * B[DTEMP + l]


@njit(_nrt=False)
def constant_lanes(l0, l1, B, tab, row, dt):
    """Q = H (T_j - T_i) of lanes l0..l1-1, H of :func:`constant`."""
    for l in range(uint(l0), uint(l1)):
        B[Q + l] = constant(B[A2 + l], B[RI + l], B[RJ + l], tab, row) * B[DTEMP + l]


@njit(_nrt=False)
def pipe_lanes(l0, l1, B, tab, row, dt):
    """Q = H (T_j - T_i) of lanes l0..l1-1, H of :func:`pipe`."""
    for l in range(uint(l0), uint(l1)):
        B[Q + l] = pipe(B[A2 + l], B[RI + l], B[RJ + l], tab, row) * B[DTEMP + l]


@njit(_nrt=False)
def none_lanes(l0, l1, B, tab, row, dt):
    """No conduction: Q = 0."""
    for l in range(uint(l0), uint(l1)):
        B[Q + l] = 0.0
