"""gsi — granular–structure interaction: a numba DEM core coupled to dolfinx solvers."""

__version__ = "0.1.0"
