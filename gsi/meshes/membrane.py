"""Thin clamped plate / membrane: a rectangular or circular slab of tetrahedra.

Choice: the slab is a 3D solid of thickness ``thickness`` whose in-plane mesh (size ``h``)
is extruded through the thickness in ``n_thickness`` layers (default 2; each prism layer is
split into tetrahedra by gmsh), so that bending is resolved through the thickness even
when ``h`` is much larger than the thickness. The slab occupies
``0 <= z <= thickness``; the rectangle is ``[0, length_x] x [0, length_y]``, the disc is
centred on the z axis. For bending, solve with degree = 2: linear tetrahedra lock in thin
plates (on the clamped-plate validation mesh P1 gives 8 % of the deflection, P2 98 %).

Tags: "contact" (top face z = thickness), "support" (the rim: side faces), "outer"
(bottom face z = 0), "volume".
"""
from __future__ import annotations

from mpi4py import MPI

from gsi.errors import GsiInputError

from ._common import GmshSession, StructureMesh, check_positive, finish, near, tag_and_mesh

NAMES = ["contact", "support", "outer"]


def build(*, shape: str = "rectangle", length_x: float = 1.0, length_y: float = 1.0,
          radius: float = 0.5, thickness: float = 0.01, h: float = 0.1,
          n_thickness: int = 2, comm: MPI.Comm = MPI.COMM_WORLD,
          root: int = 0) -> StructureMesh:
    """Build a thin slab (plate or membrane) clamped on its rim.

    Parameters
    ----------
    shape : {"rectangle", "circle"}
        Plan-form of the slab.
    length_x, length_y : float
        Side lengths of the rectangle (m); used when ``shape == "rectangle"``.
    radius : float
        Radius of the disc (m); used when ``shape == "circle"``.
    thickness : float
        Slab thickness (m).
    h : float
        In-plane element size (m).
    n_thickness : int
        Element layers through the thickness (>= 1, default 2).
    comm, root : MPI communicator and the rank that runs gmsh.

    Returns
    -------
    StructureMesh
    """
    if shape not in ("rectangle", "circle"):
        raise GsiInputError(f"structure.membrane.shape = {shape!r}: must be 'rectangle' or 'circle'")
    check_positive("membrane", thickness=thickness, h=h)
    if shape == "rectangle":
        check_positive("membrane", length_x=length_x, length_y=length_y)
    else:
        check_positive("membrane", radius=radius)
    if int(n_thickness) != n_thickness or n_thickness < 1:
        raise GsiInputError(f"structure.membrane.n_thickness = {n_thickness!r}: must be an integer >= 1")
    params = dict(shape=shape, length_x=length_x, length_y=length_y, radius=radius,
                  thickness=thickness, h=h, n_thickness=int(n_thickness))
    tags = None
    with GmshSession(comm, root, "membrane") as gmsh:
        if gmsh is not None:
            occ = gmsh.model.occ
            if shape == "rectangle":
                s = occ.addRectangle(0.0, 0.0, 0.0, length_x, length_y)
            else:
                s = occ.addDisk(0.0, 0.0, 0.0, radius, radius)
            occ.extrude([(2, s)], 0.0, 0.0, thickness, numElements=[int(n_thickness)])
            tol = 1e-3 * thickness  # OCC pads bounding boxes by ~1e-7 m

            def classify(tag, p, bbox):
                zmin, zmax = bbox[2], bbox[5]
                if near(zmin, thickness, tol) and near(zmax, thickness, tol):
                    return "contact"
                if near(zmin, 0.0, tol) and near(zmax, 0.0, tol):
                    return "outer"
                return "support"

            tags = tag_and_mesh(gmsh, classify=classify, names=NAMES, h=h,
                                builder="membrane")
        return finish(gmsh, comm, root, tags, params)
