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
from petsc4py import PETSc

from gsi.errors import GsiInputError

from . import compat
from .dirichlet import Dirichlet
from .materials import get_material
from .options import DIRECT_FACTORIZATION, ITERATIVE_RTOL, choose_solver, petsc_option_strings
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
    build their forms in ``_setup`` (ending with :meth:`_init_vectors` and
    :meth:`_make_solver`), name their time-integration fields in :meth:`_state_fields`
    and may add arrays in :meth:`_extra_state` / :meth:`_set_extra_state`.

    Notes
    -----
    The keyword options every problem takes (documented here once):

    material : StructuralMaterial or str or dict
        Material (library name, table, or object).
    factorization : {"lu", "cholesky"}, optional
        MUMPS factorization of the step matrix (direct solver, one rank); default
        ``gsi.fem.options.DIRECT_FACTORIZATION[kind]`` (Cholesky for elasticity).
    solver : {"auto", "direct", "out_of_core", "iterative"}
        Linear solver: MUMPS factorized once, the same with the factor on disk (MUMPS
        Cholesky, any number of ranks), a Krylov method with an algebraic-multigrid
        preconditioner built once and a warm start, or by size ("auto": from
        ``gsi.fem.options.AUTO_LARGE_DOFS[kind]`` dofs on).
    petsc_options : dict, optional
        PETSc options without the leading dash, under this problem's own prefix.
    rtol : float, optional
        Iterative solver: the residual falls to rtol times that of the warm start (default
        ``gsi.fem.options.ITERATIVE_RTOL``; ``ksp_rtol`` in ``petsc_options`` overrides it).
    options_key : str
        TOML key of ``petsc_options`` named by errors (e.g. ``structures[0].petsc``).

    The Dirichlet conditions live in :attr:`dirichlet` (:class:`gsi.fem.dirichlet.Dirichlet`),
    the point loads in :attr:`nodal` (:class:`NodalLoads`).
    """

    kind = ""

    def _init_problem(self, structure, material, *, factorization, solver, petsc_options,
                      options_key, rtol) -> None:
        self.structure = structure
        self.mesh = structure.mesh
        self.comm = self.mesh.comm
        self.material = get_material(material)
        self.factorization = factorization or DIRECT_FACTORIZATION[self.kind]
        choose_solver(solver, 0, self.kind)          # checks the name
        petsc_option_strings(petsc_options, options_key)
        self.solver, self.petsc_options, self.options_key = solver, petsc_options, options_key
        if rtol is not None and not 0.0 < rtol < 1.0:
            raise GsiInputError(f"structure.rtol = {rtol!r}: must be in (0, 1)")
        self.rtol = ITERATIVE_RTOL if rtol is None else float(rtol)
        self.t = 0.0
        self.n_steps = 0
        self.dirichlet = Dirichlet(structure)
        self._solver: LinearSolver | None = None

    def _init_loads(self) -> None:
        """The vertex map and nodal loads of the space ``self.V``."""
        self.vmap = VertexDofMap(self.V)
        self.nodal = NodalLoads(self.vmap)

    def _init_vectors(self, f_form, a_form) -> None:
        """The compiled load form ``_f`` = ``f_form``, the right-hand side ``_b``, the load
        vector ``_F``, scratch ``_tmp`` and the lifting ``_lift`` = -A g of the Dirichlet
        values (``a_form``: the compiled step form)."""
        self._f = f_form
        self._b = compat.create_vector(f_form)
        self._F = self._b.duplicate()
        self._tmp = self._b.duplicate()
        self._lift = compat.create_vector(f_form)
        with self._lift.localForm() as loc:
            loc.set(0.0)
        compat.apply_lifting_and_accumulate(self._lift, a_form, self.bcs)

    def _assemble_load(self, out: PETSc.Vec) -> None:
        """out <- f (the load form plus the nodal loads), owned values, no Dirichlet rows."""
        compat.assemble_vector_ghosted(out, self._f)
        out.array[:] += self.nodal.values

    def _make_solver(self, A, a_form=None, **kw) -> None:
        """Build and factorize the solver of the step matrix ``A`` (once per run), the
        assembled form of ``a_form`` (given: BDDC may assemble it unassembled, MATIS)."""
        if a_form is not None:
            kw["matis"] = lambda: compat.assemble_matis(a_form, self.bcs, self.V)
        self._solver = make_solver(A, self.comm, kind=self.solver_kind, problem=self.kind,
                                   factorization=self.factorization,
                                   petsc_options=self.petsc_options,
                                   options_key=self.options_key, rtol=self.rtol, **kw)
        self._solver.factorize()

    @property
    def bcs(self) -> list:
        """The dolfinx Dirichlet conditions (:attr:`dirichlet`), in the order given."""
        return self.dirichlet.bcs

    def add_nodal_loads(self, global_ids, loads) -> None:
        """Add point loads at mesh vertices given by global vertex ids (n,): forces (n, 3)
        (N) of an elasticity, heat (n,) (W, into the body) of a heat problem.

        Global vertex id = gmsh node tag - 1 (``mesh.geometry.input_global_indices``).
        The loads act from the next solve/step on, until :meth:`clear_nodal_loads`.
        Every rank keeps the loads at the vertices it owns (see ``NodalLoads.add``).
        """
        self.nodal.add(global_ids, loads)

    def clear_nodal_loads(self) -> None:
        """Remove every nodal load (local)."""
        self.nodal.clear()

    def load_vector(self) -> PETSc.Vec:
        """The current load vector f (N of an elasticity, W of a heat problem: the load
        form plus the nodal loads, owned values), before Dirichlet rows are set."""
        self._setup()
        self._assemble_load(self._F)
        return self._F

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

    def integral(self, key, integrand) -> float:
        """The integral of the UFL form ``integrand()`` over the whole mesh (collective),
        its form compiled once per ``key`` (the form may read fields that change)."""
        forms = self.__dict__.setdefault("_integrals", {})
        if key not in forms:
            forms[key] = compat.form(integrand())
        return compat.assemble_scalar(forms[key], self.comm)

    def volume(self) -> float:
        """Volume of the body (m^3) (collective; computed once)."""
        if getattr(self, "_volume", None) is None:
            self._volume = self.integral("volume", lambda: compat.constant(
                self.mesh, 1.0) * compat.measure("dx", self.mesh))
        return self._volume

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
