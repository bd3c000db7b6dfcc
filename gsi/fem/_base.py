"""Pieces shared by the FE problems: vertex <-> dof maps, nodal loads, the factor-once solver.

Global vertex ids
-----------------
gsi names mesh vertices by their *global vertex id*: the index of the node in the array the
mesh was built from, i.e. the gmsh node tag minus one for gmsh meshes
(``mesh.geometry.input_global_indices``). It does not depend on the number of MPI ranks,
so a load given at a global vertex id lands on the same physical node on 1 or N ranks.
"""
from __future__ import annotations

import time

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

from gsi.errors import GsiInputError

from . import compat


class VertexDofMap:
    """Map between mesh vertices (global ids) and the dofs of a Lagrange space.

    Built once, cell by cell: for P1 and P2 Lagrange on tetrahedra the first four dofs
    of a cell sit at its four vertices, in the order of the cell's geometry nodes.

    Attributes
    ----------
    node_dof : ndarray (n_nodes,) int32
        Local (block) dof of every local geometry node.
    global_ids : ndarray (n_nodes,) int64
        Global vertex id of every local geometry node.
    owned_ids, owned_dofs : ndarray
        Global ids of the vertices whose dof this rank owns (sorted) and their dofs.
    n_global : int
        Number of vertices of the whole mesh.
    """

    def __init__(self, V):
        mesh = V.mesh
        self.V = V
        self.bs = V.dofmap.index_map_bs
        gdm = compat.geometry_dofmap(mesh)
        cdofs = compat.cell_dofs(V)
        n_nodes = compat.geometry_x(mesh).shape[0]
        node_dof = np.full(n_nodes, -1, dtype=np.int32)
        node_dof[gdm[:, :4].ravel()] = cdofs[:, :4].ravel()
        if np.any(node_dof < 0):
            raise RuntimeError("VertexDofMap: some geometry node is not a cell vertex")
        self.node_dof = node_dof
        self.global_ids = compat.input_global_indices(mesh)
        imap, _ = compat.dof_index_map(V)
        owned = node_dof < imap.size_local
        order = np.argsort(self.global_ids[owned])
        self.owned_ids = self.global_ids[owned][order]
        self.owned_dofs = node_dof[owned][order]
        self.owned_nodes = np.flatnonzero(owned)[order]
        self.n_global = mesh.comm.allreduce(int(self.owned_ids.size), op=MPI.SUM)

    def lookup_owned(self, global_ids: np.ndarray):
        """(positions in ``global_ids`` owned here, their local block dofs)."""
        ids = np.asarray(global_ids, dtype=np.int64)
        if ids.size and (ids.min() < 0 or ids.max() >= self.n_global):
            raise GsiInputError(f"nodal load vertex id = {int(ids.min()) if ids.min() < 0 else int(ids.max())}: "
                                f"must be in [0, {self.n_global}) (global vertex ids of the mesh)")
        if self.owned_ids.size == 0:
            return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int32)
        pos = np.minimum(np.searchsorted(self.owned_ids, ids), self.owned_ids.size - 1)
        hit = self.owned_ids[pos] == ids
        rows = np.flatnonzero(hit)
        return rows, self.owned_dofs[pos[rows]]


class NodalLoads:
    """Point loads at vertices, kept on the owned unrolled dofs of a space.

    The loads are *added* to the assembled right-hand side every step until cleared.
    """

    def __init__(self, vmap: VertexDofMap):
        self.vmap = vmap
        imap, bs = compat.dof_index_map(vmap.V)
        self.values = np.zeros(imap.size_local * bs)

    def add(self, global_ids, loads) -> None:
        """Accumulate ``loads`` (n, bs) (or (n,) for bs = 1) at ``global_ids`` (n,).

        Every rank may pass any loads: each rank keeps those at vertices it owns, so the
        call is correct when all ranks pass the same arrays, or when each rank passes
        (at least) the loads at its own vertices. Loads at vertices owned elsewhere are
        ignored on this rank.
        """
        bs = self.vmap.bs
        ids = np.asarray(global_ids, dtype=np.int64).ravel()
        F = np.asarray(loads, dtype=float).reshape(ids.size, bs)
        if not np.all(np.isfinite(F)):
            raise GsiInputError("nodal loads: must be finite numbers (N or W)")
        rows, dofs = self.vmap.lookup_owned(ids)
        for c in range(bs):
            np.add.at(self.values, dofs * bs + c, F[rows, c])

    def clear(self) -> None:
        self.values[:] = 0.0


class FactorOnceSolver:
    """Direct solver (PETSc KSP preonly) factorizing ``A`` exactly once.

    One rank: MUMPS, LU or Cholesky. Several ranks: SuperLU_DIST LU, because MUMPS's
    distributed factorization is not bit-reproducible from run to run (it sums the
    contribution blocks in the order they arrive): measured on a 2-rank heat problem, 5 of
    5 runs of 200 steps gave 5 different fields (differing by 2.5e-12 K on 300 K), while
    SuperLU_DIST gave 5 identical ones at the same factorization time (56k-dof P2
    elasticity, 2 ranks: 42.8 s against MUMPS's 40.3 s, machine loaded). A bitwise
    ``--resume`` under mpirun needs a reproducible solve.

    ``n_factorizations`` counts the numerical factorizations this object triggered.
    """

    def __init__(self, A: PETSc.Mat, comm: MPI.Comm, *, factorization: str = "lu"):
        if factorization not in ("lu", "cholesky"):
            raise GsiInputError(f"structure.factorization = {factorization!r}: must be 'lu' or 'cholesky'")
        self.ksp = PETSc.KSP().create(comm)
        self.ksp.setOperators(A)
        self.ksp.setType("preonly")
        pc = self.ksp.getPC()
        if comm.size == 1:
            pc.setType(factorization)
            pc.setFactorSolverType("mumps")
        else:
            pc.setType("lu")
            pc.setFactorSolverType("superlu_dist")
        self.package = pc.getFactorSolverType()
        pc.setReusePreconditioner(True)
        self.n_factorizations = 0
        self.factor_seconds = 0.0   # wall time of the factorization(s) (s)
        self._ready = False

    def factorize(self) -> None:
        if not self._ready:
            t0 = time.perf_counter()
            self.ksp.setUp()
            self.factor_seconds += time.perf_counter() - t0
            self.n_factorizations += 1
            self._ready = True

    def solve(self, b: PETSc.Vec, x: PETSc.Vec) -> None:
        self.factorize()
        self.ksp.solve(b, x)
        reason = self.ksp.getConvergedReason()
        if reason < 0:
            from gsi.errors import GsiRunError
            raise GsiRunError(f"FE linear solve failed (PETSc reason {reason}): "
                              "check the supports (a free rigid-body mode makes K singular)")

    def destroy(self) -> None:
        self.ksp.destroy()
