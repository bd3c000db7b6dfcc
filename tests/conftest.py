"""Test-session set-up: load VTK (pyvista) before dolfinx.

Test modules import dolfinx at collection; VTK's scalar bars abort a process in which
dolfinx was loaded first (see gsi.viz._preload_vtk). Importing gsi.viz here, before any
test module, lets the demo tests render their pictures in-process.
"""
import gsi.viz  # noqa: F401
