"""DEM <-> FE coupling: the contact surface as a DEM wall, load and heat transfer, staggering.

* :class:`~gsi.coupling.interface.SurfaceInterface` -- the one interface of a structure:
  the tagged FE surface as DEM wall triangles (P1, or P2 split at its edge midpoints,
  loads by the P2 basis of the parent face), gathered positions, velocities and
  temperatures, scattered nodal loads and heat.
* :class:`~gsi.coupling.staggered.StaggeredCoupling` -- forces and motion, one FE step per
  n_sub DEM steps, with the per-step load balance and work record;
  :func:`~gsi.coupling.staggered.lowest_period`, :func:`~gsi.coupling.staggered.choose_n_sub`.
* :class:`~gsi.coupling.thermal.ThermalCoupling` -- heat (and thermo-elastic) coupling;
  :func:`~gsi.coupling.thermal.scale_heat_capacity` (the heat-capacity time scaling).
* :class:`~gsi.coupling.coupled_structure.CoupledStructure` -- a built structure with its wall and
  couplings, driven by a runner (``attach``, ``begin``, DEM steps, ``finish``); made by
  :meth:`gsi.case.structure.Structure.build`.

Names are imported lazily so that importing the package does not load dolfinx.
"""
from importlib import import_module

_EXPORTS = {
    "SurfaceInterface": "interface",
    "StaggeredCoupling": "staggered",
    "MechanicalRecord": "records",
    "lowest_period": "staggered",
    "choose_n_sub": "staggered",
    "ThermalCoupling": "thermal",
    "ThermalRecord": "records",
    "scale_heat_capacity": "thermal",
    "CoupledStructure": "coupled_structure",
    "IntervalRecord": "records",
}

__all__ = list(_EXPORTS)


def __getattr__(name):
    if name in _EXPORTS:
        return getattr(import_module(f"{__name__}.{_EXPORTS[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
