r"""Thermo-elasticity, one-way coupled: the heat solution loads the elasticity.

.. math::
    \sigma = C : (\varepsilon(u) - \alpha (T - T_{ref}) I)

Each :meth:`ThermoElastic.step` advances the heat problem by dt, interpolates the new
temperature into the elasticity's P1 temperature field, and then solves the elasticity
(static) or advances it by the same dt (dynamic). The thermal strain enters the
elasticity's right-hand side only, so both matrices are still factorized once.
"""
from __future__ import annotations

from .elasticity import Elasticity
from .heat import Heat
from .materials import get_material


class ThermoElastic:
    """A :class:`Heat` and an :class:`Elasticity` problem on one structure.

    Parameters
    ----------
    structure : gsi.meshes.StructureMesh
    material : StructuralMaterial or str or dict
    dt : float
        Time step of both problems (s).
    scheme : {"static", "newmark", "generalized_alpha"}
        Elasticity scheme (static: quasi-static thermal stress every step).
    T_ref : float
        Stress-free temperature; also the initial temperature unless ``T_initial`` given.
    heat_options, elasticity_options : dict
        Extra keyword options of :class:`Heat` (theta, degree, ...) and
        :class:`Elasticity` (degree, rayleigh, gravity, rho_inf, ...).
    """

    def __init__(self, structure, material, *, dt: float, scheme: str = "static",
                 T_ref: float = 0.0, T_initial: float | None = None,
                 heat_options: dict | None = None, elasticity_options: dict | None = None):
        material = get_material(material)
        self.heat = Heat(structure, material, dt=dt,
                         T_initial=T_ref if T_initial is None else T_initial,
                         **(heat_options or {}))
        self.elasticity = Elasticity(structure, material, scheme=scheme,
                                     dt=None if scheme == "static" else dt, T_ref=T_ref,
                                     **(elasticity_options or {}))
        self.elasticity.set_temperature(self.heat.T)

    @property
    def t(self) -> float:
        return self.heat.t

    @property
    def n_factorizations(self) -> int:
        """Factorizations of both problems together (2 after set-up)."""
        return self.heat.n_factorizations + self.elasticity.n_factorizations

    def step(self):
        """Heat step, then the elasticity under the new temperature. Returns (T, u)."""
        T = self.heat.step()
        self.elasticity.set_temperature(T)
        if self.elasticity.scheme == "static":
            u = self.elasticity.solve()
        else:
            u = self.elasticity.step()
        return T, u
