"""Every dolfinx call whose spelling differs between dolfinx versions, in one place.

Written against dolfinx 0.5.2 (Debian 12). The rest of :mod:`gsi.fem` (and :mod:`gsi.meshes`)
imports these helpers instead of dolfinx, so moving to a newer dolfinx (0.7: ``functionspace``,
``x.petsc_vec``, ``Expression(..., interpolation_points)`` property, 0.8+: ``mesh.geometry.dofmap``
as an ndarray, ``io.gmshio`` -> ``io.gmsh``, ...) is a change in this file only.

Conventions kept by these helpers (whatever the dolfinx version):

* ``petsc_vec(f)`` is the ghosted PETSc vector that shares memory with ``f.x.array``.
* ``geometry_dofmap(mesh)`` is a dense ``(num_cells, nodes_per_cell)`` int32 array.
* ``input_global_indices(mesh)`` maps local geometry nodes to their index in the array of
  nodes the mesh was built from (the gmsh node tag minus one for gmsh meshes): the
  "global vertex id" used by gsi's nodal loads, identical on any number of MPI ranks.
"""
from __future__ import annotations

import os

import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.cpp
import dolfinx.fem
import dolfinx.fem.petsc
import dolfinx.io
import dolfinx.mesh

DOLFINX_VERSION = dolfinx.__version__
ScalarType = PETSc.ScalarType

# ----------------------------------------------------------------------------- meshes

def _deterministic_partitioning() -> None:
    """Make dolfinx's mesh partitioner give the same partition on every run.

    dolfinx 0.5 (Debian) partitions with PT-Scotch 7, whose threaded coarsening makes the
    partition, and so the dof numbering and every distributed sum, differ from run to run
    (measured: 4 of 4 runs of one 2-rank box mesh gave 4 partitions). With one Scotch
    thread (Scotch 7's ``SCOTCH_PTHREAD_NUMBER``) 2-rank runs are bit-reproducible, which
    a bitwise ``--resume`` under mpirun needs. A user's own setting is kept.
    """
    os.environ.setdefault("SCOTCH_PTHREAD_NUMBER", "1")


def model_to_mesh(model, comm: MPI.Comm = MPI.COMM_WORLD, rank: int = 0, gdim: int = 3):
    """gmsh model (alive on ``rank``) -> distributed ``(mesh, cell_tags, facet_tags)``."""
    from dolfinx.io import gmshio
    _deterministic_partitioning()
    return gmshio.model_to_mesh(model, comm, rank, gdim=gdim)


def create_box_mesh(comm: MPI.Comm, p0, p1, n):
    """Structured tetrahedral box mesh between corners ``p0`` and ``p1`` (m), ``n`` cells."""
    _deterministic_partitioning()
    return dolfinx.mesh.create_box(comm, [np.asarray(p0, float), np.asarray(p1, float)],
                                   [int(k) for k in n], cell_type=dolfinx.mesh.CellType.tetrahedron)


def locate_boundary_facets(mesh, marker):
    """Local indices of exterior facets whose vertices all satisfy ``marker(x (3, n))``."""
    return dolfinx.mesh.locate_entities_boundary(mesh, mesh.topology.dim - 1, marker)


def make_meshtags(mesh, dim: int, entities, values):
    """Mesh tags of dimension ``dim`` (entities sorted as dolfinx requires)."""
    entities = np.asarray(entities, dtype=np.int32)
    values = np.asarray(values, dtype=np.int32)
    order = np.argsort(entities, kind="stable")
    return dolfinx.mesh.meshtags(mesh, dim, entities[order], values[order])


def geometry_x(mesh) -> np.ndarray:
    """Coordinates of the local (owned + ghost) geometry nodes, shape (n, 3) (m)."""
    return mesh.geometry.x


def geometry_dofmap(mesh) -> np.ndarray:
    """Cell -> geometry node indices as a dense (num_cells, nodes_per_cell) int32 array."""
    dm = mesh.geometry.dofmap
    if isinstance(dm, np.ndarray):
        return dm
    # the nodes per cell from the coordinate element: a rank may hold no cell at all
    # (a structure smaller than the number of ranks), when there is no links(0)
    nodes = mesh.geometry.cmap.create_dof_layout().num_dofs
    return dm.array.reshape(-1, nodes)


def input_global_indices(mesh) -> np.ndarray:
    """Original (input / gmsh node tag - 1) index of each local geometry node, int64."""
    return np.asarray(mesh.geometry.input_global_indices, dtype=np.int64)


def num_cells_local(mesh) -> int:
    """Number of cells owned by this rank."""
    return mesh.topology.index_map(mesh.topology.dim).size_local


def entities_to_geometry(mesh, dim: int, entities, *, orient: bool = False) -> np.ndarray:
    """Geometry node indices of mesh entities, shape (n, nodes_per_entity).

    With ``orient=True`` exterior facets of a tetrahedral mesh are ordered so that their
    right-hand normal points out of the body.
    """
    return dolfinx.cpp.mesh.entities_to_geometry(
        mesh._mesh if hasattr(mesh, "_mesh") else mesh, dim,
        np.asarray(entities, dtype=np.int32), orient)


def meshtag_find(tags, value: int) -> np.ndarray:
    """Local entity indices carrying the tag ``value``."""
    return tags.indices[tags.values == value]


# ----------------------------------------------------------------------------- spaces

def vector_space(mesh, degree: int = 1, family: str = "Lagrange"):
    """Vector (3-component) function space of the given family and degree."""
    return dolfinx.fem.VectorFunctionSpace(mesh, (family, degree))


def scalar_space(mesh, degree: int = 1, family: str = "Lagrange"):
    """Scalar function space of the given family and degree."""
    return dolfinx.fem.FunctionSpace(mesh, (family, degree))


def cell_dofs(V) -> np.ndarray:
    """Cell -> (block) dof indices as a dense (num_cells, dofs_per_cell) int32 array."""
    return V.dofmap.list.array.reshape(-1, V.dofmap.dof_layout.num_dofs)


def dof_index_map(V):
    """(index map of the blocked dofs, block size)."""
    return V.dofmap.index_map, V.dofmap.index_map_bs


def dof_coordinates(V) -> np.ndarray:
    """Coordinates (m) of the local (owned, then ghost) dof nodes of ``V``, shape (n, 3);
    one row per block (node) of a vector space."""
    return V.tabulate_dof_coordinates()


# ----------------------------------------------------------------------------- functions

def function(V, name: str | None = None):
    f = dolfinx.fem.Function(V)
    if name:
        f.name = name
    return f


def constant(mesh, value):
    return dolfinx.fem.Constant(mesh, ScalarType(value) if np.ndim(value) == 0
                                else np.asarray(value, dtype=ScalarType))


def petsc_vec(f) -> PETSc.Vec:
    """PETSc vector sharing memory with the dof array of ``f``."""
    return f.vector


def scatter_forward(f) -> None:
    """Update the ghost values of ``f`` from their owners."""
    f.x.scatter_forward()


def interpolate_expression(f, expr) -> None:
    """Interpolate the UFL expression ``expr`` into ``f`` (at its space's interpolation points)."""
    pts = f.function_space.element.interpolation_points
    pts = pts() if callable(pts) else pts
    f.interpolate(dolfinx.fem.Expression(expr, pts))


def interpolate_function(f, g) -> None:
    """Interpolate the Function ``g`` (same mesh) into ``f``."""
    f.interpolate(g)


# ----------------------------------------------------------------------------- forms, BCs

def form(a):
    """Compile a UFL form (FFCx, cached under ~/.cache/fenics)."""
    return dolfinx.fem.form(a)


def measure(kind: str, mesh, subdomain_data=None):
    """ufl measure ``dx``/``ds`` on ``mesh`` with optional tags."""
    return ufl.Measure(kind, domain=mesh, subdomain_data=subdomain_data)


def locate_dofs_topological(V, entity_dim: int, entities) -> np.ndarray:
    """Dofs of ``V`` (a space or a (sub-space, collapsed) pair) on the given entities."""
    return dolfinx.fem.locate_dofs_topological(V, entity_dim, np.asarray(entities, dtype=np.int32))


def dirichletbc(value, dofs, V=None):
    """Dirichlet condition; ``value`` a Constant/ndarray (needs ``V`` for a sub-space)."""
    if V is None:
        return dolfinx.fem.dirichletbc(value, dofs)
    return dolfinx.fem.dirichletbc(value, dofs, V)


def bc_dofs_owned(bc) -> np.ndarray:
    """Owned, unrolled (scalar) dof indices constrained by ``bc`` in the parent space."""
    dofs, first_ghost = bc.dof_indices()
    return np.asarray(dofs[:first_ghost], dtype=np.int64)


# ----------------------------------------------------------------------------- assembly

def create_matrix(a) -> PETSc.Mat:
    return dolfinx.fem.petsc.create_matrix(a)


def assemble_matrix(a, bcs=(), diagonal: float = 1.0) -> PETSc.Mat:
    """Assemble and finalise a PETSc matrix (rows/cols of ``bcs`` replaced by ``diagonal``)."""
    A = dolfinx.fem.petsc.assemble_matrix(a, bcs=list(bcs), diagonal=diagonal)
    A.assemble()
    return A


def assemble_matis(a, bcs, V) -> PETSc.Mat:
    """Assemble ``a`` unassembled (PETSc MATIS, for PCBDDC): one matrix per rank, the sum
    of the element matrices of the cells it owns, on the dofs of those cells (block size
    of ``V``); Dirichlet rows and columns of ``bcs`` replaced by 1 on the diagonal of
    every subdomain holding the dof.

    dolfinx 0.5.2's ``create_matrix(a, "is")`` gives a MATIS whose local matrix has no
    preallocation (its C++ preallocates before ``MatSetLocalToGlobalMapping``, when MATIS
    creates the local matrix: the first assembly segfaults), puts the Dirichlet 1 in the
    owner's subdomain only (the others keep an empty row: a singular Neumann problem) and
    spans the dofs of ghost cells too (empty rows). Here: the local matrix preallocated
    from the cell-to-dof map, the 1 added in every sharing subdomain (the assembled
    diagonal of such a dof is then the number of subdomains sharing it; its right-hand
    side is 0, so is its solution), and the subdomain restricted to its owned cells' dofs.
    """
    import scipy.sparse as sp
    A = dolfinx.fem.petsc.create_matrix(a, "is")
    L = A.getISLocalMat()
    imap, bs = dof_index_map(V)
    cd = cell_dofs(V)
    n_nodes = L.getSize()[0] // bs
    rows = np.repeat(np.arange(cd.shape[0]), cd.shape[1])
    B = sp.csr_matrix((np.ones(cd.size), (rows, cd.ravel())), shape=(cd.shape[0], n_nodes))
    C = (B.T @ B).tocsr()
    L.setPreallocationNNZ(np.repeat(np.diff(C.indptr) * bs, bs).astype(PETSc.IntType))
    L.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, False)
    A.zeroEntries()
    dolfinx.fem.petsc.assemble_matrix(A, a, bcs=list(bcs))
    for bc in bcs:
        dofs, first_ghost = bc.dof_indices()
        for d in np.asarray(dofs[first_ghost:]):
            L.setValue(int(d), int(d), 1.0, addv=PETSc.InsertMode.INSERT_VALUES)
    A.assemble()
    n_cells = V.mesh.topology.index_map(V.mesh.topology.dim).size_local
    used = np.unique(cd[:n_cells].ravel())
    if np.setdiff1d(np.arange(imap.size_local), used).size:
        raise RuntimeError("assemble_matis: an owned dof lies in no owned cell")
    sub = (bs * used[:, None] + np.arange(bs)).ravel().astype(PETSc.IntType)
    is_sub = PETSc.IS().createGeneral(sub, comm=PETSc.COMM_SELF)
    Lsub = L.createSubMatrix(is_sub, is_sub)
    blocks = A.getLGMap()[0].getBlockIndices()
    lgmap = PETSc.LGMap().create(blocks[used], bsize=bs, comm=A.getComm())
    P = PETSc.Mat().create(comm=A.getComm())
    P.setSizes(A.getSizes(), bsize=bs)
    P.setType("is")
    P.setLGMap(lgmap, lgmap)
    P.setISLocalMat(Lsub)
    P.assemble()
    A.destroy()
    is_sub.destroy()
    return P


def create_vector(L) -> PETSc.Vec:
    return dolfinx.fem.petsc.create_vector(L)


def assemble_vector_into(b: PETSc.Vec, L, *, a=None, bcs=()) -> None:
    """b <- assemble(L) with lifting of ``bcs`` through ``a``; ghosts accumulated; BC rows set.

    ``b`` is zeroed first. Leaves ``b`` with owned values complete.
    """
    with b.localForm() as loc:
        loc.set(0.0)
    dolfinx.fem.petsc.assemble_vector(b, L)
    if a is not None and bcs:
        dolfinx.fem.petsc.apply_lifting(b, [a], bcs=[list(bcs)])
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)


def assemble_vector_ghosted(b: PETSc.Vec, L) -> None:
    """b <- assemble(L), ghost contributions added to their owners (no BCs)."""
    assemble_vector_into(b, L)


def apply_lifting_and_accumulate(b: PETSc.Vec, a, bcs) -> None:
    """b -= A g on the free rows (local part incl. ghosts), then accumulate ghosts."""
    if bcs:
        dolfinx.fem.petsc.apply_lifting(b, [a], bcs=[list(bcs)])
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)


def set_bc(b: PETSc.Vec, bcs, scale: float = 1.0) -> None:
    """Set the owned Dirichlet rows of ``b`` to the prescribed values."""
    dolfinx.fem.petsc.set_bc(b, list(bcs), scale=scale)


def assemble_scalar(M, comm: MPI.Comm) -> float:
    """Global value of a functional (summed over ranks)."""
    return comm.allreduce(dolfinx.fem.assemble_scalar(M), op=MPI.SUM)


# ----------------------------------------------------------------------------- PETSc options

_petsc_lib = None


def petsc_option_used(name: str) -> bool | None:
    """Whether PETSc has read the option ``name`` (without the leading '-') from its
    options database (``PetscOptionsUsed``; petsc4py 3.18 does not wrap it, so it is called
    through ctypes). None if the PETSc library cannot be found (then nothing is checked)."""
    global _petsc_lib
    import ctypes
    import ctypes.util
    if _petsc_lib is None:
        major, minor, _ = PETSc.Sys.getVersion()
        lib = None
        for cand in (f"libpetsc_real.so.{major}.{minor}", f"libpetsc.so.{major}.{minor}",
                     ctypes.util.find_library("petsc_real"), ctypes.util.find_library("petsc")):
            if not cand:
                continue
            try:
                lib = ctypes.CDLL(cand)
                fn = lib.PetscOptionsUsed
                break
            except (OSError, AttributeError):
                lib = None
        if lib is None:
            _petsc_lib = False
        else:
            fn.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.POINTER(ctypes.c_int)]
            fn.restype = ctypes.c_int
            _petsc_lib = fn
    if _petsc_lib is False:
        return None
    used = ctypes.c_int(0)
    if _petsc_lib(None, name.encode(), ctypes.byref(used)) != 0:
        return None
    return bool(used.value)


def petsc_error_text(exc: Exception) -> str:
    """The last line of a petsc4py error (PETSc's own message, e.g. 'Input string abc has
    no numeric value'), or the error code."""
    lines = [ln.strip() for ln in str(exc).splitlines() if ln.strip()]
    if not lines:
        return f"PETSc error {getattr(exc, 'ierr', '?')}"
    import re
    return re.sub(r"^\[\d+\]\s*", "", lines[-1])


# ----------------------------------------------------------------------------- output

def xdmf_file(comm: MPI.Comm, path, mode: str = "w"):
    """XDMF file (with its HDF5 companion) that ParaView opens."""
    return dolfinx.io.XDMFFile(comm, str(path), mode)


def xdmf_write_mesh(xdmf, mesh) -> None:
    xdmf.write_mesh(mesh)


def xdmf_write_function(xdmf, f, t: float) -> None:
    xdmf.write_function(f, float(t))


def blas_library() -> str:
    """The BLAS this process runs on, from the shared libraries mapped into it
    (/proc/self/maps, Linux; "unknown" elsewhere): "openblas", "mkl", "blis", "reference"
    (netlib's, Debian's /usr/lib/<arch>/blas/libblas.so.3) or the library's file name.
    MUMPS's fronts, and so every direct factorization and BDDC's set-up, run on it: on the
    2-core test host the reference BLAS made MUMPS's Cholesky of a 9.9e4-dof P2 shell
    8 times slower than OpenBLAS (benchmarks/results/shell_precond.json)."""
    try:
        with open("/proc/self/maps") as f:
            paths = {line.split()[-1] for line in f if ".so" in line}
    except OSError:
        return "unknown"
    names = " ".join(sorted(paths)).lower()
    for key in ("openblas", "mkl", "blis"):
        if key in names:
            return key
    for path in sorted(paths):
        if "libblas.so" in path:
            return "reference" if "/blas/" in path or "netlib" in path else os.path.basename(path)
    return "unknown"


def use_mumps(pc, *, workspace: int | None = None) -> None:
    """Make the factorization PC ``pc`` use MUMPS; with ``workspace`` its working
    space is that many per cent above MUMPS's own estimate (ICNTL(14), MUMPS's default 20;
    a ``mat_mumps_icntl_14`` option still wins)."""
    pc.setFactorSolverType("mumps")
    if workspace is None:
        return
    try:
        pc.setFactorSetUpSolverType()      # the factor matrix, before PCSetUp factors it
    except PETSc.Error:                    # no operator yet (a scratch PC): MUMPS's default
        return
    pc.getFactorMatrix().setMumpsIcntl(14, int(workspace))
