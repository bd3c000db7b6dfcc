"""The base of gsi's FE linear solvers (:mod:`gsi.fem.solvers`): one PETSc KSP for one
fixed matrix, its options under a prefix of its own, checked (a key PETSc refused or did
not use is a one-line GsiInputError naming it), set up once and re-used every step.
"""
from __future__ import annotations

import itertools
import time

from mpi4py import MPI
from petsc4py import PETSc

from gsi.errors import GsiInputError, GsiRunError

from . import compat
from .options import petsc_option_strings

__all__ = ["LinearSolver"]

_prefix_counter = itertools.count()


class LinearSolver:
    """A PETSc KSP for one fixed matrix: set up once, then solve every step.

    Parameters
    ----------
    A : PETSc.Mat
        The matrix (assembled, Dirichlet rows and columns replaced by the identity).
    comm : MPI communicator
    problem : str
        "elasticity" or "heat" (names the options prefix).
    petsc_options : dict, optional
        PETSc options without the dash (see the module docstring); they override gsi's.
    options_key : str
        TOML key of those options, for error messages.

    Attributes
    ----------
    kind : str
        "direct", "out_of_core" or "iterative".
    prefix : str
        PETSc options prefix of this solver (unique in the process).
    n_factorizations : int
        Set-ups of the preconditioner this object triggered: factorizations (direct) or
        multigrid hierarchies (iterative); 1 after set-up, for the whole run.
    factor_seconds : float
        Wall time of that set-up (s).
    iterations : list of int
        Krylov iterations of every solve (1 per solve for the direct solver).
    """

    kind = ""

    def __init__(self, A: PETSc.Mat, comm: MPI.Comm, *, problem: str, petsc_options=None,
                 options_key: str = "structure.petsc"):
        self.A = A
        self.comm = comm
        self.options_key = options_key
        self.user_options = petsc_option_strings(petsc_options, options_key)
        self.prefix = f"gsi_{problem}{next(_prefix_counter)}_"
        self.ksp = PETSc.KSP().create(comm)
        self.ksp.setOptionsPrefix(self.prefix)
        self.ksp.setOperators(A)
        self.n_factorizations = 0
        self.factor_seconds = 0.0
        self.iterations: list[int] = []
        self._ready = False
        self._db_keys: list[str] = []

    # ---------------------------------------------------------------- options
    def _set_options(self, defaults: dict[str, str]) -> None:
        """Put ``defaults`` and then the user's options into PETSc's options database
        under this solver's prefix and let the KSP read them."""
        if not defaults and not self.user_options:
            return
        opts = PETSc.Options()
        for k, v in {**defaults, **self.user_options}.items():
            opts[self.prefix + k] = v
            self._db_keys.append(self.prefix + k)
        try:
            self.ksp.setFromOptions()
        except PETSc.Error as exc:
            raise self._refused(exc, defaults) from None

    def _refused(self, exc, defaults) -> GsiInputError:
        """The one-line error for options PETSc refused: find the key alone at fault
        (each user option tried on its own on a scratch solver of this process)."""
        text = compat.petsc_error_text(exc)
        self._clear_options()
        opts = PETSc.Options()
        for k, v in self.user_options.items():
            scratch = self.prefix + "check_"
            trial = {**defaults, k: v}
            ksp = PETSc.KSP().create(PETSc.COMM_SELF)
            ksp.setOptionsPrefix(scratch)
            self._configure_scratch(ksp)
            for kk, vv in trial.items():
                opts[scratch + kk] = vv
            try:
                ksp.setFromOptions()
            except PETSc.Error as e:
                return GsiInputError(f"{self.options_key}.{k} = {v!r}: PETSc refused it "
                                     f"({compat.petsc_error_text(e)})")
            finally:
                for kk in trial:
                    opts.delValue(scratch + kk)
                ksp.destroy()
        keys = ", ".join(self.user_options) or "none"
        return GsiInputError(f"{self.options_key}: PETSc refused these options ({keys}): {text}")

    def _configure_scratch(self, ksp) -> None:
        """Give a scratch KSP this solver's types (for :meth:`_refused`)."""

    def _check_used(self) -> None:
        """After the first solve: every user option must have been read by PETSc
        (collective; an option read on any rank counts)."""
        unused = []
        for k in self.user_options:
            used = compat.petsc_option_used(self.prefix + k)
            if used is None:               # PETSc's library not found: nothing to check
                break
            if not self.comm.allreduce(bool(used), op=MPI.LOR):
                unused.append(k)
        self._clear_options()
        if unused:
            k = unused[0]
            raise GsiInputError(
                f"{self.options_key}.{k} = {self.user_options[k]!r}: PETSc did not use this "
                f"option (the {self.kind} solver: {self.describe()}); check its name in the "
                "PETSc manual")

    def _clear_options(self) -> None:
        opts = PETSc.Options()
        for k in self._db_keys:
            opts.delValue(k)
        self._db_keys = []

    def describe(self) -> str:
        """KSP and PC types, e.g. 'cg + gamg'."""
        return f"{self.ksp.getType()} + {self.ksp.getPC().getType()}"

    # ---------------------------------------------------------------- solving
    def factorize(self) -> None:
        """Build the preconditioner (factorization or multigrid hierarchy) once (collective)."""
        if self._ready:
            return
        t0 = time.perf_counter()
        try:
            self.ksp.setUp()
        except PETSc.Error as exc:
            if not self.user_options:
                raise
            self._clear_options()
            raise GsiInputError(f"{self.options_key}: PETSc could not set up the solver "
                                f"{self.describe()} with these options "
                                f"({', '.join(self.user_options)}): "
                                f"{compat.petsc_error_text(exc)}") from None
        self.factor_seconds += time.perf_counter() - t0
        self.n_factorizations += 1
        self._ready = True

    def solve(self, b: PETSc.Vec, x: PETSc.Vec) -> None:
        """x <- A^-1 b (collective). ``x`` holds the initial guess of the iterative solver."""
        self.factorize()
        first = not self.iterations
        reason, its = self._solve(b, x)
        self.iterations.append(its)
        if first and self._db_keys:
            self._check_used()
        if reason < 0:
            raise GsiRunError(self._failure(reason))

    def _solve(self, b, x) -> tuple[int, int]:
        """Solve; (PETSc converged reason, iterations)."""
        self.ksp.solve(b, x)
        return int(self.ksp.getConvergedReason()), int(self.ksp.getIterationNumber())

    def _failure(self, reason: int) -> str:
        return (f"FE linear solve failed (PETSc reason {reason}): check the supports "
                "(a free rigid-body mode makes K singular)")

    def destroy(self) -> None:
        self._clear_options()
        self.ksp.destroy()
