"""Materials of particles and rigid walls, and the per-pair table of e, mu and mu_r.

``[materials.NAME]`` is one :class:`Material`; ``[[pairs]]`` is one :class:`Pair`, which
overrides the restitution, sliding and rolling friction of one material pair. Without a
``[[pairs]]`` entry, a pair of different materials takes the geometric mean of the two
materials' e, mu and mu_r (so a frictionless wall gives a frictionless contact); a
particle-particle pair and a particle-wall pair are different material pairs, so
e_pp = 0.8 with e_pw = 0.5 is::

    [materials.copper]   # ... e = 0.8
    [materials.floor]    # ...
    [[pairs]]
    materials = ["copper", "floor"]
    e = 0.5
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from gsi.config.schema import between, nonnegative, param, positive
from gsi.dem.materials import MATERIAL_DEFAULTS as D
from gsi.errors import GsiInputError

__all__ = ["Material", "Pair"]


@dataclass(kw_only=True)
class Material:
    """A DEM material (particles and rigid walls): elastic, contact and thermal properties
    (the defaults are :data:`gsi.dem.materials.MATERIAL_DEFAULTS`, those of
    :class:`gsi.dem.Material`)."""

    E: float = param(unit="Pa", check=positive(), doc="Young's modulus")
    nu: float = param(unit="-", check=between(-1.0, 0.5, open_lo=True, open_hi=True),
                      doc="Poisson's ratio")
    rho: float = param(unit="kg/m^3", check=positive(), doc="density")
    e: float = param(D["e"], unit="-", check=between(0.0, 1.0, open_lo=True), doc="restitution")
    mu: float = param(D["mu"], unit="-", check=nonnegative(), doc="sliding friction")
    mu_r: float = param(D["mu_r"], unit="-", check=nonnegative(), doc="rolling friction")
    k: float = param(D["k"], unit="W/(m K)", check=positive(), doc="thermal conductivity")
    cp: float = param(D["cp"], unit="J/(kg K)", check=positive(), doc="specific heat capacity")
    emissivity: Optional[float] = param(None, unit="-", check=between(0.0, 1.0),
                                        doc="emissivity for dem.radiation (none: does not "
                                            "radiate; every particle material needs one)")

    def to_dem(self, *, heat_scale: float = 1.0):
        """The :class:`gsi.dem.Material`; ``heat_scale`` s divides c_p (heat-capacity
        time scaling, see :mod:`gsi.case.case`)."""
        from gsi.dem.materials import Material as DemMaterial
        return DemMaterial(E=self.E, nu=self.nu, rho=self.rho, e=self.e, mu=self.mu,
                           mu_r=self.mu_r, k=self.k, cp=self.cp / heat_scale)


@dataclass(kw_only=True)
class Pair:
    """Contact properties of one material pair (``[[pairs]]``), overriding the mixing rule."""

    materials: tuple[str, ...] = param(doc="the two material names, e.g. [\"glass\", \"steel\"]")
    e: Optional[float] = param(None, unit="-", check=between(0.0, 1.0, open_lo=True),
                               doc="restitution of the pair")
    mu: Optional[float] = param(None, unit="-", check=nonnegative(), doc="sliding friction of the pair")
    mu_r: Optional[float] = param(None, unit="-", check=nonnegative(),
                                  doc="rolling friction of the pair")

    def validate(self, path: str) -> None:
        if len(self.materials) != 2:
            raise GsiInputError(f"{path}.materials = {list(self.materials)}: must name two "
                                f"materials, e.g. [\"glass\", \"steel\"]")
        if self.e is None and self.mu is None and self.mu_r is None:
            raise GsiInputError(f"{path}: give at least one of e, mu, mu_r")

    def overrides(self) -> dict:
        """``{"e": .., "mu": .., "mu_r": ..}`` of the values given."""
        return {k: getattr(self, k) for k in ("e", "mu", "mu_r") if getattr(self, k) is not None}
