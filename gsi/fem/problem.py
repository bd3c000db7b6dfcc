"""What every FE problem shares (:class:`Problem`): the solver choice, its options and
iterations, time and step count, the nodal loads at vertices, and ``state()`` /
``set_state()``. :class:`gsi.fem.elasticity.Elasticity` and :class:`gsi.fem.heat.Heat`
keep only their forms and time schemes.

Global vertex ids
-----------------
gsi names mesh vertices by their *global vertex id*: the index of the node in the array the
mesh was built from, i.e. the gmsh node tag minus one for gmsh meshes
(``mesh.geometry.input_global_indices``). It does not depend on the number of MPI ranks,
so a load given at a global vertex id lands on the same physical node on 1 or N ranks.
"""
from __future__ import annotations

import numpy as np
from mpi4py import MPI

from gsi.errors import GsiInputError

from . import compat
from .materials import get_material
from .options import ITERATIVE_RTOL, choose_solver, petsc_option_strings
from .solvers import LinearSolver, make_solver


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


class Problem:
    """The base of an FE problem on ``structure`` (a :class:`gsi.meshes.StructureMesh`).

    Subclasses set :attr:`kind` ("elasticity" or "heat": the solver defaults), call
    :meth:`_init_problem` and, once their space ``V`` exists, :meth:`_init_loads`; they
    name their time-integration fields in :meth:`_state_fields` and may add arrays in
    :meth:`_extra_state` / :meth:`_set_extra_state`.
    """

    kind = ""

    def _init_problem(self, structure, material, *, factorization, solver, petsc_options,
                      options_key, rtol) -> None:
        self.structure = structure
        self.mesh = structure.mesh
        self.comm = self.mesh.comm
        self.material = get_material(material)
        self.factorization = factorization
        choose_solver(solver, 0, self.kind)          # checks the name
        petsc_option_strings(petsc_options, options_key)
        self.solver, self.petsc_options, self.options_key = solver, petsc_options, options_key
        if rtol is not None and not 0.0 < rtol < 1.0:
            raise GsiInputError(f"structure.rtol = {rtol!r}: must be in (0, 1)")
        self.rtol = ITERATIVE_RTOL if rtol is None else float(rtol)
        self.t = 0.0
        self.n_steps = 0
        self._solver: LinearSolver | None = None

    def _init_loads(self) -> None:
        """The vertex map and nodal loads of the space ``self.V``."""
        self.vmap = VertexDofMap(self.V)
        self.nodal = NodalLoads(self.vmap)

    def _make_solver(self, A, **kw) -> None:
        """Build and factorize the solver of the step matrix ``A`` (once per run)."""
        self._solver = make_solver(A, self.comm, kind=self.solver_kind, problem=self.kind,
                                   factorization=self.factorization,
                                   petsc_options=self.petsc_options,
                                   options_key=self.options_key, rtol=self.rtol, **kw)
        self._solver.factorize()

    # ------------------------------------------------------------------ solver
    def set_up(self) -> None:
        """Assemble the matrices and build (factorize) the solver now (else the first
        solve or step does it)."""
        self._setup()

    @property
    def is_set_up(self) -> bool:
        """Whether the matrices are assembled and the solver built (the first solve or
        step does it)."""
        return self._solver is not None

    @property
    def linear_solver(self) -> LinearSolver | None:
        """The linear solver (None before the set-up): ``describe()``, ``ksp``,
        ``prefix``, ``scratch_dir``, ``factor_seconds``, ``destroy()``."""
        return self._solver

    @property
    def n_factorizations(self) -> int:
        """Number of factorizations of the effective matrix (direct) or builds of its
        multigrid preconditioner (iterative) so far (1 after set-up)."""
        return 0 if self._solver is None else self._solver.n_factorizations

    @property
    def n_dofs(self) -> int:
        imap, bs = compat.dof_index_map(self.V)
        return imap.size_global * bs

    @property
    def solver_kind(self) -> str:
        """The linear solver used: "direct" or "iterative" ("auto" resolved by size)."""
        return choose_solver(self.solver, self.n_dofs, self.kind)

    @property
    def iterations(self) -> list[int]:
        """Krylov iterations of every solve so far (1 each for the direct solver)."""
        return [] if self._solver is None else list(self._solver.iterations)

    # ------------------------------------------------------------------ time
    def advance_time(self, dt: float) -> None:
        """Count one step of ``dt`` (s) without solving (a structure that stays at rest)."""
        self.t += dt
        self.n_steps += 1

    # ------------------------------------------------------------------ state
    def _state_fields(self) -> dict:
        """name -> Function of the time-integration state."""
        raise NotImplementedError

    def _extra_state(self) -> dict:
        return {}

    def _set_extra_state(self, st: dict) -> None:
        pass

    def _n_owned(self) -> int:
        imap, bs = compat.dof_index_map(self.V)
        return imap.size_local * bs

    def state(self) -> dict:
        """Plain arrays of this rank's state for checkpoints: the owned dof values of the
        time-integration fields, the nodal loads (``nodal``), ``t``, ``n_steps`` (and
        the problem's own extras). A restart must use the same mesh and number of
        ranks."""
        n = self._n_owned()
        st = {name: f.x.array[:n].copy() for name, f in self._state_fields().items()}
        st.update(t=np.float64(self.t), n_steps=np.int64(self.n_steps),
                  n_ranks=np.int64(self.comm.size), nodal=self.nodal.values.copy())
        st.update(self._extra_state())
        return st

    def set_state(self, st: dict) -> None:
        """Restore :meth:`state` (collective; same mesh and number of ranks)."""
        if int(st["n_ranks"]) != self.comm.size:
            raise GsiInputError(f"restart n_ranks = {int(st['n_ranks'])}: must equal the "
                                f"current number of MPI ranks ({self.comm.size})")
        n = self._n_owned()
        for name, f in self._state_fields().items():
            f.x.array[:n] = st[name]
            compat.scatter_forward(f)
        self.t, self.n_steps = float(st["t"]), int(st["n_steps"])
        if "nodal" in st:
            self.nodal.values[:] = st["nodal"]
        self._set_extra_state(st)
