"""Structural materials: isotropic linear elastic + thermal constants, and a small library.

Library values are typical room-temperature values, each with its source:

* ``steel``: structural carbon steel (S235-S355). E, nu, alpha from EN 1993-1-1 §3.2.6;
  rho = 7850 kg/m^3 (EN 1991-1-1 Table A.4); k = 53.3 W/(m K) and c = 440 J/(kg K) at 20 degC
  from the EN 1993-1-2 §3.4.1 formulas.
* ``aluminium``: 6061-T6 (ASM Aerospace Specification Metals data sheet / ASM Handbook
  Vol. 2): E = 68.9 GPa, nu = 0.33, rho = 2700, alpha = 23.6e-6, k = 167, c = 896.
* ``rubber``: soft natural-rubber membrane, small-strain values (Mark (ed.), *Physical
  Properties of Polymers Handbook*, 2nd ed., 2007, natural rubber; ranges E 1-5 MPa,
  k 0.13-0.16, c 1.8-2.0 kJ/(kg K)). nu = 0.45 rather than the measured ~0.499 because
  linear P1 tetrahedra lock when nearly incompressible; use P2 and set nu yourself for
  closer values.
* ``concrete``: normal-weight C30/37. E = 33 GPa (EN 1992-1-1 Table 3.1), nu = 0.2 and
  alpha = 10e-6 (EN 1992-1-1 §3.1.3), rho = 2400 (EN 1991-1-1 Table A.1, plain),
  c = 900 (EN 1992-1-2 §3.3.2, 20-100 degC), k = 1.6 (between the EN 1992-1-2 §3.3.3
  lower and upper limits at 20 degC, 1.33 and 1.95).
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from gsi.errors import GsiInputError


@dataclass(frozen=True)
class StructuralMaterial:
    """Isotropic linear-elastic, heat-conducting solid.

    Attributes
    ----------
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio (-), -1 < nu < 0.5.
    rho : float
        Density (kg/m^3).
    alpha : float
        Linear thermal expansion coefficient (1/K).
    k : float
        Thermal conductivity (W/(m K)).
    c : float
        Specific heat capacity (J/(kg K)).
    """

    E: float
    nu: float
    rho: float
    alpha: float = 0.0
    k: float = 1.0
    c: float = 1.0

    def __post_init__(self):
        for key in ("E", "rho", "k", "c"):
            v = getattr(self, key)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise GsiInputError(f"structure.material.{key} = {v!r}: must be a number > 0")
        if not (isinstance(self.nu, (int, float)) and -1.0 < self.nu < 0.5):
            raise GsiInputError(f"structure.material.nu = {self.nu!r}: must be in (-1, 0.5)")
        if not (isinstance(self.alpha, (int, float)) and math.isfinite(self.alpha) and self.alpha >= 0):
            raise GsiInputError(f"structure.material.alpha = {self.alpha!r}: must be >= 0 (1/K)")

    @property
    def mu(self) -> float:
        """Shear modulus (Lame's second parameter) mu = E / (2 (1 + nu)) (Pa)."""
        return self.E / (2.0 * (1.0 + self.nu))

    @property
    def lmbda(self) -> float:
        """Lame's first parameter lambda = E nu / ((1 + nu)(1 - 2 nu)) (Pa)."""
        return self.E * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu))

    @property
    def diffusivity(self) -> float:
        """Thermal diffusivity k / (rho c) (m^2/s)."""
        return self.k / (self.rho * self.c)

    def as_dict(self) -> dict:
        return asdict(self)


MATERIALS: dict[str, StructuralMaterial] = {
    "steel": StructuralMaterial(E=210e9, nu=0.3, rho=7850.0, alpha=12e-6, k=53.3, c=440.0),
    "aluminium": StructuralMaterial(E=68.9e9, nu=0.33, rho=2700.0, alpha=23.6e-6, k=167.0, c=896.0),
    "rubber": StructuralMaterial(E=2.0e6, nu=0.45, rho=930.0, alpha=2.2e-4, k=0.15, c=1900.0),
    "concrete": StructuralMaterial(E=33e9, nu=0.2, rho=2400.0, alpha=10e-6, k=1.6, c=900.0),
}


def get_material(spec) -> StructuralMaterial:
    """A material from a library name, a dict of fields, or a StructuralMaterial.

    A dict may name a library ``base`` and override fields:
    ``{"base": "steel", "E": 200e9}``.
    """
    if isinstance(spec, StructuralMaterial):
        return spec
    if isinstance(spec, str):
        if spec not in MATERIALS:
            raise GsiInputError(f"structure.material = {spec!r}: must be one of {sorted(MATERIALS)} "
                                "or a table of E, nu, rho, alpha, k, c")
        return MATERIALS[spec]
    if isinstance(spec, dict):
        spec = dict(spec)
        base = spec.pop("base", None)
        fields = get_material(base).as_dict() if base is not None else {}
        allowed = set(StructuralMaterial.__dataclass_fields__)
        for key in spec:
            if key not in allowed:
                raise GsiInputError(f"structure.material.{key} = {spec[key]!r}: unknown field; "
                                    f"allowed: base, {', '.join(sorted(allowed))}")
        fields.update(spec)
        for key in ("E", "nu", "rho"):
            if key not in fields:
                raise GsiInputError(f"structure.material.{key} = None: must be given (or a base)")
        return StructuralMaterial(**fields)
    raise GsiInputError(f"structure.material = {spec!r}: must be a name or a table")
