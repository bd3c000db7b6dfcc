"""Materials and the per-type pair tables of the DEM (docs/design.md, "DEM physics").

A :class:`Material` holds the properties of one particle or wall type.  The
:func:`pair_table` precomputes, for every pair of types (i, j), the effective values
that the contact laws read (LIGGGHTS ``Yeff[itype][jtype]`` style), so no material
arithmetic happens in the inner loops.  Walls are types in the same table (their
R and m enter as infinity in the geometry code, not here).

Pair values (column constants ``P_*`` index the last axis of the table):

- ``P_E``    1/E* = (1-nu_i^2)/E_i + (1-nu_j^2)/E_j                       (Pa)
- ``P_G``    1/G* = 2(2-nu_i)(1+nu_i)/E_i + 2(2-nu_j)(1+nu_j)/E_j          (Pa)
- ``P_BETA`` beta = ln(e)/sqrt(ln(e)^2 + pi^2), e = sqrt(e_i e_j)         (-)
- ``P_MU``   mu = sqrt(mu_i mu_j)                                         (-)
- ``P_MUR``  mu_r = sqrt(mu_r,i mu_r,j)                                   (-)
- ``P_KH``   4 k_i k_j/(k_i + k_j), the conductivity factor of the heat models (W/(m K))
- ``P_KN``   linear-law normal stiffness k_n (the simulation's ``k_n``)      (N/m)
- ``P_HC``   constant conductance h_c of the ``constant`` heat model          (W/K)
- ``P_E_REST`` the pair restitution e                                       (-)
- ``P_ST_SN`` sqrt(S_t/S_n) = sqrt(4 G*/E*), saves a square root per contact (-)
- ``P_K_I``, ``P_K_J`` the conductivities k_i, k_j of the two types (W/(m K))
- ``P_PIPE_W`` length w of the pipes of the ``pipe`` heat model (m)
- ``P_PIPE_R`` contact resistance R_c* of the ``pipe`` heat model, per length (K m/W)

Mixing rule (chosen here, LIGGGHTS asks for a full matrix instead): a pair of
different materials takes the geometric mean of e, mu and mu_r, so a frictionless
wall (mu = 0) gives a frictionless contact.  ``pair_overrides`` replaces them.
"""
from dataclasses import dataclass
import math

import numpy as np

from gsi.errors import GsiInputError

(P_E, P_G, P_BETA, P_MU, P_MUR, P_KH, P_KN, P_HC, P_E_REST, P_ST_SN, P_K_I, P_K_J, P_PIPE_W,
 P_PIPE_R) = range(14)
N_PAIR = 14


#: the one set of material defaults (DEM and case layer): restitution, sliding and
#: rolling friction (-), conductivity (W/(m K)), specific heat capacity (J/(kg K))
MATERIAL_DEFAULTS = dict(e=0.5, mu=0.5, mu_r=0.0, k=1.0, cp=1000.0)


@dataclass(frozen=True)
class Material:
    """Properties of one particle or wall material.

    Parameters
    ----------
    E : float
        Young's modulus (Pa), > 0.
    nu : float
        Poisson's ratio (-), in (-1, 0.5).
    rho : float
        Density (kg/m^3), > 0 (unused for walls).
    e : float, default 0.5
        Coefficient of restitution (-), in [0, 1].
    mu : float, default 0.5
        Sliding friction coefficient (-), >= 0.
    mu_r : float, default 0.0
        Rolling friction coefficient (-), >= 0 (used when rolling resistance is on).
    k : float, default 1.0
        Thermal conductivity (W/(m K)), > 0.
    cp : float, default 1000.0
        Specific heat capacity (J/(kg K)), > 0.

    The defaults are :data:`MATERIAL_DEFAULTS`, the same as a case's ``[materials.NAME]``
    (:class:`gsi.case.materials.Material`).
    """

    E: float
    nu: float
    rho: float
    e: float = 0.5
    mu: float = 0.5
    mu_r: float = 0.0
    k: float = 1.0
    cp: float = 1000.0

    def validate(self, name):
        """Raise :class:`GsiInputError` naming ``materials.<name>.<key>`` if a value is bad."""
        checks = [
            ("E", self.E > 0, "must be > 0 (Pa)"),
            ("nu", -1.0 < self.nu < 0.5, "must be in (-1, 0.5) (-)"),
            ("rho", self.rho > 0, "must be > 0 (kg/m^3)"),
            ("e", 0.0 <= self.e <= 1.0, "must be in [0, 1] (-)"),
            ("mu", self.mu >= 0, "must be >= 0 (-)"),
            ("mu_r", self.mu_r >= 0, "must be >= 0 (-)"),
            ("k", self.k > 0, "must be > 0 (W/(m K))"),
            ("cp", self.cp > 0, "must be > 0 (J/(kg K))"),
        ]
        for key, ok, what in checks:
            value = getattr(self, key)
            if not (ok and math.isfinite(value)):
                raise GsiInputError(f"materials.{name}.{key} = {value}: {what}")

    @property
    def G(self):
        """Shear modulus G = E/(2(1+nu)) (Pa)."""
        return self.E / (2.0 * (1.0 + self.nu))


def beta_of_e(e):
    """Damping ratio beta = ln(e)/sqrt(ln(e)^2 + pi^2) (-); e = 0 gives -1, e = 1 gives 0."""
    if e <= 0.0:
        return -1.0
    le = math.log(e)
    return le / math.sqrt(le * le + math.pi ** 2)


#: the one time-step rule of gsi (used by gsi.case.Case.time_step and Simulation):
#: default DEM step, warning and refusal thresholds as fractions of the Rayleigh time t_R
DT_DEFAULT = 0.2
DT_WARN = 0.3
DT_REFUSE = 0.5
#: the same for the linear law, as fractions of its contact time t_c = pi sqrt(m*/k_n)
DT_LINEAR_DEFAULT = 1.0 / 50
DT_LINEAR_REFUSE = 1.0 / 10


def rayleigh_time(R, mat):
    """Rayleigh time t_R = pi R sqrt(rho/G)/(0.1631 nu + 0.8766) (s) of a sphere of radius R (m)."""
    return math.pi * R * math.sqrt(mat.rho / mat.G) / (0.1631 * mat.nu + 0.8766)


def pair_table(materials, *, k_n=0.0, h_c=0.0, pipe_length=0.0, pipe_resistance=0.0,
               pair_overrides=None):
    """Effective pair properties for every pair of material types.

    Parameters
    ----------
    materials : list of Material
        Materials in type order (type index = list index).
    k_n : float, default 0.0
        Normal stiffness of the linear law (N/m), the same for every pair.
    h_c : float, default 0.0
        Contact conductance of the ``constant`` heat model (W/K).
    pipe_length, pipe_resistance : float, default 0.0
        Pipe length w (m) and contact resistance per length R_c* (K m/W) of the ``pipe``
        heat model.
    pair_overrides : dict, optional
        ``{(i, j): {"e": .., "mu": .., "mu_r": ..}}`` by type index, symmetric.

    Returns
    -------
    numpy.ndarray
        Table of shape (ntypes, ntypes, N_PAIR), float64; columns ``P_*``.
    """
    nt = len(materials)
    tab = np.zeros((nt, nt, N_PAIR))
    over = {}
    for (a, b), d in (pair_overrides or {}).items():
        over[(a, b)] = d
        over[(b, a)] = d
    for i, mi in enumerate(materials):
        for j, mj in enumerate(materials):
            inv_E = (1 - mi.nu ** 2) / mi.E + (1 - mj.nu ** 2) / mj.E
            inv_G = (2 * (2 - mi.nu) * (1 + mi.nu) / mi.E
                     + 2 * (2 - mj.nu) * (1 + mj.nu) / mj.E)
            d = over.get((i, j), {})
            e = d.get("e", math.sqrt(mi.e * mj.e))
            mu = d.get("mu", math.sqrt(mi.mu * mj.mu))
            mu_r = d.get("mu_r", math.sqrt(mi.mu_r * mj.mu_r))
            tab[i, j, P_E] = 1.0 / inv_E
            tab[i, j, P_G] = 1.0 / inv_G
            tab[i, j, P_BETA] = beta_of_e(e)
            tab[i, j, P_MU] = mu
            tab[i, j, P_MUR] = mu_r
            tab[i, j, P_KH] = 4.0 * mi.k * mj.k / (mi.k + mj.k)
            tab[i, j, P_KN] = k_n
            tab[i, j, P_HC] = h_c
            tab[i, j, P_E_REST] = e
            tab[i, j, P_ST_SN] = math.sqrt(4.0 * inv_E / inv_G)
            tab[i, j, P_K_I] = mi.k
            tab[i, j, P_K_J] = mj.k
            tab[i, j, P_PIPE_W] = pipe_length
            tab[i, j, P_PIPE_R] = pipe_resistance
    return tab
