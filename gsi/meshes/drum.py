"""Rotating-drum shell: a cylindrical tube with open ends, axis along x (horizontal).

The inner surface has radius ``radius``; the wall has thickness ``thickness``; the tube
spans 0 <= x <= ``length``. Gravity in gsi points along -z, so the drum rolls about x.

Tags: "contact" (inner cylindrical surface), "support" (the two end annuli, x = 0 and
x = length: the drum is held at its end rings), "outer" (outer cylindrical surface),
"volume".
"""
from __future__ import annotations

import numpy as np
from mpi4py import MPI

from ._common import GmshSession, StructureMesh, check_positive, finish, near, tag_and_mesh

NAMES = ["contact", "support", "outer"]


def build(*, radius: float = 0.25, length: float = 0.3, thickness: float = 0.005,
          h: float = 0.03, comm: MPI.Comm = MPI.COMM_WORLD,
          root: int = 0) -> StructureMesh:
    """Build a drum shell.

    Parameters
    ----------
    radius : float
        Inner radius (m).
    length : float
        Axial length along x (m).
    thickness : float
        Wall thickness (m).
    h : float
        Element size (m).
    comm, root : MPI communicator and the rank that runs gmsh.
    """
    check_positive("drum", radius=radius, length=length, thickness=thickness, h=h)
    params = dict(radius=radius, length=length, thickness=thickness, h=h)
    tags = None
    with GmshSession(comm, root, "drum") as gmsh:
        if gmsh is not None:
            occ = gmsh.model.occ
            outer = occ.addCylinder(0, 0, 0, length, 0, 0, radius + thickness)
            inner = occ.addCylinder(-thickness, 0, 0, length + 2 * thickness, 0, 0, radius)
            occ.cut([(3, outer)], [(3, inner)])
            tol = max(1e-3 * thickness, 1e-7)

            def classify(tag, p, bbox):
                if near(bbox[0], bbox[3], tol):
                    return "support"
                r = float(np.hypot(p[1], p[2]))
                return "contact" if abs(r - radius) < 0.5 * thickness else "outer"

            tags = tag_and_mesh(gmsh, classify=classify, names=NAMES, h=h,
                                builder="drum")
        return finish(gmsh, comm, root, tags, params)
