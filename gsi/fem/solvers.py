"""The linear solvers of the FE problems (their shared base: :mod:`gsi.fem.problem`).

Linear solvers
--------------
Every problem solves with one fixed matrix per run (the effective matrix of its time
scheme), so the expensive part of a solver is built once and re-used every step:

* ``direct``: MUMPS LU (or Cholesky) on one rank, SuperLU_DIST LU on several (for
  bit-reproducible runs, see :class:`FactorOnceSolver`), factorized once;
* ``out_of_core``: MUMPS Cholesky on any number of ranks, factorized once with the factor
  written to disk (:class:`OutOfCoreSolver`): the direct solve of structures whose factor
  does not fit in memory;
* ``iterative``: conjugate gradients preconditioned by algebraic multigrid, the hierarchy
  built once (:class:`IterativeSolver`): hypre's BoomerAMG for both problems, in its
  systems form for elasticity (:data:`gsi.fem.options.ITERATIVE_PC`, measured in
  benchmarks/shell_precond.py), or with ``petsc_options = {pc_type = "gamg"}`` (and where
  PETSc has no hypre) PETSc's GAMG, with the six rigid-body modes as its near-nullspace
  for elasticity (smoothed aggregation, Vanek, Mandel & Brezina 1996). Every solve starts from the
  last solution x_0 (warm start) and stops at ||b - A x|| <= 1e-12 ||b - A x_0||
  (:data:`gsi.fem.options.ITERATIVE_RTOL`). Two presets of
  :data:`gsi.fem.options.ITERATIVE_DEFAULTS` replace the multigrid, each CG to 1e-10:
  ``{pc_type = "bddc"}`` (elasticity, 2 or more ranks: BDDC, a subdomain per rank) and
  ``{pc_type = "cholesky"}`` (elasticity and heat, any ranks: MUMPS's block low-rank
  Cholesky factor, :data:`gsi.fem.options.BLR_EPSILON`);
* ``auto``: from :data:`gsi.fem.options.AUTO_LARGE_DOFS` global dofs on
  :data:`gsi.fem.options.AUTO_LARGE_SOLVER`
  (elasticity out of core, heat iterative), else direct.

``petsc_options`` (TOML ``[structures.petsc]``) are PETSc options without the leading
dash, e.g. ``{"ksp_rtol": 1e-12, "pc_gamg_threshold": 0.02}``; they are set under an
options prefix of their own for each solver (two structures never share options) and
override gsi's defaults. A key that PETSc did not use, or a value it refused, is a
one-line GsiInputError naming the key.
"""
from __future__ import annotations

import os
import shutil
import tempfile
import weakref

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

from gsi.errors import GsiInputError

from . import compat
from .linear_solver import LinearSolver
from .options import (ITERATIVE_ATOL, ITERATIVE_RTOL, OUT_OF_CORE_DEFAULTS, direct_workspace,
                      iterative_defaults)

__all__ = ["LinearSolver", "FactorOnceSolver", "OutOfCoreSolver", "IterativeSolver",
           "make_solver", "rigid_body_modes"]


def _hypre_available() -> bool:
    pc = PETSc.PC().create(PETSc.COMM_SELF)
    try:
        pc.setType("hypre")
        return True
    except PETSc.Error:
        return False
    finally:
        pc.destroy()


def rigid_body_modes(V, A: PETSc.Mat) -> PETSc.NullSpace:
    """The six rigid-body modes of a 3D vector space (three translations, three
    rotations about the centroid), orthonormalized: GAMG's near-nullspace of elasticity."""
    comm = A.getComm().tompi4py()
    imap, bs = compat.dof_index_map(V)
    if bs != 3:
        raise RuntimeError("rigid_body_modes: needs a 3-component vector space")
    n = imap.size_local
    x = compat.dof_coordinates(V)[:n]
    total = comm.allreduce(np.r_[x.sum(axis=0), n], op=MPI.SUM)
    x = x - total[:3] / max(total[3], 1.0)
    basis = [A.createVecLeft() for _ in range(6)]
    arr = [b.getArray() for b in basis]
    for a in arr:
        a[:] = 0.0
    for c in range(3):
        arr[c][c::3] = 1.0
    arr[3][0::3], arr[3][1::3] = -x[:, 1], x[:, 0]
    arr[4][1::3], arr[4][2::3] = -x[:, 2], x[:, 1]
    arr[5][0::3], arr[5][2::3] = x[:, 2], -x[:, 0]
    del arr
    for i, b in enumerate(basis):            # modified Gram-Schmidt
        for prev in basis[:i]:
            b.axpy(-b.dot(prev), prev)
        b.normalize()
    return PETSc.NullSpace().create(vectors=basis, comm=A.getComm())


class FactorOnceSolver(LinearSolver):
    """Direct solver (PETSc KSP preonly) factorizing ``A`` exactly once.

    One rank: MUMPS, LU or Cholesky. Several ranks: SuperLU_DIST LU, because MUMPS's
    distributed factorization is not bit-reproducible from run to run (it sums the
    contribution blocks in the order they arrive): measured on a 2-rank heat problem, 5 of
    5 runs of 200 steps gave 5 different fields (differing by 2.5e-12 K on 300 K), while
    SuperLU_DIST gave 5 identical ones at the same factorization time (56k-dof P2
    elasticity, 2 ranks: 42.8 s against MUMPS's 40.3 s, machine loaded). A bitwise
    ``--resume`` under mpirun needs a reproducible solve.

    ``n_factorizations`` counts the numerical factorizations this object triggered.
    Without ``petsc_options`` PETSc's options database is not read at all.
    """

    kind = "direct"

    def __init__(self, A: PETSc.Mat, comm: MPI.Comm, *, factorization: str = "lu",
                 problem: str = "elasticity", petsc_options=None,
                 options_key: str = "structure.petsc"):
        if factorization not in ("lu", "cholesky"):
            raise GsiInputError(f"structure.factorization = {factorization!r}: must be 'lu' or 'cholesky'")
        super().__init__(A, comm, problem=problem, petsc_options=petsc_options,
                         options_key=options_key)
        self.factorization = factorization
        self._configure_scratch(self.ksp)
        self.ksp.getPC().setReusePreconditioner(True)
        self._set_options({})

    def _configure_scratch(self, ksp) -> None:
        ksp.setType("preonly")
        pc = ksp.getPC()
        if ksp.getComm().getSize() == 1:
            pc.setType(self.factorization)
            compat.use_mumps(pc, workspace=direct_workspace(self.factorization, self.user_options))
        else:
            pc.setType("lu")
            pc.setFactorSolverType("superlu_dist")


_SCRATCH_PREFIX = "gsi-mumps-"


def _scratch_dir() -> str:
    """A new directory for MUMPS's out-of-core files of one solver, under
    $MUMPS_OOC_TMPDIR or the system's temporary directory; the directories left there by
    killed gsi processes of this host are removed first."""
    import socket
    root = os.environ.get("MUMPS_OOC_TMPDIR") or tempfile.gettempdir()
    host = socket.gethostname().replace("-", "_")
    prefix = f"{_SCRATCH_PREFIX}{host}-"
    try:
        names = os.listdir(root)
    except OSError:
        names = []
    for name in names:
        if not name.startswith(prefix):
            continue
        pid = name[len(prefix):].split("-", 1)[0]
        if pid.isdigit() and int(pid) != os.getpid() and not _alive(int(pid)):
            shutil.rmtree(os.path.join(root, name), ignore_errors=True)
    return tempfile.mkdtemp(prefix=f"{prefix}{os.getpid()}-", dir=root)


def _alive(pid: int) -> bool:
    """Whether process ``pid`` exists on this host (another user's counts as alive)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        pass
    return True


class FactorFiles:
    """The directory of one solver's MUMPS out-of-core files (``path``:
    ``gsi-mumps-<host>-<pid>-*`` under ``$MUMPS_OOC_TMPDIR`` if set, else the system's
    temporary directory), removed with its ``owner`` (when it is garbage-collected, at the
    interpreter's exit, or by :meth:`remove`); the directories of killed runs are removed
    by the next solver that makes one (:func:`_scratch_dir`). MUMPS reads
    $MUMPS_OOC_TMPDIR when it factorizes: :meth:`factorize` points it at ``path`` for
    that call and restores the user's value."""

    def __init__(self, owner):
        self.path = _scratch_dir()
        self.remove = weakref.finalize(owner, shutil.rmtree, self.path, ignore_errors=True)

    def factorize(self, factorize) -> None:
        before = os.environ.get("MUMPS_OOC_TMPDIR")
        os.environ["MUMPS_OOC_TMPDIR"] = self.path
        try:
            factorize()
        finally:
            if before is None:
                del os.environ["MUMPS_OOC_TMPDIR"]
            else:
                os.environ["MUMPS_OOC_TMPDIR"] = before


class OutOfCoreSolver(LinearSolver):
    """Direct solver with its factor on disk: MUMPS Cholesky, factorized once.

    For structures whose factor does not fit in memory (a 1e6-dof P2 shell on 2 ranks:
    see benchmarks/fe_scale.py): MUMPS's out-of-core mode (Amestoy et al., MUMPS users'
    guide, ICNTL(22) = 1) writes the factor to files while it factorizes and reads it back
    at every solve, so memory holds the matrix and the active fronts only. The files go to
    a directory of this solver's own (``scratch_dir``: ``gsi-mumps-<host>-<pid>-*``)
    under ``$MUMPS_OOC_TMPDIR`` if set, else the system's temporary directory (``$TMPDIR``,
    else /tmp). The directory is removed with the solver, when it is garbage-collected or
    at the interpreter's exit (PETSc does not destroy the objects alive at its end, and
    MUMPS removes its files only then); the directories of killed runs (their process gone,
    same host) are removed by the next out-of-core solver that starts. Unlike the in-memory direct
    solver on several ranks (SuperLU_DIST), MUMPS's distributed factorization is not
    bit-reproducible from run to run (see :class:`FactorOnceSolver`): the fields agree to
    round-off. ``petsc_options`` override the defaults
    (:data:`gsi.fem.options.OUT_OF_CORE_DEFAULTS`).
    """

    kind = "out_of_core"

    def __init__(self, A: PETSc.Mat, comm: MPI.Comm, *, problem: str = "elasticity",
                 petsc_options=None, options_key: str = "structure.petsc"):
        super().__init__(A, comm, problem=problem, petsc_options=petsc_options,
                         options_key=options_key)
        self.files = FactorFiles(self)
        self.scratch_dir = self.files.path
        self._configure_scratch(self.ksp)
        self.ksp.getPC().setReusePreconditioner(True)
        self._set_options({k: v for k, v in OUT_OF_CORE_DEFAULTS.items()
                           if k.startswith("mat_mumps")})

    def factorize(self) -> None:
        if not self._ready:
            self.files.factorize(super().factorize)

    def destroy(self) -> None:
        super().destroy()
        self.files.remove()

    def _configure_scratch(self, ksp) -> None:
        ksp.setType(OUT_OF_CORE_DEFAULTS["ksp_type"])
        pc = ksp.getPC()
        pc.setType(OUT_OF_CORE_DEFAULTS["pc_type"])
        pc.setFactorSolverType(OUT_OF_CORE_DEFAULTS["pc_factor_mat_solver_type"])


class IterativeSolver(LinearSolver):
    """CG + algebraic multigrid, the hierarchy built once, warm-started from ``x``.

    The preconditioner is the user's ``pc_type`` if given, else
    :data:`gsi.fem.options.ITERATIVE_PC` of the problem (GAMG where PETSc has no hypre),
    with gsi's defaults of that type (:func:`gsi.fem.options.iterative_defaults`).

    Parameters
    ----------
    A, comm, problem, petsc_options, options_key
        As :class:`LinearSolver`.
    matis : callable, optional
        Makes A unassembled (:func:`gsi.fem.compat.assemble_matis`), for ``pc_type = "bddc"``.
    near_nullspace : PETSc.NullSpace or callable, optional
        Near-nullspace of A (elasticity: :func:`rigid_body_modes`), or a function making
        it; attached to A for GAMG, and for BoomerAMG only when the user asks for
        interpolation vectors (``pc_hypre_boomeramg_vec_interp_variant``: the nodal form,
        which benchmarks/shell_precond.py measured slower per step than the systems form).
    rtol : float
        Relative tolerance: the residual falls to ``rtol`` times the initial guess's
        residual (``ksp_rtol`` overrides it).

    Notes
    -----
    The KSP gets its operator once and keeps the preconditioner
    (``PCSetReusePreconditioner``), so PETSc does not rebuild it when a solve follows;
    ``n_factorizations`` stays 1. A right-hand side of zero gives x = 0 without iterating
    (a relative tolerance cannot be met there from a nonzero warm start). Besides the
    relative tolerance, a solve stops at ||b - A x|| <= ITERATIVE_ATOL ||b|| (round-off
    level; ``ksp_atol`` replaces it).
    """

    kind = "iterative"

    def __init__(self, A: PETSc.Mat, comm: MPI.Comm, *, problem: str, petsc_options=None,
                 options_key: str = "structure.petsc", near_nullspace=None,
                 rtol: float = ITERATIVE_RTOL, matis=None):
        super().__init__(A, comm, problem=problem, petsc_options=petsc_options,
                         options_key=options_key)
        defaults = iterative_defaults(problem, self.user_options.get("pc_type"),
                                      hypre=_hypre_available())
        if rtol != ITERATIVE_RTOL:      # a caller's own tolerance wins over a type's default
            defaults.pop("ksp_rtol", None)
        self.defaults = defaults
        self.P = None
        target = A
        if defaults["pc_type"] == "bddc":
            if matis is None:
                raise GsiInputError(f"{options_key}.pc_type = 'bddc': BDDC is available for "
                                    "elasticity only; use pc_type = 'hypre' or 'gamg' here")
            if comm.size == 1:  # one subdomain: a direct solve, at BDDC's extra cost
                raise GsiInputError(f"{options_key}.pc_type = 'bddc': needs 2 or more MPI "
                                    "ranks (a subdomain per rank); on one rank use "
                                    "solver = 'direct'")
            self.P = target = matis()            # BDDC's own (unassembled) copy of A
            self.ksp.setOperators(A, self.P)       # CG multiplies by A itself
        wants = defaults["pc_type"] in ("gamg", "bddc") or any(
            k.startswith("pc_hypre_boomeramg_vec_interp") for k in self.user_options)
        if near_nullspace is not None and wants:
            target.setNearNullSpace(near_nullspace() if callable(near_nullspace) else near_nullspace)
        ksp = self.ksp
        self._configure_scratch(ksp)
        ksp.setTolerances(rtol=rtol, atol=0.0, max_it=10000)
        ksp.setNormType(PETSc.KSP.NormType.UNPRECONDITIONED)
        ksp.setInitialGuessNonzero(True)
        ksp.getPC().setReusePreconditioner(True)
        self._set_options(defaults)
        # the block low-rank factor on disk (mat_mumps_icntl_22 = 1): its files in a
        # directory of this solver's own, as out_of_core's
        on_disk = str(self.user_options.get("mat_mumps_icntl_22", "0")) == "1"
        self.files = FactorFiles(self) if on_disk and defaults["pc_type"] == "cholesky" else None
        self.scratch_dir = self.files.path if self.files else None

    def factorize(self) -> None:
        if self.files is None or self._ready:
            super().factorize()
        else:
            self.files.factorize(super().factorize)

    def _configure_scratch(self, ksp) -> None:
        ksp.setType(self.defaults["ksp_type"])
        if "pc_type" not in self.user_options:      # a user's type: set (and checked) by
            ksp.getPC().setType(self.defaults["pc_type"])   # PETSc's options, in _set_options

    def _solve(self, b, x) -> tuple[int, int]:
        bnorm = b.norm()
        if bnorm == 0.0:
            x.set(0.0)
            return 1, 0
        if "ksp_atol" not in self.user_options:
            # a floor near round-off: a warm start that already solves the system is kept
            self.ksp.setTolerances(atol=ITERATIVE_ATOL * bnorm)
        return super()._solve(b, x)

    def destroy(self) -> None:
        super().destroy()
        _ = self.P is not None and self.P.destroy()
        _ = self.files is not None and self.files.remove()

    def _failure(self, reason: int) -> str:
        its = self.ksp.getIterationNumber()
        rnorm = self.ksp.getResidualNorm()
        return (f"FE iterative solve failed (PETSc reason {reason}, {its} iterations, residual "
                f"{rnorm:.3g}): check the supports (a free rigid-body mode makes K singular), "
                "or use solver = 'direct'")


def make_solver(A: PETSc.Mat, comm: MPI.Comm, *, kind: str, problem: str,
                factorization: str = "lu", petsc_options=None,
                options_key: str = "structure.petsc", near_nullspace=None,
                rtol: float = ITERATIVE_RTOL, matis=None) -> LinearSolver:
    """The solver of ``kind`` ("direct", "out_of_core" or "iterative", see
    :func:`gsi.fem.options.choose_solver`)."""
    if kind == "direct":
        return FactorOnceSolver(A, comm, factorization=factorization, problem=problem,
                                petsc_options=petsc_options, options_key=options_key)
    if kind == "out_of_core":
        return OutOfCoreSolver(A, comm, problem=problem, petsc_options=petsc_options,
                               options_key=options_key)
    return IterativeSolver(A, comm, problem=problem, petsc_options=petsc_options,
                           options_key=options_key, near_nullspace=near_nullspace, rtol=rtol,
                           matis=matis)
