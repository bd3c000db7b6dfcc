"""The structure's contact surface as a triangle set, for the coupling with the DEM.

The triangles are the boundary facets with the given tag; their vertices are FE mesh
vertices. The surface is gathered over the MPI ranks onto **every** rank, in an order that
does not depend on the number of ranks:

* vertices sorted by global vertex id (gmsh node tag - 1),
* triangles sorted by their (sorted) vertex-id triple, each oriented so that its
  right-hand normal (x_b - x_a) x (x_c - x_a) points out of the structure.

Field values at the vertices (displacement, velocity, temperature) are gathered the same
way. Loads go the other way: :meth:`ContactSurface.add_nodal_loads` takes an array in the
surface's vertex order on rank ``root`` (default 0), broadcasts it, and every rank adds
the rows of the vertices it owns through the problem's nodal-load entry point, so that each
load is applied exactly once.

With P1 elements, splitting a point force F at p over a triangle's vertices with the
barycentric weights of p is the consistent nodal load. With P2 the loads still act on the
vertex dofs only: statically equivalent to F at p (same resultant and moment, since the
weights reproduce p), but not the P2-consistent load (which would evaluate the quadratic
basis functions at p).
"""
from __future__ import annotations

import numpy as np
from mpi4py import MPI

from gsi.errors import GsiInputError

from . import compat


class ContactSurface:
    """Triangle set of surface ``tag`` of an elasticity and/or heat problem.

    Parameters
    ----------
    elasticity : gsi.fem.elasticity.Elasticity, optional
    heat : gsi.fem.heat.Heat, optional
        At least one; both must live on the same structure (a heat problem can also be
        added later with :meth:`attach`).
    tag : str or sequence of str
        Surface name(s) (default "contact"); several tags make one surface of all their
        facets (a facet in two of them counts once).

    Attributes
    ----------
    x0 : ndarray (nv, 3)
        Reference (undeformed) vertex coordinates (m).
    triangles : ndarray (nt, 3) int64
        Vertex indices into ``x0`` (outward oriented).
    global_ids : ndarray (nv,) int64
        Global vertex ids of the surface vertices (sorted).
    """

    def __init__(self, *, elasticity=None, heat=None, tag: str = "contact"):
        prob = elasticity if elasticity is not None else heat
        if prob is None:
            raise GsiInputError("coupling.surface: needs an elasticity or a heat problem")
        self.elasticity, self.heat = elasticity, heat
        self.tags = (tag,) if isinstance(tag, str) else tuple(tag)
        if not self.tags:
            raise GsiInputError("coupling.surface: give at least one surface tag")
        self.tag = self.tags[0] if len(self.tags) == 1 else self.tags
        self.structure = structure = prob.structure
        mesh = structure.mesh
        self.comm = comm = mesh.comm
        facets = np.unique(np.concatenate(
            [compat.meshtag_find(structure.facet_tags, structure.facet_tag(t))
             for t in self.tags]).astype(np.int32))
        nodes = compat.entities_to_geometry(mesh, mesh.topology.dim - 1, facets, orient=True)
        gids = compat.input_global_indices(mesh)
        x = compat.geometry_x(mesh)
        tri_g = gids[nodes] if nodes.size else np.zeros((0, 3), dtype=np.int64)
        tri_g = tri_g.reshape(-1, 3)
        # gather triangles (as global-id triples) and vertex coordinates
        all_tri = np.concatenate(comm.allgather(tri_g)) if comm.size > 1 else tri_g
        node_ids = np.unique(nodes.ravel())
        vid_local = gids[node_ids]
        vx_local = x[node_ids]
        all_vid = np.concatenate(comm.allgather(vid_local)) if comm.size > 1 else vid_local
        all_vx = np.concatenate(comm.allgather(vx_local)) if comm.size > 1 else vx_local
        # unique triangles (a facet may be present on several ranks), canonical order
        key = np.sort(all_tri, axis=1)
        _, first = np.unique(key, axis=0, return_index=True)
        tri = all_tri[first]
        key = key[first]
        order = np.lexsort((key[:, 2], key[:, 1], key[:, 0]))
        tri = tri[order]
        # unique vertices sorted by global id
        self.global_ids, vfirst = np.unique(all_vid, return_index=True)
        self.x0 = np.ascontiguousarray(all_vx[vfirst][:, :3])
        self.triangles = np.searchsorted(self.global_ids, tri).astype(np.int64)
        # owned rows and their dofs, per problem
        self._own = {}
        self.attach(elasticity=elasticity, heat=heat)

    def attach(self, *, elasticity=None, heat=None) -> None:
        """Gather from / scatter to ``elasticity`` and/or ``heat`` too (same structure).
        Collective."""
        for name, p in (("elasticity", elasticity), ("heat", heat)):
            if p is None:
                continue
            if p.structure is not self.structure:
                raise GsiInputError("coupling.surface: elasticity and heat must share one structure")
            rows, dofs = p.vmap.lookup_owned(self.global_ids)
            n_owned = self.comm.allreduce(int(rows.size), op=MPI.SUM)
            if n_owned != self.global_ids.size:
                raise RuntimeError(f"ContactSurface: {n_owned} owned vertices for "
                                   f"{self.global_ids.size} surface vertices")
            self._own[name] = (rows, dofs, p.vmap.bs)
            setattr(self, name, p)

    @property
    def n_vertices(self) -> int:
        return int(self.global_ids.size)

    @property
    def n_triangles(self) -> int:
        return int(self.triangles.shape[0])

    # ------------------------------------------------------------------ gather
    def gather(self, name: str, f) -> np.ndarray:
        """The values of ``f`` (a Function of the ``name`` problem, "elasticity" or
        "heat") at the surface vertices, (nv, bs) or (nv,), on every rank (collective)."""
        rows, dofs, bs = self._own[name]
        out = np.zeros((self.n_vertices, bs))
        vals = f.x.array
        for c in range(bs):
            out[rows, c] = vals[dofs * bs + c]
        self.comm.Allreduce(MPI.IN_PLACE, out, op=MPI.SUM)  # each vertex owned once: exact
        return out if bs > 1 else out[:, 0]

    def n_owned(self, name: str) -> int:
        """Surface vertices whose ``name`` dofs this rank owns."""
        return int(self._own[name][0].size)

    def displacement(self) -> np.ndarray:
        """Current displacement at the surface vertices (nv, 3) (m), on every rank."""
        return self.gather("elasticity", self.elasticity.u)

    def velocity(self) -> np.ndarray:
        """Current velocity at the surface vertices (nv, 3) (m/s), on every rank."""
        return self.gather("elasticity", self.elasticity.v)

    def temperature(self) -> np.ndarray:
        """Current temperature at the surface vertices (nv,) (K or degC), on every rank."""
        return self.gather("heat", self.heat.T)

    def positions(self) -> np.ndarray:
        """Deformed vertex coordinates x0 + u (nv, 3) (m)."""
        return self.x0 + self.displacement()

    # ------------------------------------------------------------------ scatter
    def _scatter(self, name: str, values: np.ndarray, root: int | None, width: int):
        if name not in self._own:
            raise GsiInputError(f"coupling.surface: no {name} problem attached")
        vals = None
        if root is None or self.comm.rank == root:
            vals = np.asarray(values, dtype=float).reshape(self.n_vertices, width)
        if root is not None and self.comm.size > 1:
            vals = self.comm.bcast(vals, root=root)
        rows, _, _ = self._own[name]
        return self.global_ids[rows], vals[rows]

    def add_nodal_loads(self, forces, *, root: int | None = 0) -> None:
        """Add forces (nv, 3) (N) in the surface's vertex order to the elasticity problem.

        ``forces`` is read on rank ``root`` (broadcast to the others); with ``root=None``
        every rank must pass the same array.
        """
        ids, F = self._scatter("elasticity", forces, root, 3)
        self.elasticity.add_nodal_loads(ids, F)

    def add_nodal_heat(self, q, *, root: int | None = 0) -> None:
        """Add heat loads (nv,) (W, into the structure) in vertex order to the heat problem."""
        ids, Q = self._scatter("heat", q, root, 1)
        self.heat.add_nodal_heat(ids, Q[:, 0])

    def normals(self, x=None) -> np.ndarray:
        """Unit outward normals of the triangles (nt, 3) at coordinates ``x`` (default x0)."""
        x = self.x0 if x is None else x
        a, b, c = (x[self.triangles[:, k]] for k in range(3))
        n = np.cross(b - a, c - a)
        return n / np.linalg.norm(n, axis=1)[:, None]

    def area(self, x=None) -> float:
        """Total area of the triangles (m^2)."""
        x = self.x0 if x is None else x
        a, b, c = (x[self.triangles[:, k]] for k in range(3))
        return float(0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum())
