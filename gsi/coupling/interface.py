r"""The FE contact surface as a DEM mesh wall: forces and heat to the FE, motion and
temperature to the DEM. One interface serves the mechanical and the thermal coupling.

docs/design.md, "Coupling". The tagged contact surface of the structure
(:class:`gsi.fem.surface.ContactSurface`: boundary triangles whose vertices are FE mesh
vertices, gathered on every rank in a rank-independent order) becomes one
:class:`gsi.dem.MeshWall`. Contact is two-sided closest-point, so the triangles'
orientation (outward, as ContactSurface gives them) only documents which side is which.

Interface nodes and load transfer
---------------------------------
A particle-triangle contact at point p with barycentric weights (w_a, w_b, w_c) puts
-F w_k dt on wall vertex k (the DEM accumulates this in ``vertex_impulse``). Held over the
FE step dt_FE, the nodal force is P_k = vertex_impulse_k / dt_FE (N).

* **P1** (``degree = 1``): the wall is the surface triangles themselves; w_k are the P1
  basis functions at p, so P_k is exactly the consistent nodal load of the point force.
* **P2** (``degree = 2``): the wall is each surface triangle split into four at its edge
  midpoints -- the P2 nodes of the face -- so every P2 surface node is a wall vertex, and
  the deformed surface the DEM sees is the piecewise-linear interpolant through all P2
  nodes. Each sub-triangle carries its six-node parent face (``parent_nodes``: a, b, c,
  ab, bc, ca) and its vertices' barycentric coordinates in the parent
  (``parent_coords``); the DEM maps a contact's weights to parent coordinates l and puts
  the impulse on the six parent nodes with the P2 basis values l_a(2 l_a - 1), ...,
  4 l_a l_b, ... (:func:`gsi.dem.wall_kernels.mesh_scatter`). So P_k is exactly the
  consistent P2 nodal load of the point force: sum_k P_k . u_k = F . u(p) for every
  P2 field u. (The vertex weights are negative for l < 1/2, as P2's are.) The mid-edge
  nodes are found by coordinates: this needs straight-sided (geometry order 1) meshes.

Node order (the wall's vertex order): the ContactSurface vertices (sorted global vertex
id), then the edge midpoints sorted by their (sorted) pair of global vertex ids; it does
not depend on the number of MPI ranks.

Heat (the thermal coupling, :mod:`gsi.coupling.thermal`): the structure's temperature is
gathered at the surface vertices; on a P2 wall an edge midpoint takes the mean of its two
ends (:meth:`SurfaceInterface.wall_temperature`), so the barycentric interpolation on a
sub-triangle is the P1 field of the FE face. Heat the DEM puts on a midpoint goes half to
each end (:meth:`SurfaceInterface.vertex_heat`, the transpose), so the nodal heat load is
P1-consistent: l_a(2 l_a - 1) + (4 l_a l_b + 4 l_c l_a)/2 = l_a, and the total is kept
exactly.

MPI: positions and velocities are gathered onto every rank (each node is owned by one
rank: an exact sum); loads given on rank ``root`` are broadcast, and each rank adds the
rows of the nodes it owns, so each load is applied once.
"""
from __future__ import annotations

import numpy as np
from mpi4py import MPI

from gsi.errors import GsiInputError

__all__ = ["SurfaceInterface"]


class SurfaceInterface:
    """Interface nodes and wall triangles of the contact surface of a structure.

    Parameters
    ----------
    elasticity : gsi.fem.elasticity.Elasticity, optional
        The structure's elasticity (P1 or P2 vector Lagrange on a straight-sided
        tetrahedral mesh); its degree sets the wall (P2: split at the edge midpoints).
    heat : gsi.fem.heat.Heat, optional
        The structure's heat problem (or :meth:`add_heat` later). At least one of the two.
    tag : str or sequence of str
        Contact surface tag(s) (default "contact"); several tags make one surface.

    Attributes
    ----------
    x0 : ndarray (n_nodes, 3)
        Reference coordinates of the interface nodes (m).
    triangles : ndarray (n_tri, 3) int64
        Wall triangles as node indices (outward oriented).
    surface : gsi.fem.surface.ContactSurface
        The gathered surface (vertices are the first ``surface.n_vertices`` nodes).
    n_vertices, n_midpoints : int
        Surface vertices and P2 edge-midpoint nodes (0 for P1).
    midpoint_edges : ndarray (n_midpoints, 2) int64
        The two surface vertices of each midpoint node's edge.
    tags : tuple of str
        The contact surface tags.
    """

    def __init__(self, elasticity=None, *, heat=None, tag="contact"):
        from gsi.fem.surface import ContactSurface
        if elasticity is None and heat is None:
            raise GsiInputError("coupling.interface: needs an elasticity or a heat problem")
        if elasticity is not None and elasticity.degree not in (1, 2):
            raise GsiInputError(f"structure.degree = {elasticity.degree!r}: the coupling "
                                "supports 1 or 2")
        self.elasticity = elasticity
        self.heat = heat
        self.comm = (elasticity if elasticity is not None else heat).comm
        self.surface = s = ContactSurface(elasticity=elasticity, heat=heat, tag=tag)
        self.tags = s.tags
        self.n_vertices = s.n_vertices
        if elasticity is None or elasticity.degree == 1:
            self.x0 = s.x0.copy()
            self.triangles = s.triangles.copy()
            self.n_midpoints = 0
            self.midpoint_edges = np.zeros((0, 2), np.int64)
            self._mid = None
        else:
            self._setup_midpoints()

    def add_heat(self, heat) -> None:
        """Also transfer temperatures and heat to ``heat`` (same structure). Collective."""
        if self.heat is heat:
            return
        if self.heat is not None:
            raise GsiInputError("coupling.interface: already has a heat problem")
        self.surface.attach(heat=heat)
        self.heat = heat

    # ------------------------------------------------------------------ P2 nodes
    def _setup_midpoints(self) -> None:
        from scipy.spatial import cKDTree
        from gsi.fem import compat
        s, el = self.surface, self.elasticity
        tri = s.triangles
        e = np.stack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]], axis=1).reshape(-1, 2)
        e_sorted = np.sort(e, axis=1)
        # vertices are numbered in global-id order, so this sorts edges by global-id pairs
        edges, inverse = np.unique(e_sorted, axis=0, return_inverse=True)
        nv, ne = s.n_vertices, len(edges)
        mid_of = (nv + inverse).reshape(-1, 3)          # node of edges ab, bc, ca per triangle
        a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
        ab, bc, ca = mid_of[:, 0], mid_of[:, 1], mid_of[:, 2]
        self.triangles = np.concatenate([
            np.c_[a, ab, ca], np.c_[ab, b, bc], np.c_[ca, bc, c], np.c_[ab, bc, ca]]
        ).astype(np.int64)
        # each sub-triangle's six-node parent face and its vertices' parent coordinates
        nt = len(tri)
        self.parent_nodes = np.tile(np.c_[a, b, c, ab, bc, ca], (4, 1)).astype(np.int64)
        A, B, C = np.eye(3)
        AB, BC, CA = 0.5 * (A + B), 0.5 * (B + C), 0.5 * (C + A)
        sub = np.array([[A, AB, CA], [AB, B, BC], [CA, BC, C], [AB, BC, CA]])
        self.parent_coords = np.repeat(sub, nt, axis=0)
        x_mid = 0.5 * (s.x0[edges[:, 0]] + s.x0[edges[:, 1]])
        self.x0 = np.vstack([s.x0, x_mid])
        self.n_midpoints = ne
        #: (ne, 2) surface-vertex pairs of the edges, in the order of the midpoint nodes
        self.midpoint_edges = edges
        # owned P2 dofs at the midpoints (by coordinates)
        imap, bs = compat.dof_index_map(el.V)
        X = el.V.tabulate_dof_coordinates()[: imap.size_local]
        size = float(np.ptp(self.x0, axis=0).max()) or 1.0
        tol = 1e-9 * size
        rows = np.zeros(0, np.int64)
        dofs = np.zeros(0, np.int64)
        if len(X):
            d, k = cKDTree(X).query(x_mid, distance_upper_bound=tol)
            hit = np.isfinite(d)
            rows, dofs = np.flatnonzero(hit), k[hit].astype(np.int64)
        found = self.comm.allreduce(int(rows.size), op=MPI.SUM)
        if found != ne:
            raise GsiInputError(
                f"structure.degree = 2: found {found} of {ne} P2 edge-midpoint dofs of the "
                "contact surface; the coupling needs a straight-sided mesh (structure mesh "
                "order = 1)")
        self._mid = (rows, dofs, bs)

    @property
    def n_nodes(self) -> int:
        return int(self.x0.shape[0])

    # ------------------------------------------------------------------ gather
    def _gather_mid(self, f) -> np.ndarray:
        rows, dofs, bs = self._mid
        out = np.zeros((self.n_midpoints, 3))
        vals = f.x.array
        for c in range(3):
            out[rows, c] = vals[dofs * bs + c]
        self.comm.Allreduce(MPI.IN_PLACE, out, op=MPI.SUM)
        return out

    def _gather(self, f, vertex_values) -> np.ndarray:
        if self._mid is None:
            return vertex_values
        return np.vstack([vertex_values, self._gather_mid(f)])

    def displacement(self) -> np.ndarray:
        """Displacement at the interface nodes (n_nodes, 3) (m), on every rank (collective)."""
        return self._gather(self.elasticity.u, self.surface.displacement())

    def velocity(self) -> np.ndarray:
        """Velocity at the interface nodes (n_nodes, 3) (m/s), on every rank (collective)."""
        return self._gather(self.elasticity.v, self.surface.velocity())

    def positions(self) -> np.ndarray:
        """Deformed node coordinates x0 + u (n_nodes, 3) (m) (collective)."""
        return self.x0 + self.displacement()

    # ------------------------------------------------------------------ loads
    def add_nodal_loads(self, forces, *, root: int | None = 0) -> np.ndarray:
        """Add forces (n_nodes, 3) (N) at the interface nodes to the elasticity problem.

        ``forces`` is read on rank ``root`` and broadcast (``root=None``: every rank passes
        the same array). Returns the broadcast array (on every rank). Collective.
        """
        F = None
        if root is None or self.comm.rank == root:
            F = np.asarray(forces, dtype=float)
            if F.shape != (self.n_nodes, 3) or not np.all(np.isfinite(F)):
                raise GsiInputError(f"coupling loads shape {F.shape}: must be "
                                    f"({self.n_nodes}, 3) finite (N)")
        if root is not None and self.comm.size > 1:
            F = self.comm.bcast(F, root=root)
        self.surface.add_nodal_loads(F[: self.n_vertices], root=None)
        if self._mid is not None:
            rows, dofs, bs = self._mid
            values = self.elasticity.nodal.values   # owned unrolled dofs (NodalLoads)
            for c in range(3):
                np.add.at(values, dofs * bs + c, F[self.n_vertices + rows, c])
        return F

    # ------------------------------------------------------------------ heat
    def surface_temperature(self) -> np.ndarray:
        """Temperature at the surface vertices (n_vertices,), on every rank (collective)."""
        if self.heat is None:
            raise GsiInputError("coupling.interface: no heat problem (structure.thermal)")
        return self.surface.temperature()

    def wall_temperature(self, T_surface=None) -> np.ndarray:
        """Temperature of the wall nodes (n_nodes,): the surface vertices' values, then (P2
        walls) each edge midpoint's as the mean of its two ends, the P1 field of the FE
        face on the refined wall. ``T_surface`` (n_vertices,) defaults to
        :meth:`surface_temperature` (then collective)."""
        T = self.surface_temperature() if T_surface is None else np.asarray(T_surface, float)
        if self.n_midpoints == 0:
            return T
        return np.concatenate([T, 0.5 * T[self.midpoint_edges].sum(axis=1)])

    def vertex_heat(self, node_heat) -> np.ndarray:
        """Heat on the wall nodes (n_nodes,) -> on the surface vertices (n_vertices,): a
        midpoint's share goes half to each end (the transpose of :meth:`wall_temperature`;
        the total is kept exactly). Local."""
        node_heat = np.asarray(node_heat, float)
        if self.n_midpoints == 0:
            return node_heat
        out = node_heat[: self.n_vertices].copy()
        half = 0.5 * node_heat[self.n_vertices:]
        np.add.at(out, self.midpoint_edges[:, 0], half)
        np.add.at(out, self.midpoint_edges[:, 1], half)
        return out

    def add_nodal_heat(self, heat_flow, *, root: int | None = 0) -> None:
        """Add heat loads (n_vertices,) (W, into the structure) at the surface vertices
        (map wall-node heat with :meth:`vertex_heat` first). Read on rank ``root`` and
        broadcast (``root=None``: every rank passes the same array). Collective."""
        self.surface.add_nodal_heat(heat_flow, root=root)

    # ------------------------------------------------------------------ DEM wall
    def make_wall(self, sim, *, material: str, vertex_temperature=None):
        """Add the interface as a mesh wall (at the reference positions ``x0``) to ``sim``.

        Call on the rank that holds the DEM only (not collective); move the wall with
        ``wall.set_vertices(positions, velocities)``. ``vertex_temperature`` (n_nodes,)
        makes it a conducting wall. Returns the MeshWall.
        """
        from gsi.dem.walls import MeshWall
        if material not in sim.materials:
            raise GsiInputError(f"coupling.wall_material = {material!r}: not a DEM material; "
                                f"known: {sorted(sim.materials)}")
        p2 = {} if self._mid is None else dict(parent_nodes=self.parent_nodes,
                                               parent_coords=self.parent_coords)
        return sim.add_mesh_wall(MeshWall(self.x0.copy(), self.triangles, material=material,
                                          vertex_temperature=vertex_temperature, **p2))
