"""Structured tetrahedral box (bar, beam or block) -- the validation tests' geometry.

Built with dolfinx's structured box generator (no gmsh), so it is cheap and its
element edges align with the axes. Occupies [0, length_x] x [0, length_y] x [0, length_z].

Tags: the six faces "x0", "x1", "y0", "y1", "z0", "z1" (at the min / max coordinate) and
"volume". Global vertex ids are the structured-grid vertex numbers in dolfinx's input
order (``mesh.geometry.input_global_indices``), independent of the number of ranks.
"""
from __future__ import annotations

import numpy as np
from mpi4py import MPI

from gsi.errors import GsiInputError

from ._common import VOLUME_TAG, StructureMesh, check_positive

FACES = ["x0", "x1", "y0", "y1", "z0", "z1"]


def build(*, length_x: float = 1.0, length_y: float = 0.1, length_z: float = 0.1,
          n: tuple = (10, 1, 1), h: float | None = None,
          comm: MPI.Comm = MPI.COMM_WORLD) -> StructureMesh:
    """Build a box of tetrahedra (6 per hexahedral grid cell).

    Parameters
    ----------
    length_x, length_y, length_z : float
        Box edge lengths (m).
    n : tuple of 3 int
        Grid cells along x, y, z. Ignored when ``h`` is given.
    h : float, optional
        Target element size (m): n = ceil(length / h) per direction.
    comm : MPI communicator.
    """
    from gsi.fem import compat
    check_positive("box", length_x=length_x, length_y=length_y, length_z=length_z)
    L = np.array([length_x, length_y, length_z], dtype=float)
    if h is not None:
        check_positive("box", h=h)
        n = tuple(int(max(1, np.ceil(Li / h - 1e-9))) for Li in L)
    if len(n) != 3 or any(int(k) != k or k < 1 for k in n):
        raise GsiInputError(f"structure.box.n = {n!r}: must be three integers >= 1")
    mesh = compat.create_box_mesh(comm, np.zeros(3), L, n)
    tol = 1e-9 * L.max()
    entities, values = [], []
    tags = {}
    for i, name in enumerate(FACES):
        axis, side = divmod(i, 2)
        target = L[axis] * side
        facets = compat.locate_boundary_facets(
            mesh, lambda x, a=axis, c=target: np.abs(x[a] - c) < tol)
        entities.append(facets)
        values.append(np.full(facets.size, i + 1, dtype=np.int32))
        tags[name] = i + 1
    # an edge facet cannot lie on two faces of a box: faces are disjoint sets of facets
    ft = compat.make_meshtags(mesh, 2, np.concatenate(entities), np.concatenate(values))
    ncell = mesh.topology.index_map(3).size_local + mesh.topology.index_map(3).num_ghosts
    ct = compat.make_meshtags(mesh, 3, np.arange(ncell, dtype=np.int32),
                              np.full(ncell, VOLUME_TAG, dtype=np.int32))
    tags["volume"] = VOLUME_TAG
    return StructureMesh(mesh=mesh, cell_tags=ct, facet_tags=ft, tags=tags,
                         params=dict(length_x=length_x, length_y=length_y,
                                     length_z=length_z, n=tuple(int(k) for k in n)))
