"""dolfinx structure solvers: elasticity (static, dynamic), heat, thermo-elasticity.

One problem per module; every dolfinx call whose spelling depends on the dolfinx version is
in :mod:`gsi.fem.compat`.

* :class:`~gsi.fem.elasticity.Elasticity` -- K u = f, or M a + C v + K u = f (Newmark /
  generalized-alpha, Rayleigh damping), supports and tractions by tag, gravity, thermal
  strain, nodal point loads at global vertex ids.
* :class:`~gsi.fem.heat.Heat` -- theta-scheme conduction with fixed temperature, flux,
  convection by tag and nodal heat loads.
* :class:`~gsi.fem.thermoelastic.ThermoElastic` -- heat then elasticity each step.
* What the problems share: :class:`~gsi.fem.problem.Problem` (solver, time, nodal loads,
  ``state()``/``set_state()``), :class:`~gsi.fem.dirichlet.Dirichlet` (prescribed values
  by tag), :mod:`~gsi.fem.solvers` (direct, out-of-core, iterative); the elasticity's time
  scheme :mod:`~gsi.fem.newmark`, the heat problem's surface conditions
  :class:`~gsi.fem.heat_boundary.HeatBoundary` and stability bounds :mod:`~gsi.fem.heat_bounds`.
* :class:`~gsi.fem.surface.ContactSurface` -- the tagged surface(s) as triangles, gathered
  on every rank; loads and heat scattered to the owning ranks (the coupling's
  :class:`gsi.coupling.interface.SurfaceInterface` builds the DEM wall on it).
* :class:`~gsi.fem.output.FemOutput` -- XDMF fields and a CSV of key numbers.
* :mod:`~gsi.fem.materials` -- ``StructuralMaterial`` and the ``MATERIALS`` library.

The matrices of every problem are factorized once per run (``problem.n_factorizations``).
Classes are imported lazily so that ``gsi.fem.materials`` works without loading dolfinx.
"""
from importlib import import_module

_EXPORTS = {
    "Elasticity": "elasticity",
    "Heat": "heat",
    "ThermoElastic": "thermoelastic",
    "ContactSurface": "surface",
    "FemOutput": "output",
    "StructuralMaterial": "materials",
    "MATERIALS": "materials",
    "get_material": "materials",
}

__all__ = list(_EXPORTS)


def __getattr__(name):
    if name in _EXPORTS:
        return getattr(import_module(f"{__name__}.{_EXPORTS[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
