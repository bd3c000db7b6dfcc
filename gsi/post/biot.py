r"""Biot number of the particle contacts (seed 001 (thesis), section II.4, eq. II.4).

The contact-conduction models (:mod:`gsi.dem.contact.conductance`) give each particle one temperature.
That holds when the resistance of the contact, 1/H, is much larger than the resistance
inside the particle, ~ 1/(k pi R); their ratio is the Biot number of the thesis

.. math::
    Bi = \frac{H}{k \pi R} \ll 1 .

For two equal spheres of one material with contact radius a (H = 2 k a, ``radius``; H =
2 k sqrt(pi) a, ``area``) it depends on the geometry alone: Bi = 2 a/(pi R) and
2 a/(sqrt(pi) R). The thesis's case 4 (R = 2 mm, overlap 0.2 mm, a = 0.6245 mm) gives
Bi = 0.199 with either copper or alumina: not << 1.

:func:`contact_biot` evaluates Bi at every particle-particle contact of a
:class:`gsi.dem.Simulation` with the conductance the engine uses (the same contact radius
:func:`gsi.dem.contact_geometry.pair_radius2` and the same model formula); each contact
counts with the larger of its two sides' Bi (the smaller particle, or the lower k).
Particle-wall contacts are not included (a wall is not lumped).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gsi.dem.materials import P_HC, P_KH

__all__ = ["BIOT_LIMIT", "BiotReport", "biot_number", "contact_biot", "conductance"]

#: Bi above this is "not << 1": the lumped particle temperature is questionable
BIOT_LIMIT = 0.1


def biot_number(H, k, R):
    """Bi = H/(k pi R) (-), thesis eq. II.4.

    Parameters
    ----------
    H : float or array
        Contact conductance (W/K).
    k : float or array
        Thermal conductivity of the particle (W/(m K)).
    R : float or array
        Particle radius (m).
    """
    return np.asarray(H, float) / (np.asarray(k, float) * math.pi * np.asarray(R, float))


def conductance(model, a2, kh, h_c=0.0):
    """Contact conductance H (W/K) of ``model`` at squared contact radius ``a2`` (m^2),
    as :mod:`gsi.dem.contact.conductance`: area kh sqrt(pi a^2), radius kh a, constant h_c;
    ``kh`` = 4 k_i k_j/(k_i + k_j) (W/(m K))."""
    a2 = np.maximum(np.asarray(a2, float), 0.0)
    if model == "area":
        return kh * np.sqrt(math.pi * a2)
    if model == "radius":
        return kh * np.sqrt(a2)
    if model == "constant":
        return np.where(a2 > 0.0, h_c, 0.0) * np.ones_like(a2)
    raise ValueError(f"heat model {model!r}: not one of area, radius, constant")


@dataclass
class BiotReport:
    """Biot numbers of the particle-particle contacts at one instant.

    Attributes
    ----------
    model : str
        Heat model of the simulation.
    n_contacts : int
        Touching particle pairs.
    max, mean : float
        Largest and mean Bi over the contacts (nan without contacts).
    ids : (int, int) or None
        Particle ids of the contact with the largest Bi.
    H, a, R, k : float
        That contact's conductance (W/K), contact radius (m), and the radius (m) and
        conductivity (W/(m K)) of the side that gives its Bi.
    material : str or None
        Material of that side.
    """

    model: str
    n_contacts: int
    max: float
    mean: float
    ids: tuple | None = None
    H: float = math.nan
    a: float = math.nan
    R: float = math.nan
    k: float = math.nan
    material: str | None = None

    def describe(self) -> str:
        """One line: the largest Bi and the contact that has it."""
        if not self.n_contacts:
            return f"no particle contacts ({self.model} model)"
        return (f"Bi = H/(k pi R) = {self.max:.3g} (mean {self.mean:.3g} over "
                f"{self.n_contacts} contacts; largest at particles {self.ids}: {self.material}, "
                f"R = {self.R:.4g} m, k = {self.k:.4g} W/(m K), contact radius "
                f"{self.a:.4g} m, H = {self.H:.4g} W/K)")


def contact_biot(sim) -> BiotReport:
    """Bi at every touching particle pair of ``sim`` now (see the module docstring).

    Parameters
    ----------
    sim : gsi.dem.Simulation
        With a heat model (``sim.heat`` not None).

    Returns
    -------
    BiotReport
    """
    from scipy.spatial import cKDTree

    model = sim.heat
    if model is None:
        raise ValueError("contact_biot: the simulation has no heat model")
    n = sim.n
    if n < 2:
        return BiotReport(model=model, n_contacts=0, max=math.nan, mean=math.nan)
    x, r, typ = sim.x, sim.radius, sim.type
    pairs = cKDTree(x).query_pairs(2.0 * float(r.max()), output_type="ndarray")
    if len(pairs):
        i, j = pairs[:, 0], pairs[:, 1]
        d = x[j] - x[i]
        L2 = (d * d).sum(1)
        touch = (L2 < (r[i] + r[j]) ** 2) & (L2 > 0.0)
        i, j, L2 = i[touch], j[touch], L2[touch]
    else:
        i = j = np.zeros(0, np.int64)
        L2 = np.zeros(0)
    if len(i) == 0:
        return BiotReport(model=model, n_contacts=0, max=math.nan, mean=math.nan)
    s = (r[i] ** 2 - r[j] ** 2 + L2) * 0.5 / np.sqrt(L2)      # as pair_radius2
    a2 = r[i] ** 2 - s * s
    tab = sim.table
    H = conductance(model, a2, tab[typ[i], typ[j], P_KH], tab[typ[i], typ[j], P_HC])
    names = sim.material_names
    k = np.array([sim.materials[m].k for m in names])
    bi_i = biot_number(H, k[typ[i]], r[i])
    bi_j = biot_number(H, k[typ[j]], r[j])
    bi = np.maximum(bi_i, bi_j)
    w = int(np.argmax(bi))
    side = i[w] if bi_i[w] >= bi_j[w] else j[w]
    return BiotReport(model=model, n_contacts=len(i), max=float(bi[w]), mean=float(bi.mean()),
                      ids=(int(sim.ids[i[w]]), int(sim.ids[j[w]])), H=float(H[w]),
                      a=float(math.sqrt(max(a2[w], 0.0))), R=float(r[side]),
                      k=float(k[typ[side]]), material=names[typ[side]])
