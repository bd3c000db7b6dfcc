"""gsi.dem — the numba DEM core (particles, contact laws, walls, heat, insertion, output).

Public API: :class:`Simulation`, :class:`Material`, :class:`PlaneWall`,
:class:`MeshWall`, size distributions :class:`Uniform`, :class:`Normal`,
:class:`Discrete`, insertion regions :class:`Box`, :class:`Cylinder` and fills
:func:`lattice_fill`, :func:`random_fill`, output :class:`ParticleWriter`,
:func:`write_wall_vtu`, the contact log :class:`ContactLog`.  See :mod:`gsi.dem.simulation` for the shape of a run.
"""
from gsi.dem.materials import Material
from gsi.dem.simulation import Simulation
from gsi.dem.walls import PlaneWall, MeshWall
from gsi.dem.distributions import Uniform, Normal, Discrete, Constant

__all__ = ["Simulation", "Material", "PlaneWall", "MeshWall", "Uniform", "Normal",
           "Discrete", "Constant"]
from gsi.dem.insertion import Box, Cylinder, lattice_fill, random_fill, Inserter
from gsi.dem.output import ParticleWriter, write_wall_vtu, write_particles_vtu
from gsi.dem.contact_log import ContactLog

__all__ += ["Box", "Cylinder", "lattice_fill", "random_fill", "Inserter", "ParticleWriter",
            "write_wall_vtu", "write_particles_vtu", "ContactLog"]
