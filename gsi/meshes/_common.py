"""Shared pieces of the gmsh-API builders: the result type, the gmsh session, tagging.

Every builder makes its geometry with gmsh's OpenCASCADE kernel on MPI rank ``root`` only,
meshes it with tetrahedra, tags physical groups by name, and hands the model to
dolfinx (``gsi.fem.compat.model_to_mesh``), which distributes it over ``comm``.

Global vertex ids: the i-th gmsh node (tag i + 1) becomes global vertex id i
(``mesh.geometry.input_global_indices``); these ids do not depend on the number of ranks.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from mpi4py import MPI

from gsi.errors import GsiInputError

#: physical-group number of the volume; surface groups are numbered from 1 in the
#: order each builder lists them (the numbers are in ``StructureMesh.tags``)
VOLUME_TAG = 100


@dataclass
class StructureMesh:
    """A distributed dolfinx mesh with its gmsh physical groups.

    Attributes
    ----------
    mesh : dolfinx.mesh.Mesh
        Tetrahedral mesh (m), distributed over ``mesh.comm``.
    cell_tags, facet_tags : dolfinx.mesh.MeshTags
        Cell and boundary-facet markers (values are the physical-group numbers).
    tags : dict[str, int]
        Physical-group name -> number, e.g. ``{"contact": 1, "support": 2, "outer": 3,
        "volume": 100}``. Surface names are facet tags, "volume" is the cell tag.
    params : dict
        The parameters the mesh was built with (for output headers and restarts).
    volumes : dict[str, int]
        Volume (cell) group name -> number; builders have {"volume": 100}.
    """

    mesh: object
    cell_tags: object
    facet_tags: object
    tags: dict
    params: dict = field(default_factory=dict)
    volumes: dict = field(default_factory=dict)

    def facet_tag(self, name: str) -> int:
        """Number of the surface group ``name``; raises GsiInputError if absent."""
        if name not in self.tags or name == "volume":
            known = sorted(k for k in self.tags if k != "volume")
            raise GsiInputError(f"structure tag = {name!r}: must be one of {known}")
        return self.tags[name]


def check_positive(builder: str, **values) -> None:
    """Raise a one-line GsiInputError for any value that is not a finite number > 0."""
    for key, v in values.items():
        try:
            ok = math.isfinite(float(v)) and float(v) > 0.0
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise GsiInputError(f"structure.{builder}.{key} = {v!r}: must be a number > 0 (m)")


def check_less(builder: str, small: str, vs: float, large: str, vl: float) -> None:
    if not vs < vl:
        raise GsiInputError(
            f"structure.{builder}.{small} = {vs!r}: must be < {large} = {vl!r} (m)")


class GmshSession:
    """``with GmshSession(comm, root) as gmsh:`` -- gmsh alive on ``root`` only (else None).

    gmsh is initialised on entry and finalised on exit (gmsh 4.8 cannot tell whether a
    session is already open; do not call a builder inside your own gmsh session).
    """

    def __init__(self, comm: MPI.Comm, root: int, name: str):
        self.comm, self.root, self.name = comm, root, name
        self.gmsh = None

    def __enter__(self):
        if self.comm.rank == self.root:
            import gmsh
            gmsh.initialize()
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.model.add(self.name)
            self.gmsh = gmsh
        return self.gmsh

    def __exit__(self, *exc):
        if self.gmsh is not None:
            self.gmsh.finalize()
        return False


def surface_sample_point(gmsh, tag: int) -> np.ndarray:
    """A point on (the underlying geometry of) surface ``tag``: the parametric midpoint."""
    lo, hi = gmsh.model.getParametrizationBounds(2, tag)
    uv = 0.5 * (np.asarray(lo) + np.asarray(hi))
    return np.asarray(gmsh.model.getValue(2, tag, list(uv)), dtype=float)


def tag_and_mesh(gmsh, *, classify: Callable[[int, np.ndarray, tuple], str | None],
                 names: list[str], h: float,
                 builder: str) -> dict[str, int]:
    """Tag the single volume and its boundary surfaces, then mesh with tets of size ``h``.

    ``classify(surface_tag, sample_point, bounding_box)`` returns a name from ``names``
    (or None: untagged). Every name in ``names`` must receive at least one surface.
    Returns name -> physical-group number.
    """
    gmsh.model.occ.synchronize()
    vols = gmsh.model.getEntities(3)
    if len(vols) != 1:
        raise RuntimeError(f"{builder}: expected one volume, got {len(vols)}")
    groups: dict[str, list[int]] = {n: [] for n in names}
    for dim, tag in gmsh.model.getBoundary(vols, oriented=False, combined=True):
        p = surface_sample_point(gmsh, tag)
        bbox = gmsh.model.getBoundingBox(dim, tag)
        name = classify(tag, p, bbox)
        if name is not None:
            groups[name].append(tag)
    tags: dict[str, int] = {}
    for i, n in enumerate(names, start=1):
        if not groups[n]:
            raise RuntimeError(f"{builder}: no surface classified as {n!r}")
        gmsh.model.addPhysicalGroup(2, groups[n], i)
        gmsh.model.setPhysicalName(2, i, n)
        tags[n] = i
    gmsh.model.addPhysicalGroup(3, [vols[0][1]], VOLUME_TAG)
    gmsh.model.setPhysicalName(3, VOLUME_TAG, "volume")
    tags["volume"] = VOLUME_TAG
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.2 * h)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)  # Delaunay: robust on thin walls
    gmsh.model.mesh.generate(3)
    return tags


def finish(gmsh, comm: MPI.Comm, root: int, tags: dict | None, params: dict) -> StructureMesh:
    """Distribute the gmsh model of ``root`` with dolfinx; broadcast the tag dictionary."""
    from gsi.fem import compat
    tags = comm.bcast(tags, root=root)
    mesh, ct, ft = compat.model_to_mesh(gmsh.model if gmsh is not None else None, comm, root, gdim=3)
    return StructureMesh(mesh=mesh, cell_tags=ct, facet_tags=ft, tags=tags, params=dict(params))


def near(a: float, b: float, tol: float) -> bool:
    return abs(a - b) <= tol
