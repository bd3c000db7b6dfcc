"""Benchmark: preconditioners of the dynamic elasticity matrix of thin P2 walls (issue 33).

For two thin structures, the P2 silo shell of benchmarks/fe_scale.py (``shell`` builder:
radius 0.5 m, 10 mm steel wall, ``--n-thickness`` element layers, clamped at the outlet
rim) and the clamped circular plate of the validation case 6b (``membrane`` builder,
radius 0.5 m, 20 mm steel, two layers, clamped rim), at ``--sizes`` sizes from
``--min-dofs`` to ``--max-dofs`` (geometric), this script assembles the matrix gsi solves
every generalized-alpha step (:class:`gsi.fem.elasticity.Elasticity`, rho_inf = 0.3,
dt = T_1 / 20: 1.25e-4 s for the shell as fe_scale.py, 2.5e-4 s for the plate, whose
first period is about 5 ms) and solves the first step from rest with each candidate:
conjugate gradients from x_0 = 0 (gsi's warm start from a structure at rest) until the
unpreconditioned residual falls to 1e-12 of the initial one, ||b - A x|| <= 1e-12 ||b||
(gsi's stopping rule, :data:`gsi.fem.options.ITERATIVE_RTOL`), with at most
``--max-its`` iterations. The right-hand side is that of the step: self-weight and
nodal loads on the contact surface, times (1 - alpha_f), Dirichlet rows zeroed.

Candidates (``--candidates``, PETSc 3.18 / hypre as Debian 12 builds them):

* ``gamg``: GAMG smoothed aggregation with the six rigid-body modes as its
  near-nullspace, Chebyshev/Jacobi smoothing (gsi's ``pc_type = "gamg"``,
  :data:`gsi.fem.options.ITERATIVE_DEFAULTS`; its iterative default before issue 33);
* ``gamg_sor``: the same with an SOR smoother under Chebyshev (a cheap GAMG variant);
* ``hypre_sys``: gsi's iterative default for elasticity now: BoomerAMG, systems form ("unknown" approach: the 3 components coarsened
  separately, the matrix's block size 3 gives hypre its number of functions), HMIS
  coarsening, extended+i interpolation, strong threshold 0.5;
* ``hypre_nodal``: BoomerAMG, nodal form: nodes coarsened together
  (``pc_hypre_boomeramg_nodal_coarsen 6``: the sum of the 3x3 block entries' absolute
  values as the node-to-node strength) with the rigid-body rotations as interpolation
  vectors (the near-nullspace of the matrix, ``pc_hypre_boomeramg_vec_interp_variant 2``:
  Gauss-Seidel's GM-2 variant of Baker, Kolev & Yang 2010, up to 4 interpolation
  weights per point after ``vec_interp_qmax``);
* ``hypre_nodal_t07``: the same with a strong threshold of 0.7 (of 0.25, 0.5, 0.7, 0.8
  and 0.9 the best on the shell at 1e4 dofs: 110 iterations against 146 at 0.5; the
  Frobenius-norm nodal strength, ``nodal_coarsen 1``, needed 335; all six rigid-body
  modes as interpolation vectors 139 at twice the cost per iteration; the GM-1 variant
  201; no interpolation vectors 226);
* ``bjacobi_lu``: block Jacobi with a MUMPS Cholesky solve of each rank's diagonal block
  (on 1 rank: a direct solve, 1 iteration; the baseline of the domain-decomposition
  family);
* ``bddc``: PCBDDC on a MATIS matrix, if ``--bddc`` is given (see below);
* ``bddc_deluxe``: the same with deluxe scaling (``pc_bddc_use_deluxe_scaling``: the
  interface averaged with the subdomains' Schur complements instead of their diagonal),
  named in ``--candidates``;
* ``direct`` (MUMPS LU) and ``direct_chol``, ``direct_chol_metis``, ``_pord``,
  ``_scotch``, ``_ptscotch``, ``_parmetis``, ``_ws50`` (MUMPS Cholesky with its automatic
  ordering, METIS, PORD, SCOTCH, the parallel orderings, 50 % working space): the direct
  baselines; each prints MUMPS's own flop count (RINFOG(3)) and factor entries
  (INFOG(29)), which the load does not change, and INFOG(1, 2) (its error code);
* ``pmg_gamg``: p-multigrid, PCMG on two levels: the P2 space smoothed by two
  Chebyshev/Jacobi sweeps, the P1 space (the interpolation P1 -> P2 of dolfinx 0.5.2's
  ``interpolation_matrix`` as prolongation, the Galerkin operator P^T A P) by one GAMG
  cycle with the P1 space's rigid-body modes as near-nullspace.

BDDC needs the matrix unassembled (MATIS: one matrix per rank, the sum of its cells'
element matrices). dolfinx 0.5.2 accepts ``create_matrix(a, "is")`` but returns a MATIS
whose local matrix has no preallocation: its C++ ``la::petsc::create_matrix`` calls
``MatXAIJSetPreallocation`` before ``MatSetLocalToGlobalMapping`` (which is when MATIS
creates its local matrix), so the preallocation goes nowhere and the first
``zeroEntries``/assembly segfaults (measured here on a 4^3 box, 1 and 2 ranks). The
script therefore preallocates the local matrix itself, from the cell-to-dof map, before
assembling into it with dolfinx, and puts a 1 on the local diagonal of the Dirichlet dofs
a rank shares but does not own (dolfinx sets the owner's only; an empty row makes the
local Neumann problem singular: "Matrix is missing diagonal entry"), and restricts each
subdomain to the dofs of the cells its rank owns (dolfinx's local space also holds the
dofs of ghost cells, left empty by the assembly). On 1 rank BDDC has
one subdomain and is a direct solve; on 2, two subdomains, which says nothing yet about
its growth with the number of subdomains.

With ``--uniform`` the sizes are not taken at ``--max-dofs`` but refined uniformly from
the ``--min-dofs`` mesh: L_0 + i element layers through the wall and in-plane size
h_0 L_0 / (L_0 + i) at the i-th size (L_0 = 1 for the shell, 2 for the plate), so every
element keeps its shape (aspect ratio) and only the mesh size changes: the test of an
iteration count independent of the mesh. Without it the wall keeps its layers while h
falls, the elements become less flat and every method's iterations fall with the
dofs (the aspect-ratio effect fe_scale.py's docstring reports for GAMG).

For each (structure, size, candidate) it prints ``iterations``, ``setup_s`` (the
preconditioner's set-up) and ``solve_s`` (the CG solve), the iterations at which CG's
(recursive) residual first fell to 1e-8 and 1e-10 of the initial one, the rate (mean residual
reduction per iteration) and checks the solution against the first candidate's
(relative difference). The last line is machine-readable key=value: for each candidate
``its_<c>_<structure>`` (iterations at the largest size), ``growth_<c>_<structure>``
(iterations at the largest size over those at the smallest), and ``best`` (the candidate
whose shell iterations grow least among those that converged at every size,
bjacobi_lu and bddc excepted on 1 rank: they are direct solves there), ``its_at_max``,
``its_growth``, ``dofs_max``, ``ranks``, ``gflop_<c>_<structure>`` for the MUMPS
candidates, ``blas`` (the BLAS MUMPS ran on: :func:`gsi.fem.compat.blas_library`), the
load average at the start and the end. Every set-up and solve is a PETSc log stage of its
own (``<candidate>_<dofs>_setup``/``_solve``): with ``PETSC_OPTIONS=-log_view`` PETSc
breaks each down by event. ``--skip-sizes N`` builds the first N sizes' meshes but solves
only the larger ones (with ``--uniform``: refined from the same first mesh).

Measured (2026-12-04, the 2-core test host loaded by other jobs, load 6-10: times are
several times an idle host's, iteration counts are not affected; the records and their
notes are in benchmarks/results/shell_precond.json). CG iterations to 1e-12, one
generalized-alpha step from rest:

=====================  ==========================  ==========================
candidate              shell, uniform refinement   plate, uniform refinement
                       4.9e3 / 3.2e4 / 9.9e4 dofs  1.1e4 / 3.2e4 / 7.1e4 dofs
=====================  ==========================  ==========================
gamg (gsi today)       894 / 1468 / 1721           433 / 518 / 480
hypre_sys              229 / 413 / 500             68 / 77 / 70
hypre_nodal            166 / 265 / 302             61 / 65 / 68
hypre_nodal_t07        136 / 292 / 407             59 / 70 / 74
pmg_gamg               675 / 1024 / 1237           406 / 347 / 334
=====================  ==========================  ==========================

* No candidate has an iteration count independent of the mesh on the shell: refined
  uniformly (element shapes kept) every count grows by 1.8-3.0 times over 20 times the
  dofs, GAMG's by 1.93. On the plate (a / t = 25, thicker than the shell's R / t = 50)
  every count is flat within 25 %.
* BoomerAMG (either form) needs 3.5-7 times fewer iterations than GAMG on both
  structures, but on the shell each costs 8 times more (its hierarchy on the P2 matrix:
  operator complexity 3.3 on the 1e4 shell, with HMIS and extended+i interpolation).
  Measured on the quiet host (2 ranks, load 2-3, uniform 3.2e4 dofs): per step GAMG
  8.0 s, systems 19.0 s, nodal t0.7 44.7 s on the shell; on the plate BoomerAMG's
  iterations cost about GAMG's and it is 5-8 times faster per step (3.2e4: systems 1.55 s,
  nodal 2.5 s, GAMG 12.8 s). Re-run 2026-12-05 at one load (6.5-7.4, 2 ranks, uniform
  3.2e4 shell): GAMG 1,471 its in 1.1 + 76.3 s, systems 425 its in 0.4 + 49.6 s: the
  8-times cost per iteration and GAMG's lead above were not reproduced (a BoomerAMG
  iteration cost 2.2 times a GAMG one; 2.1-2.3 times in CPU time on the one-layer shell).
* p-multigrid (GAMG under a P2 -> P1 level) saves a quarter to a third of GAMG's
  iterations with the same growth; on the quiet host its step costs 3 times GAMG's on the
  shell (23.8 s against 8.0 s) and half of it on the plate.
* Without ``--uniform`` (the wall keeps its layers while h falls) every count on the
  shell falls with the dofs (GAMG 851 / 727 / 548 at 1e4 / 3e4 / 1e5), as fe_scale.py
  measured: the elements become less flat.
* 2 ranks (1e4 / 3e4 dofs, fixed layers): the counts are those of 1 rank within 10 %
  (GAMG 881 / 737 on the shell), except GAMG's on the 1e4 plate (551 against 433); block Jacobi with a Cholesky factor per rank, no coarse
  space, needs 1185 / 1152. BDDC on two subdomains reaches 1e-10 in 140 / 96 (shell) and
  70 / 57 (plate) iterations, then stalls above 1e-12 (600 iterations; PETSc reports an
  indefinite preconditioner on the 3e4 shell): with gsi's 1e-12 it does not converge, and
  two subdomains cannot show its growth with their number. On the uniformly refined
  shell its 1e-8 count grows from 110 to 285 (4.9e3 -> 3.2e4 dofs), BoomerAMG nodal's
  from 110 to 169.
* BDDC with deluxe scaling (2026-12-05, uniformly refined shell, 4.9e3 / 3.2e4 dofs, CG
  iterations to 1e-8 of the initial residual; each rank a subdomain, 4 and 8 ranks
  oversubscribed on the 2 cores, which leaves the counts alone): 2 subdomains 12 / 19
  (plain BDDC 110 / 285, BoomerAMG systems 153 / 276), 4 subdomains 29 / 21,
  8 subdomains 83 / 178. With few subdomains it is the best preconditioner measured
  here (3.2e4, 2 ranks, load 10: set-up 10.3 s + solve 4.6 s against BoomerAMG's 1.0 s +
  92.5 s), but its count grows with the number of subdomains (PETSc's default coarse
  space: subdomain vertices and edge/face averages), so it does not yet scale; and like
  plain BDDC it breaks down (PETSc reason -8, indefinite preconditioner) at 2e-12 to
  3e-11 of the initial residual, short of gsi's 1e-12. Not tried: an adaptive coarse
  space (``pc_bddc_adaptive_threshold``), which targets this growth.
* BDDC made robust (2026-12-05, issue 33's third step; uniformly refined shell, CG to
  ``--rtol 1e-10``; ``bddc_mumps``: deluxe scaling and MUMPS for the Neumann, Dirichlet
  and coarse solves; ``bddc_adaptN``: the same with PETSc's adaptive coarse space,
  ``pc_bddc_adaptive_threshold N``; 4 and 8 ranks oversubscribed, counts only):

  ============  ===========================  ===========================
  subdomains    bddc_mumps (default coarse)  bddc_adapt2
                4.9e3 / 3.2e4 / 9.9e4 dofs   4.9e3 / 3.2e4 / 9.9e4 dofs
  ============  ===========================  ===========================
  2             15 / 24 / 28                 11 / 11 / 12
  4             38 / 28 / 104                13 / 13 / 13
  8             116 / 253 / 314              14 / 14 / 14
  8, 2.2e5     -                            14 (set-up 269 s, solve 3.8 s)
  ============  ===========================  ===========================

  (8 subdomains, 3.2e4: an earlier run gave 255 for the default coarse space.) With
  8 subdomains at 9.9e4 the adaptive set-up took 38.1 s and its solve 3.9 s against the
  default coarse space's 21.4 s + 76.7 s (oversubscribed, load 9). Through gsi itself
  (``benchmarks/fe_scale.py --petsc '{"pc_type": "bddc"}'``, 2 ranks, fixed one-layer
  shell, one step): 11 / 13 iterations at 9.9e3 / 3.0e4 dofs, set-up 12.9 s and step
  2.6 s at 3.0e4 (load 9).
  8 subdomains at 3.2e4: threshold 5 23, threshold 10 27, ``pc_bddc_use_faces`` 193
  iterations. The cause of the "breakdown": the tolerance, not BDDC. 1e-12 of ||b|| is
  below these systems' round-off floor (the 3.2e4 shell: eps || |A| |x| || / ||b|| =
  2.0e-11; the MUMPS direct solution's own residual 1.4e-11 of ||b||), so CG's last
  iterations work on round-off: with PETSc's own LU in the local solves it stops on
  reason -8 (indefinite preconditioner), with MUMPS it stagnates at 1.6e-11 (600
  iterations). At 1e-10 every BDDC solution lies within 1.2e-12 (3.2e4) and 4.8e-12
  (9.9e4) of the direct one. Times at 2 ranks (load 5-9): 9.9e4 dofs, bddc_adapt2
  set-up 276 s + solve 8.1 s, bddc_mumps 120 s + 12.8 s, MUMPS direct 91.6 s + 0.36 s:
  the adaptive coarse space's dense interface eigenproblems dominate with 2 large
  subdomains; with 4 (oversubscribed, load 6-9) its set-up at 9.9e4 fell to 40.6 s.
* GAMG with an SOR smoother under Chebyshev fails from 3e4 dofs on (the preconditioner's
  Chebyshev eigenvalue estimate breaks down: PETSc reason -11).

Run::

    nice -n 10 python benchmarks/shell_precond.py --min-dofs 1e4 --max-dofs 1e5 --sizes 3
    nice -n 10 python benchmarks/shell_precond.py --uniform --structures shell --min-dofs 5e3 \
        --sizes 3 --candidates gamg,hypre_sys,hypre_nodal,hypre_nodal_t07,pmg_gamg
    nice -n 10 python benchmarks/shell_precond.py --uniform --structures plate --min-dofs 1e4 \
        --sizes 3 --candidates gamg,hypre_sys,hypre_nodal,hypre_nodal_t07,pmg_gamg
    mpirun -n 2 python benchmarks/shell_precond.py --min-dofs 1e4 --max-dofs 3e4 --sizes 2 \
        --candidates hypre_nodal_t07 --bddc --max-its 600
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout too

from gsi import meshes  # noqa: E402
from gsi.fem import compat  # noqa: E402
from gsi.fem.elasticity import Elasticity  # noqa: E402
from gsi.fem.materials import StructuralMaterial  # noqa: E402
from gsi.fem.options import ITERATIVE_DEFAULTS, ITERATIVE_RTOL  # noqa: E402
from gsi.fem.solvers import rigid_body_modes  # noqa: E402
from gsi.fem.surface import ContactSurface  # noqa: E402
from gsi.meshes import shell  # noqa: E402

RHO_INF = 0.3
_HYPRE_COMMON = {"pc_type": "hypre", "pc_hypre_type": "boomeramg",
                 "pc_hypre_boomeramg_coarsen_type": "HMIS",
                 "pc_hypre_boomeramg_interp_type": "ext+i",
                 "pc_hypre_boomeramg_strong_threshold": "0.5",
                 "pc_hypre_boomeramg_P_max": "4",
                 "pc_hypre_boomeramg_agg_nl": "0"}
#: BDDC with deluxe scaling and every local solve (Neumann, Dirichlet, the coarse problem)
#: a MUMPS factorization (PETSc's own LU is the default of the first two)
_BDDC_MUMPS = {"pc_type": "bddc", "pc_bddc_use_deluxe_scaling": "",
               "pc_bddc_neumann_pc_type": "lu",
               "pc_bddc_neumann_pc_factor_mat_solver_type": "mumps",
               "pc_bddc_dirichlet_pc_type": "lu",
               "pc_bddc_dirichlet_pc_factor_mat_solver_type": "mumps",
               "pc_bddc_coarse_redundant_pc_factor_mat_solver_type": "mumps"}
CANDIDATES = {
    "gamg": dict(ITERATIVE_DEFAULTS["elasticity_gamg"]),
    "gamg_sor": dict(ITERATIVE_DEFAULTS["elasticity_gamg"], mg_levels_pc_type="sor"),
    "hypre_sys": dict(_HYPRE_COMMON),
    "hypre_nodal": dict(_HYPRE_COMMON, pc_hypre_boomeramg_nodal_coarsen="6",
                        pc_hypre_boomeramg_vec_interp_variant="2",
                        pc_hypre_boomeramg_vec_interp_qmax="4"),
    "hypre_nodal_t07": dict(_HYPRE_COMMON, pc_hypre_boomeramg_nodal_coarsen="6",
                            pc_hypre_boomeramg_vec_interp_variant="2",
                            pc_hypre_boomeramg_vec_interp_qmax="4",
                            pc_hypre_boomeramg_strong_threshold="0.7"),
    "bjacobi_lu": {"pc_type": "bjacobi", "sub_pc_type": "cholesky",
                   "sub_pc_factor_mat_solver_type": "mumps"},
    "direct": {"ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"},
    # MUMPS variants (issue 33): Cholesky; its orderings METIS (ICNTL(7) = 5), PORD (4),
    # SCOTCH (3); parallel ordering (ICNTL(28) = 2) by PT-SCOTCH (ICNTL(29) = 1) or ParMETIS (2)
    **{f"direct_chol{sfx}": {"ksp_type": "preonly", "pc_type": "cholesky",
                             "pc_factor_mat_solver_type": "mumps", **extra}
       for sfx, extra in (("", {}), ("_metis", {"mat_mumps_icntl_7": "5"}),
                          ("_pord", {"mat_mumps_icntl_7": "4"}),
                          ("_scotch", {"mat_mumps_icntl_7": "3"}),
                          ("_ptscotch", {"mat_mumps_icntl_28": "2", "mat_mumps_icntl_29": "1"}),
                          ("_parmetis", {"mat_mumps_icntl_28": "2", "mat_mumps_icntl_29": "2"}),
                          # 50 % more workspace than MUMPS's estimate (its default: 20 %)
                          ("_ws50", {"mat_mumps_icntl_14": "50"}))},
    "bddc": {"pc_type": "bddc"},
    "bddc_deluxe": {"pc_type": "bddc", "pc_bddc_use_deluxe_scaling": ""},
    "bddc_mumps": dict(_BDDC_MUMPS),
    "bddc_adapt2": dict(_BDDC_MUMPS, pc_bddc_adaptive_threshold="2"),
    "bddc_adapt5": dict(_BDDC_MUMPS, pc_bddc_adaptive_threshold="5"),
    "bddc_adapt10": dict(_BDDC_MUMPS, pc_bddc_adaptive_threshold="10"),
    "bddc_faces": dict(_BDDC_MUMPS, pc_bddc_use_faces=""),
    "bddc_nonnsp": dict(_BDDC_MUMPS, pc_bddc_use_nnsp="false"),
    "pmg_gamg": {"pc_type": "mg", "pc_mg_levels": "2", "pc_mg_galerkin": "none",
                 "mg_levels_ksp_type": "chebyshev", "mg_levels_pc_type": "jacobi",
                 "mg_levels_esteig_ksp_type": "cg", "mg_levels_ksp_max_it": "2",
                 "mg_coarse_ksp_type": "preonly", "mg_coarse_pc_type": "gamg",
                 "mg_coarse_pc_gamg_coarse_eq_limit": "1000",
                 "mg_coarse_mg_levels_ksp_type": "chebyshev",
                 "mg_coarse_mg_levels_pc_type": "jacobi",
                 "mg_coarse_mg_levels_esteig_ksp_type": "cg"},
}
#: the near-nullspace each candidate gets: all six rigid-body modes (GAMG, BDDC), the three
#: rotations only (hypre's interpolation vectors: the translations are the per-function
#: constants its interpolation reproduces already) or none
NULLSPACE = {"gamg": "rbm", "gamg_sor": "rbm", "hypre_nodal": "rotations",
             "hypre_nodal_t07": "rotations", "bddc": "rbm", "bddc_deluxe": "rbm",
             **{c: "rbm" for c in ("bddc_mumps", "bddc_adapt2", "bddc_adapt5",
                                   "bddc_adapt10", "bddc_faces", "bddc_nonnsp")}}


#: options added to every bddc candidate (``--bddc-set``)
BDDC_EXTRA: dict[str, str] = {}


def load_average() -> float:
    return os.getloadavg()[0]


def build_shell(target: float, n_thickness: int, h: float | None = None):
    if h is None:
        h = shell.h_for_dofs(target, n_thickness=n_thickness, components=3)
    return meshes.build("shell", h=h, n_thickness=n_thickness), h, 1.25e-4


def build_plate(target: float, n_thickness: int, h: float | None = None):
    if h is None:
        # 23.7k dofs at h = a / 10 with two layers (the validation case's mesh)
        h = 0.05 * math.sqrt(23.7e3 / target)
    return meshes.build("membrane", shape="circle", radius=0.5, thickness=0.02, h=h,
                        n_thickness=n_thickness), h, 2.5e-4


#: element layers through the wall of the first size (``--uniform`` adds one per size)
BASE_LAYERS = {"shell": 1, "plate": 2}


def meshes_of(structure: str, targets, n_thickness: int, uniform: bool):
    """(mesh, h, dt) of each size: at ``targets`` dofs with a fixed number of layers, or
    (``uniform``) refined uniformly from the first target's mesh: L_0 + i layers through
    the wall and h_0 L_0 / (L_0 + i) in-plane, so every element keeps its shape."""
    builder = build_shell if structure == "shell" else build_plate
    layers = n_thickness if structure == "shell" else BASE_LAYERS["plate"]
    if not uniform:
        for target in targets:
            yield builder(target, layers)
        return
    _, h0, _ = builder(targets[0], layers)
    for i in range(len(targets)):
        yield builder(0.0, layers + i, h=h0 * layers / (layers + i))


def step_system(sm, dt: float):
    """(problem, A, b): gsi's generalized-alpha matrix and the right-hand side of the
    first step from rest under self-weight and contact-surface nodal loads."""
    comm = MPI.COMM_WORLD
    mat = StructuralMaterial(E=200e9, nu=0.3, rho=7800.0)
    # a trivial preconditioner: the set-up assembles the matrix without building GAMG
    p = Elasticity(sm, mat, degree=2, scheme="generalized_alpha", dt=dt, rho_inf=RHO_INF,
                   gravity=(0.0, 0.0, -9.81), solver="iterative",
                   petsc_options={"pc_type": "jacobi"})
    p.clamp("support")
    s = ContactSurface(elasticity=p)
    x = s.x0 if comm.rank == 0 else np.zeros((0, 3))
    loads = np.c_[0.2 * np.sin(6.0 * x[:, 2]), 0.2 * np.cos(5.0 * x[:, 0]), -1.0 - x[:, 1] ** 2]
    s.add_nodal_loads(loads if comm.rank == 0 else None)
    p.set_up()
    A = p.linear_solver.A
    b = A.createVecLeft()
    p.load_vector().copy(b)
    b.scale(1.0 - p.params["alpha_f"])
    compat.set_bc(b, p.bcs)
    return p, A, b


def near_nullspace(p, A, kind):
    if kind is None:
        return None
    nsp = rigid_body_modes(p.V, A)
    if kind == "rbm":
        return nsp
    vecs = [v.copy() for v in nsp.getVecs()[3:]]
    return PETSc.NullSpace().create(vectors=vecs, comm=A.getComm())


def matis_matrix(p):
    """The step matrix of ``p`` assembled unassembled (MATIS) for BDDC
    (:func:`gsi.fem.compat.assemble_matis`, gsi's own ``pc_type = "bddc"`` path)."""
    import ufl
    from gsi.fem.elasticity import epsilon, sigma_mech
    m = p.material
    u, w = ufl.TrialFunction(p.V), ufl.TestFunction(p.V)
    dx = compat.measure("dx", p.mesh)
    c_M, c_K = p.newmark.matrix_weights()
    a = compat.form(c_M * m.rho * ufl.inner(u, w) * dx
                    + c_K * ufl.inner(sigma_mech(u, m.mu, m.lmbda), epsilon(w)) * dx)
    return compat.assemble_matis(a, p.bcs, p.V)


def p_multigrid(ksp, p, A):
    """Make ``ksp``'s PCMG a P2 -> P1 two-level method: the P1 -> P2 interpolation of the
    vector spaces as its prolongation, the P1 Galerkin operator P^T A P (formed here)
    solved by one GAMG cycle with the P1 space's rigid-body modes. Returns the P1
    operator (destroyed by the caller)."""
    import dolfinx.cpp.fem.petsc as cpp_petsc
    V1 = compat.vector_space(p.mesh, 1)
    P = cpp_petsc.interpolation_matrix(V1._cpp_object, p.V._cpp_object)
    P.assemble()
    pc = ksp.getPC()
    pc.setMGInterpolation(1, P)
    Ac = A.PtAP(P)
    Ac.setBlockSize(3)
    Ac.setNearNullSpace(rigid_body_modes(V1, Ac))
    pc.getMGCoarseSolve().setOperators(Ac)
    P.destroy()
    return Ac


def run_candidate(name, p, A, b, x_ref, max_its, comm, rtol=ITERATIVE_RTOL):
    opts = PETSc.Options()
    prefix = f"sp_{name}_"
    settings = dict(CANDIDATES[name])
    if name.startswith("bddc"):
        settings.update(BDDC_EXTRA)
    # a copy of its own: the near-nullspace attached to the matrix is the candidate's
    op = matis_matrix(p) if name.startswith("bddc") else A.duplicate(copy=True)
    nsp = near_nullspace(p, op, NULLSPACE.get(name))
    if nsp is not None:
        op.setNearNullSpace(nsp)
    ksp = PETSc.KSP().create(comm)
    ksp.setOptionsPrefix(prefix)
    for k, v in settings.items():
        opts[prefix + k] = v
    ksp.setOperators(op)
    ksp.setTolerances(rtol=rtol, atol=0.0, max_it=max_its)
    ksp.setNormType(PETSc.KSP.NormType.UNPRECONDITIONED)
    ksp.setType("cg")
    ksp.setFromOptions()
    coarse_op = p_multigrid(ksp, p, op) if name.startswith("pmg") else None
    ksp.setConvergenceHistory(length=max_its + 1, reset=True)
    x = b.duplicate()
    x.set(0.0)
    comm.barrier()
    # a PETSc log stage per set-up and per solve: ``-log_view`` (e.g. in $PETSC_OPTIONS)
    # then breaks each down by event (factorizations, BDDC's Schur complements, ...)
    stage = PETSc.Log.Stage(f"{name}_{p.n_dofs}_setup")
    stage.push()
    t0 = time.perf_counter()
    ok = True
    try:
        ksp.setUp()
        ksp.setUpOnBlocks()          # block Jacobi/ASM factor their blocks here, not in the solve
    except PETSc.Error as exc:
        ok = False
        err = compat.petsc_error_text(exc)
    comm.barrier()
    t_setup = time.perf_counter() - t0
    stage.pop()
    out = dict(candidate=name, setup_s=t_setup)
    if ok and settings.get("pc_factor_mat_solver_type") == "mumps":
        # MUMPS's own statistics, independent of the host's load: the factorization's
        # floating-point operations (RINFOG(3)) and the factor's entries (INFOG(29))
        F = ksp.getPC().getFactorMatrix()
        out.update(gflop=F.getMumpsRinfog(3) / 1e9, factor_entries=F.getMumpsInfog(29),
                   mumps_infog1=F.getMumpsInfog(1), mumps_infog2=F.getMumpsInfog(2))
    if not ok:
        out.update(its=-1, solve_s=float("nan"), reason=0, rate=float("nan"), err=err)
    else:
        stage = PETSc.Log.Stage(f"{name}_{p.n_dofs}_solve")
        stage.push()
        t0 = time.perf_counter()
        ksp.solve(b, x)
        comm.barrier()
        stage.pop()
        its = ksp.getIterationNumber()
        r = b.duplicate()
        A.mult(x, r)
        r.aypx(-1.0, b)
        rel = r.norm() / b.norm()
        out.update(its=its, solve_s=time.perf_counter() - t0, reason=int(ksp.getConvergedReason()),
                   rate=rel ** (1.0 / max(its, 1)), res=rel)
        hist = np.asarray(ksp.getConvergenceHistory())
        for tol in (1e-8, 1e-10):
            hit = np.flatnonzero(hist <= tol * hist[0]) if hist.size else []
            # a solve converged before the history shows it (a direct solve: 1 iteration)
            out[f"its_{tol:.0e}"] = int(hit[0]) if len(hit) else (its if out["reason"] > 0 else -1)
        if x_ref is not None:
            d = x.copy()
            d.axpy(-1.0, x_ref)
            out["diff"] = d.norm() / x_ref.norm()
        out["x"] = x
    for k in settings:
        opts.delValue(prefix + k)
    ksp.destroy()
    op.destroy()
    if coarse_op is not None:
        coarse_op.destroy()
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--min-dofs", type=float, default=1e4)
    ap.add_argument("--max-dofs", type=float, default=1e5)
    ap.add_argument("--sizes", type=int, default=3)
    ap.add_argument("--structures", default="shell,plate")
    ap.add_argument("--candidates", default="gamg,gamg_sor,hypre_sys,hypre_nodal,bjacobi_lu")
    ap.add_argument("--bddc", action="store_true", help="add PCBDDC on a MATIS matrix")
    ap.add_argument("--n-thickness", type=int, default=1, help="element layers of the shell wall")
    ap.add_argument("--uniform", action="store_true",
                    help="refine uniformly from the --min-dofs mesh (one more element layer "
                         "through the wall per size, h scaled alike); --max-dofs unused")
    ap.add_argument("--skip-sizes", type=int, default=0,
                    help="build but do not solve the first N sizes (with --uniform: the "
                    "larger sizes alone, refined from the same first mesh)")
    ap.add_argument("--max-its", type=int, default=3000)
    ap.add_argument("--rtol", type=float, default=ITERATIVE_RTOL,
                    help="CG's relative tolerance (default gsi's ITERATIVE_RTOL)")
    ap.add_argument("--bddc-set", default="",
                    help="extra PETSc options of every bddc candidate: k=v,k=v (k without "
                         "the dash; 'k=' a flag)")
    ap.add_argument("--bjacobi-max-dofs", type=float, default=1.1e5,
                    help="skip bjacobi_lu above this size (a factor per rank)")
    args = ap.parse_args()
    comm = MPI.COMM_WORLD
    BDDC_EXTRA.update(kv.split("=", 1) for kv in args.bddc_set.split(",") if kv)
    load0 = load_average()
    cands = [c for c in args.candidates.split(",") if c] + (["bddc"] if args.bddc else [])
    structures = [s for s in args.structures.split(",") if s]
    targets = np.geomspace(args.min_dofs, args.max_dofs, args.sizes)
    rows = []
    for st in structures:
        for i, (sm, h, dt) in enumerate(meshes_of(st, targets, args.n_thickness, args.uniform)):
            if i < args.skip_sizes:
                continue
            p, A, b = step_system(sm, dt)
            x_ref = None
            for c in cands:
                if c == "bjacobi_lu" and p.n_dofs > args.bjacobi_max_dofs:
                    continue
                r = run_candidate(c, p, A, b, x_ref, args.max_its, comm, args.rtol)
                if x_ref is None and r.get("reason", -1) > 0:
                    x_ref = r["x"]
                r.pop("x", None)
                r.update(structure=st, dofs=p.n_dofs, h=h, ranks=comm.size)
                rows.append(r)
                if comm.rank == 0:
                    print(f"{st:5s} dofs={r['dofs']:7d} {c:12s} its={r['its']:5d} "
                          f"reason={r['reason']:3d} setup={r['setup_s']:7.2f}s "
                          f"solve={r['solve_s']:8.2f}s rate={r['rate']:.3f} "
                          f"res={r.get('res', float('nan')):.1e} "
                          f"diff={r.get('diff', float('nan')):.1e} "
                          f"its_1e-8={r.get('its_1e-08', -1)} its_1e-10={r.get('its_1e-10', -1)} "
                          + (f"gflop={r['gflop']:.1f} factor_entries={r['factor_entries']} "
                             f"INFOG(1,2)={r['mumps_infog1']},{r['mumps_infog2']} "
                             if "gflop" in r else "")
                          + f"load={load_average():.1f}"
                          + (f" error: {r['err']}" if "err" in r else ""), flush=True)
            p.linear_solver.destroy()
            del p, A, b, sm
    if comm.rank != 0:
        return
    kv = [f"ranks={comm.size}"]
    growth = {}
    for st in structures:
        for c in cands:
            rs = sorted((r for r in rows if r["structure"] == st and r["candidate"] == c),
                        key=lambda r: r["dofs"])
            if not rs:
                continue
            conv = all(r["reason"] > 0 for r in rs)
            its_max = rs[-1]["its"] if rs[-1]["reason"] > 0 else -1
            g = rs[-1]["its"] / max(rs[0]["its"], 1) if conv else float("nan")
            kv += [f"its_{c}_{st}={its_max}", f"growth_{c}_{st}={g:.3g}"]
            # every size: iterations (-1: not converged), set-up and solve seconds
            kv += [f"dofs_{c}_{st}=" + "/".join(str(r["dofs"]) for r in rs),
                   f"itsall_{c}_{st}=" + "/".join(
                       str(r["its"] if r["reason"] > 0 else -1) for r in rs),
                   f"setup_{c}_{st}=" + "/".join(f"{r['setup_s']:.2f}" for r in rs),
                   f"solve_{c}_{st}=" + "/".join(f"{r['solve_s']:.2f}" for r in rs)]
            if all("gflop" in r for r in rs):
                kv += [f"gflop_{c}_{st}=" + "/".join(f"{r['gflop']:.1f}" for r in rs)]
            if st == "shell" and conv and len(rs) == len(targets) - args.skip_sizes and not (
                    comm.size == 1 and (c == "bjacobi_lu" or c.startswith(("direct", "bddc")))):
                growth[c] = (g, rs[-1]["its"], rs[-1]["dofs"])
    if growth:
        best = min(growth, key=lambda c: (growth[c][0], growth[c][1]))
        kv += [f"best={best}", f"its_at_max={growth[best][1]}",
               f"its_growth={growth[best][0]:.3g}", f"dofs_max={growth[best][2]}"]
    kv += [f"blas={compat.blas_library()}", f"load_start={load0:.2f}",
           f"load_end={load_average():.2f}"]
    print(" ".join(kv), flush=True)


if __name__ == "__main__":
    main()
