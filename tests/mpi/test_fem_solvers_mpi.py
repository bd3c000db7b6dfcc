"""The same structure on 1 and 2 MPI ranks with each linear solver
(tests/mpi/fem_solver_mpi_case.py): static, dynamic (generalized-alpha) and heat.

The direct solver's answers differ between partitions by round-off; the iterative
solver's by its tolerance (||b - A x|| <= 1e-12 ||b - A x_0||, x_0 the last solution): the multigrid hierarchy, and so the
iterates, depend on the partition. Both are held to 1e-8 of the largest value.

Fast: a small thick disc, iterative and out-of-core solvers (the direct one on 1 and 2 ranks is
tests/mpi/test_fem_mpi.py). Slow (-m slow): the silo shell of meshes.shell at about
1.2e5 dofs with the three solvers.
"""
import importlib.util
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("gsi_tests_mpirun", HERE / "mpirun.py")
mpirun = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(mpirun)

pytestmark = pytest.mark.mpi

TOL = 1e-8


def _pair(tmp, solver, mesh, *extra, timeout=300):
    return [mpirun.run_json(HERE / "fem_solver_mpi_case.py", n, tmp / f"{solver}_{mesh}_{n}.json",
                            args=(solver, mesh, *extra), timeout=timeout) for n in (1, 2)]


def _check_agree(r1, r2, kind):
    assert (r1["n_ranks"], r2["n_ranks"]) == (1, 2)
    assert r1["solver_kinds"] == r2["solver_kinds"] == [kind] * 3
    for key in ("static_norm", "dynamic_norm", "heat_norm"):
        assert r2[key] == pytest.approx(r1[key], rel=TOL), key
        assert r1[key] > 0
    for key in ("static_surface_u", "dynamic_surface_u", "surface_T", "static_reaction"):
        a, b = np.array(r1[key]), np.array(r2[key])
        assert np.abs(b - a).max() <= TOL * np.abs(a).max(), key
    for r in (r1, r2):
        assert r["dynamic_setups"] == r["heat_setups"] == 1


def test_iterative_solver_same_on_1_and_2_ranks(tmp_path):
    r1, r2 = _pair(tmp_path, "iterative", "slab")
    _check_agree(r1, r2, "iterative")
    assert min(r1["dynamic_its"] + r2["dynamic_its"]) > 1


def test_out_of_core_solver_same_on_1_and_2_ranks(tmp_path):
    r1, r2 = _pair(tmp_path, "out_of_core", "slab")
    _check_agree(r1, r2, "out_of_core")


@pytest.mark.slow
@pytest.mark.parametrize("solver", ["direct", "out_of_core", "iterative"])
def test_shell_same_on_1_and_2_ranks(tmp_path, solver):
    r1, r2 = _pair(tmp_path, solver, "shell", 0.04, timeout=3600)
    assert r1["n_dofs"] > 1e5
    _check_agree(r1, r2, solver)


def test_iterative_matches_direct_on_thin_walls_on_2_ranks(tmp_path):
    """The coarse shell and plate of tests/unit/fem/test_fem_iterative_thin.py on 2 ranks:
    CG + BoomerAMG against the direct solver (SuperLU_DIST on 2 ranks), static,
    generalized-alpha and heat, to the same 1e-8 of the largest value; and CG + BDDC
    (``pc_type = "bddc"``, two subdomains), static and generalized-alpha."""
    r = mpirun.run_json(HERE / "thin_solver_mpi_case.py", 2, tmp_path / "thin.json")
    assert r["n_ranks"] == 2
    for name in ("shell", "plate"):
        it = r[name]["iterative"]
        assert it["kinds"] == ["iterative"] * 3
        assert it["pcs"] == ["cg + hypre"] * 3
        assert min(min(its) for its in it["its"]) > 1
        for key, err in r[name]["errors"].items():
            assert err <= TOL, f"{name} {key}: {err:.2e}"
        # pc_type = "bddc": a subdomain per rank, CG to its 1e-10 (gsi.fem.options)
        bd = r[name]["bddc"]
        assert bd["pcs"][:2] == ["cg + bddc"] * 2 and bd["kinds"][:2] == ["iterative"] * 2
        assert min(min(its) for its in bd["its"][:2]) > 1
        for key, err in r[name]["bddc_errors"].items():
            assert err <= TOL, f"{name} bddc {key}: {err:.2e}"


@pytest.mark.parametrize("ranks", [1, 2])
def test_blr_cholesky_preset_matches_direct(tmp_path, ranks):
    """``solver = "iterative"`` with ``petsc = { pc_type = "cholesky" }`` (elasticity and
    heat): CG preconditioned by MUMPS's block low-rank Cholesky at epsilon 1e-5
    (gsi.fem.options.BLR_EPSILON), to its 1e-10, on the coarse shell and plate on 1 and 2
    ranks: static, generalized-alpha and heat against the direct solver to 1e-8 of the
    largest value, as the other iterative solvers above. These coarse walls' fronts are
    small, so the factor may be uncompressed and CG then takes one iteration: the test
    holds the preset's plumbing and tolerance (the compressed factor's iterations are
    measured by benchmarks/fe_scale.py, docs' performance page)."""
    r = mpirun.run_json(HERE / "thin_solver_mpi_case.py", ranks, tmp_path / "blr.json",
                        args=("blr",))
    assert r["n_ranks"] == ranks
    for name in ("shell", "plate"):
        blr = r[name]["blr"]
        assert blr["kinds"] == ["iterative"] * 3
        assert blr["pcs"] == ["cg + cholesky"] * 3
        assert min(min(its) for its in blr["its"]) >= 1
        for key, err in r[name]["errors"].items():
            assert err <= TOL, f"{name} blr {key}: {err:.2e}"


def test_bddc_keeps_average_acceleration_energy_on_2_ranks(tmp_path):
    """BDDC's CG stops at 1e-10 of the step's initial residual (not gsi's 1e-12): the
    suddenly loaded bar's energy under average acceleration is still conserved to the
    validation case's 1e-9 of its magnitude over 300 steps (tests/validation/
    test_fem_newmark_bar.py), as with the direct solver on the same 2 ranks."""
    r = mpirun.run_json(HERE / "bddc_energy_mpi_case.py", 2, tmp_path / "energy.json")
    assert r["n_ranks"] == 2 and r["bddc"]["pc"] == "cg + bddc"
    assert len(r["bddc"]["its"]) == 300 and min(r["bddc"]["its"]) >= 1
    for solver in ("direct", "bddc"):
        assert r[solver]["spread"] <= 1e-9, f"{solver}: {r[solver]['spread']:.2e}"
