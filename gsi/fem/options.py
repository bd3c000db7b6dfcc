"""Choices of the FE linear solvers that need neither dolfinx nor PETSc (``gsi check``).

See :mod:`gsi.fem.solvers` for the solvers themselves.
"""
from __future__ import annotations

import math
import re

from gsi.errors import GsiInputError

__all__ = ["SOLVERS", "DIRECT_FACTORIZATION", "DIRECT_MUMPS_WORKSPACE", "ITERATIVE_RTOL",
           "ITERATIVE_ATOL", "AUTO_LARGE_DOFS", "AUTO_LARGE_SOLVER", "ITERATIVE_DEFAULTS",
           "ITERATIVE_PC", "OUT_OF_CORE_DEFAULTS", "BLR_EPSILON", "choose_solver",
           "direct_workspace", "iterative_defaults", "petsc_option_strings"]

#: ``direct``: the factor in memory; ``out_of_core``: a MUMPS Cholesky factor written to
#: disk (any number of ranks); ``iterative``: CG + algebraic multigrid; ``auto``: by size
SOLVERS = ("direct", "out_of_core", "iterative", "auto")

#: The one-rank MUMPS factorization of ``solver = "direct"`` when the problem is given none
#: (``factorization``): Cholesky (LDL^T) for elasticity, whose step matrices (K, or
#: c_M M + c_K K with Rayleigh damping, the Dirichlet rows and columns replaced by the
#: identity) are symmetric: half LU's work and factor. Measured by MUMPS itself
#: (benchmarks/shell_precond.py, 9.9e4-dof P2 silo shell, 2 ranks, load-independent
#: figures): LU 213.5 Gflop and 1.39e8 factor entries, Cholesky 113.2 Gflop and 7.1e7;
#: set-up 17.7 s against 11.0 s in the same run (load 12.7). MUMPS's orderings (METIS,
#: PORD, SCOTCH, its automatic choice) lie within 4 % of each other there, and its parallel
#: ordering is not available in this build (INFOG(1) = -38), so the ordering stays MUMPS's
#: own. Heat keeps LU. On several ranks ``direct`` is SuperLU_DIST LU (bit-reproducible).
DIRECT_FACTORIZATION = {"elasticity": "cholesky", "heat": "lu"}

#: ... with MUMPS's working space this many per cent above its estimate (ICNTL(14), its
#: default 20 %), by factorization: 50 % for Cholesky, whose symmetric-indefinite
#: factorization delays pivots: at 2.2e5 dofs (the same shell, 2 ranks) it ran short of
#: space with 20 % (INFOG(1) = -9, 1.4e6 entries missing) where LU passed.
DIRECT_MUMPS_WORKSPACE = {"cholesky": 50}


def direct_workspace(factorization: str, user_options) -> int | None:
    """MUMPS's ICNTL(14) for the one-rank direct solver: DIRECT_MUMPS_WORKSPACE's, or None
    (MUMPS's own) for LU and whenever the user gives PETSc options (they may choose another
    package, or ``mat_mumps_icntl_14`` themselves)."""
    return None if user_options else DIRECT_MUMPS_WORKSPACE.get(factorization)

#: Relative tolerance of the iterative solvers: the (unpreconditioned) residual must fall
#: to ITERATIVE_RTOL times the residual of the initial guess, ||b - A x|| <= ITERATIVE_RTOL
#: ||b - A x_0||. x_0 is the last solution (warm start), so the tolerance is relative to
#: what changes over the step, not to the whole state (a temperature of 300 K, a deflection
#: built up over the run): energy balances hold over the step. At 1e-12 every FE validation
#: case passes with the iterative solver to its own tolerance (1e-10 of ||b|| left the patch
#: test's 1e-10 exactness, the average-acceleration energy conservation to 1e-9 and the
#: thermal coupling's energy conservation to 1e-12 unmet).
ITERATIVE_RTOL = 1e-12

#: ... or to ITERATIVE_ATOL ||b||, the round-off of b itself, whichever is larger: a warm
#: start that already solves the system (a steady state, a repeated solve) is not iterated
#: far. (1e-14 is too large: the thermal coupling's step energy balance, the change of a
#: 300 K field over one step, then misses its 1e-12.)
ITERATIVE_ATOL = 1e-16

#: ``solver = "auto"`` takes AUTO_LARGE_SOLVER[problem] from this many global dofs on, and
#: the in-memory direct solver below. Measured on the project's 2-core test machine
#: (benchmarks/fe_scale.py, P2 silo shell, 2 ranks; the figures in its docstring): the
#: direct solver's time per step is 60-670 times below the iterative one's at every size
#: (elasticity: CG + GAMG needs 159-884 iterations on the 10 mm wall), but its factor in
#: memory passes the 8 GB a 2-rank run may use from about 2e5 dofs on (SuperLU_DIST: 4.9 GB
#: at 2e5; 12.4 GB for the 2.8e5-dof membrane of benchmarks/coupled_large.py). From there
#: elasticity keeps a direct solve with the factor on disk (``out_of_core``: MUMPS
#: Cholesky; 1e6 dofs on 2 ranks in less than 8 GB, see fe_scale.py) and heat takes CG +
#: BoomerAMG (9-13 iterations at every size). Re-measured with CG + BoomerAMG for
#: elasticity (1 rank, 1e4-2e5 dofs, shell and clamped plate; docs' performance page): the
#: direct step is still 59-223 times faster and the iterative path is cheaper in total only
#: for runs shorter than 0.2-3.6 steps, so the threshold stays. The block low-rank
#: Cholesky preset (BLR_EPSILON below) sets up faster than the exact factor from 2e5 dofs
#: on (1e6 dofs, 2 ranks, both factors on disk: 138 s against 253.5 s) but its step is
#: slower at every size (10.5 s against 5.50 s there), so it is cheaper in total only for
#: runs shorter than 23 steps at 1e6 dofs: ``auto`` keeps the exact factor.
AUTO_LARGE_DOFS = {"elasticity": 200_000, "heat": 200_000}
AUTO_LARGE_SOLVER = {"elasticity": "out_of_core", "heat": "iterative"}

#: gsi's PETSc defaults of the out-of-core direct solver (``petsc_options`` override them):
#: MUMPS Cholesky (the effective matrices of gsi's problems are symmetric positive
#: definite), METIS nested-dissection ordering, the factor
#: written to files in a directory of the solver's own under $MUMPS_OOC_TMPDIR (else the
#: system's temporary directory), removed with the solver or at exit (a killed run's
#: directory by the next out-of-core solver on that host).
OUT_OF_CORE_DEFAULTS = {"ksp_type": "preonly", "pc_type": "cholesky",
                        "pc_factor_mat_solver_type": "mumps", "mat_mumps_icntl_7": "5",
                        "mat_mumps_icntl_22": "1"}

_CG = {"ksp_type": "cg", "ksp_converged_use_initial_residual_norm": ""}
_GAMG = {"pc_type": "gamg", "pc_gamg_coarse_eq_limit": "1000",
         "mg_levels_ksp_type": "chebyshev", "mg_levels_pc_type": "jacobi",
         "mg_levels_esteig_ksp_type": "cg"}

#: ``petsc = { pc_type = "cholesky" }`` with ``solver = "iterative"`` (issue 33): CG
#: preconditioned by an approximate Cholesky factor, MUMPS's block low-rank (BLR)
#: factorization (Amestoy et al. 2015, "Improving multifrontal methods by means of block
#: low-rank representations"; MUMPS >= 5.1, here Debian's 5.5.1): ICNTL(35) = 2 (BLR in
#: the factorization and the solves, the factor kept compressed), CNTL(7) = BLR_EPSILON
#: (the compression tolerance: off-diagonal blocks of the fronts kept to this relative
#: accuracy), METIS ordering, 50 % working space (the Cholesky's, see
#: DIRECT_MUMPS_WORKSPACE), on any number of ranks. An inexact factor is a
#: preconditioner, so CG iterates to ``ksp_rtol`` 1e-10 (BDDC's tolerance, and for the
#: same reason: 1e-12 lies below these systems' round-off floor). PETSc 3.18 exposes
#: ICNTL(35), ICNTL(36), ICNTL(38) and CNTL(7), not ICNTL(37) (compression of the
#: contribution blocks, which would cut the active memory): checked with ``-help``.
#: Measured (benchmarks/fe_scale.py, one-layer P2 silo shell, 2 ranks; docs' performance
#: page, "Block low-rank Cholesky as the preconditioner"): epsilon 1e-2 breaks CG down
#: (the factor is no longer positive definite, PETSc reason -8), 1e-3 takes 10-11
#: iterations per step from 1e5 to 4e5 dofs, 1e-4 5 / 5 / 6 / 7 at 1e5 / 2e5 / 4e5 / 1e6
#: (growth 1.4, above issue 33's 1.3), 1e-5 4 at 1e5 and 4 at 998,280 dofs (growth 1.0),
#: hence 1e-5. At 998,280 dofs with the factor on disk, 1e-5 against 1e-4: set-up 138 s
#: against 123 s, step 10.5 s against 15.6 s, 9.0 against 8.2 GB (load 5-7); the
#: compressed factor costs 510 Gflop and 4.3e8 entries against the exact factor's
#: 3,735 Gflop and 1.03e9. ``mat_mumps_icntl_22 = 1`` puts the compressed factor on disk,
#: in a directory of the solver's own as ``out_of_core``'s (gsi.fem.solvers.FactorFiles):
#: with the elasticity's K and M assembled after the factorization, 4 iterations, 41.8 s
#: set-up, 3.12 s step, 7.36 GB at 998,280 dofs (2 ranks, idle host), within issue 33's
#: targets (the exact factor on disk: 88.6 s, 1.67 s, 5.12 GB).
BLR_EPSILON = 1e-5
_BLR = {"pc_type": "cholesky", "pc_factor_mat_solver_type": "mumps", "ksp_rtol": "1e-10",
        "mat_mumps_icntl_7": "5", "mat_mumps_icntl_14": "50", "mat_mumps_icntl_35": "2",
        "mat_mumps_cntl_7": repr(BLR_EPSILON)}

#: gsi's PETSc defaults of the iterative solvers, by ``<problem>_<pc_type>``
#: (``petsc_options`` override them; a user's ``pc_type`` selects the entry of that type).
#: Elasticity with BoomerAMG is its systems form (the matrix's block size 3 gives hypre
#: three functions, each coarsened on its own), HMIS coarsening, extended+i
#: interpolation, at most 4 weights per row, strong threshold 0.5 (benchmarks/
#: shell_precond.py's ``hypre_sys``); with GAMG, smoothed aggregation with the six
#: rigid-body modes as near-nullspace and Chebyshev/Jacobi smoothing.
ITERATIVE_DEFAULTS = {
    "elasticity_hypre": {**_CG, "pc_type": "hypre", "pc_hypre_type": "boomeramg",
                         "pc_hypre_boomeramg_coarsen_type": "HMIS",
                         "pc_hypre_boomeramg_interp_type": "ext+i",
                         "pc_hypre_boomeramg_strong_threshold": "0.5",
                         "pc_hypre_boomeramg_P_max": "4",
                         "pc_hypre_boomeramg_agg_nl": "0"},
    "elasticity_gamg": {**_CG, **_GAMG},
    "elasticity_bddc": {**_CG, "pc_type": "bddc", "ksp_rtol": "1e-10",
                        "pc_bddc_use_deluxe_scaling": "",
                        "pc_bddc_adaptive_threshold": "2",
                        "pc_bddc_neumann_pc_type": "lu",
                        "pc_bddc_neumann_pc_factor_mat_solver_type": "mumps",
                        "pc_bddc_dirichlet_pc_type": "lu",
                        "pc_bddc_dirichlet_pc_factor_mat_solver_type": "mumps",
                        "pc_bddc_coarse_redundant_pc_factor_mat_solver_type": "petsc"},
    "elasticity_cholesky": {**_CG, **_BLR},
    "heat_hypre": {**_CG, "pc_type": "hypre", "pc_hypre_type": "boomeramg"},
    "heat_cholesky": {**_CG, **_BLR},
    "heat_gamg": {**_CG, **_GAMG},
}

#: ``petsc_options = {pc_type = "bddc"}`` (elasticity only; issue 33): BDDC (Dohrmann 2003)
#: on the step matrix assembled unassembled (MATIS, one subdomain per rank), deluxe
#: scaling, PETSc's adaptive coarse space (threshold 2: the interface eigenvectors of the
#: generalized eigenproblems whose eigenvalues pass 2 join the coarse space), MUMPS for
#: the local solves, PETSc's own LU for the coarse one (MUMPS's LU of the coarse matrix
#: failed on a slender bar, PC reason FACTOR_OTHER, and its second solve with PETSc reason
#: -11; PETSc's LU of the same matrix solves it: tests/mpi/bddc_energy_mpi_case.py), the
#: six rigid-body modes as near-nullspace. Measured
#: (benchmarks/shell_precond.py, uniformly refined P2 silo shell, CG to 1e-10): 11-14
#: iterations from 4.9e3 to 9.9e4 dofs on 2, 4 and 8 subdomains. Its ``ksp_rtol`` is
#: 1e-10, not ITERATIVE_RTOL: 1e-12 lies below the round-off floor of these systems
#: (eps || |A| |x| || / ||b|| = 2e-11 on the 3.2e4-dof shell; the direct solution's own
#: residual is 1.4e-11 of ||b||), where BDDC's CG stagnates or stops on an "indefinite
#: preconditioner" (PETSc reason -8) while only round-off is left; at 1e-10 its answer
#: lies within 1.2e-12 of the direct one. On one rank it is a direct solve (one subdomain).
#:
#: The preconditioner of ``solver = "iterative"`` by problem (GAMG where PETSc has no
#: hypre; ``petsc_options = {pc_type = "gamg"}`` picks GAMG with its defaults above).
#: Measured (benchmarks/shell_precond.py, fe_scale.py; one generalized-alpha step, CG to
#: 1e-12): BoomerAMG (systems form) needs 3.5-7 times fewer iterations than GAMG with the
#: rigid-body modes on both the P2 silo shell and the clamped plate, and its step is
#: faster on one rank on both (see the docs' performance page for the figures).
ITERATIVE_PC = {"elasticity": "hypre", "heat": "hypre"}


def iterative_defaults(problem: str, pc_type: str | None, *, hypre: bool = True) -> dict[str, str]:
    """gsi's PETSc defaults of the iterative solver of ``problem`` with the preconditioner
    ``pc_type`` (None: :data:`ITERATIVE_PC`, GAMG without ``hypre``); a type gsi has no
    defaults for gets CG and that type only."""
    if pc_type is None:
        pc_type = ITERATIVE_PC[problem] if hypre else "gamg"
    return dict(ITERATIVE_DEFAULTS.get(f"{problem}_{pc_type}", {**_CG, "pc_type": pc_type}))


_KEY_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def choose_solver(solver: str, n_dofs: int, problem: str, *, key: str = "structure.solver") -> str:
    """The solver actually used: ``solver`` itself, or for "auto" ``AUTO_LARGE_SOLVER[problem]``
    from ``AUTO_LARGE_DOFS[problem]`` global dofs on ("elasticity" or "heat"), else direct."""
    if solver not in SOLVERS:
        raise GsiInputError(f"{key} = {solver!r}: must be one of {', '.join(map(repr, SOLVERS))}")
    if solver != "auto":
        return solver
    return AUTO_LARGE_SOLVER[problem] if n_dofs >= AUTO_LARGE_DOFS[problem] else "direct"


def petsc_option_strings(options, key: str = "structure.petsc") -> dict[str, str]:
    """Check the form of PETSc pass-through options and turn the values into PETSc's strings.

    Keys are option names without the leading dash (letters, digits, '_'); values are
    numbers, strings or booleans (a flag: ``ksp_monitor = true``).
    """
    if options is None:
        return {}
    if not isinstance(options, dict):
        raise GsiInputError(f"{key} = {options!r}: must be a table of PETSc options, e.g. "
                            "{ ksp_rtol = 1e-10 }")
    out = {}
    for k, v in options.items():
        if not isinstance(k, str) or not _KEY_RE.match(k):
            raise GsiInputError(f"{key}.{k}: not a PETSc option name; write it without the "
                                "leading '-' (letters, digits and '_', e.g. ksp_rtol)")
        if isinstance(v, bool):
            out[k] = "" if v else "false"       # a flag: present without a value
        elif isinstance(v, int):
            out[k] = str(v)
        elif isinstance(v, float):
            if not math.isfinite(v):
                raise GsiInputError(f"{key}.{k} = {v!r}: must be finite")
            out[k] = repr(v)
        elif isinstance(v, str) and v and not any(c.isspace() for c in v):
            out[k] = v
        else:
            raise GsiInputError(f"{key}.{k} = {v!r}: must be a number, a word or true/false")
    return out


