"""Linear solver choice: direct (MUMPS, factorized once), out of core (MUMPS Cholesky, the
factor on disk) against iterative (CG + algebraic multigrid, built once, warm-started), the
"auto" rule, and PETSc pass-through options.

The iterative solver stops at ||b - A x|| <= 1e-12 ||b - A x_0||, x_0 the last solution
(gsi.fem.options.ITERATIVE_RTOL); its answers agree with the direct solver's to about that tolerance times the conditioning
of these small problems, asserted here at 1e-8 of the largest value.
"""
import os
import pathlib
import socket
import subprocess
import sys

import numpy as np
import pytest
from petsc4py import PETSc

from gsi import meshes
from gsi.case.structure import Structure
from gsi.config.schema import load
from gsi.errors import GsiInputError
from gsi.fem.elasticity import Elasticity
from gsi.fem.heat import Heat
from gsi.fem.options import AUTO_LARGE_DOFS, ITERATIVE_RTOL, choose_solver

AGREE = 1e-8


@pytest.fixture(scope="module")
def slab():
    """A thick disc (radius / thickness = 10): few CG iterations, so the test is quick."""
    return meshes.build("membrane", shape="circle", radius=0.3, thickness=0.03, h=0.06,
                        n_thickness=2)


def _static(slab, solver, **kw):
    p = Elasticity(slab, "steel", degree=2, gravity=(0.0, 0.0, -9.81), solver=solver, **kw)
    p.clamp("support")
    p.set_traction("contact", [1.0e3, 0.0, -2.0e4])
    p.solve()
    return p


def _dynamic(slab, solver, **kw):
    p = Elasticity(slab, "steel", degree=2, scheme="generalized_alpha", dt=2e-5, rho_inf=0.8,
                   rayleigh=(5.0, 1e-7), solver=solver, **kw)
    p.clamp("support")
    p.set_traction("contact", [0.0, 0.0, -2.0e4])
    for k in range(4):
        p.set_traction("contact", [0.0, 1.0e3 * k, -2.0e4])
        p.step()
    return p


def _heat(slab, solver):
    h = Heat(slab, "steel", dt=0.5, T_initial=20.0, degree=2, solver=solver)
    h.fix_temperature("support", 80.0)
    h.set_convection("outer", 25.0, 20.0)
    h.set_flux("contact", 2.0e3)
    for _ in range(3):
        h.step()
    return h


def _close(a, b):
    return np.abs(a - b).max() <= AGREE * np.abs(a).max()


@pytest.mark.parametrize("other", ["iterative", "out_of_core"])
def test_static_results_agree_between_solvers(slab, other):
    d, i = _static(slab, "direct"), _static(slab, other)
    assert (d.solver_kind, i.solver_kind) == ("direct", other)
    assert _close(d.u.x.array, i.u.x.array)
    assert _close(d.reaction("support"), i.reaction("support"))
    assert d.iterations == [1]
    assert i.iterations[0] > 1 if other == "iterative" else i.iterations == [1]


@pytest.mark.parametrize("other", ["iterative", "out_of_core"])
def test_dynamic_results_agree_between_solvers(slab, other):
    d, i = _dynamic(slab, "direct"), _dynamic(slab, other)
    for name in ("u", "v", "a"):
        assert _close(getattr(d, name).x.array, getattr(i, name).x.array), name
    assert d.n_factorizations == i.n_factorizations == 1


@pytest.mark.parametrize("other", ["iterative", "out_of_core"])
def test_heat_results_agree_between_solvers(slab, other):
    d, i = _heat(slab, "direct"), _heat(slab, other)
    assert _close(d.T.x.array - 20.0, i.T.x.array - 20.0)
    assert i.heat_flow("support") == pytest.approx(d.heat_flow("support"), rel=1e-7)
    assert i.n_factorizations == 1 and len(i.iterations) == 3


def test_out_of_core_factor_is_on_disk_while_it_lives(slab, tmp_path, monkeypatch):
    """MUMPS writes the factor to $MUMPS_OOC_TMPDIR while it factorizes (ICNTL(22) = 1),
    every step reads it back, and the files go with the solver."""
    monkeypatch.setenv("MUMPS_OOC_TMPDIR", str(tmp_path))
    p = Elasticity(slab, "steel", degree=2, scheme="newmark", dt=2e-5, solver="out_of_core")
    p.clamp("support")
    p.set_traction("contact", [0.0, 0.0, -2.0e4])
    p.step()
    files = list(tmp_path.glob("gsi-mumps-*/mumps_*"))      # in the solver's own directory
    assert files and sum(f.stat().st_size for f in files) > 1e5      # the factor, in bytes
    assert [f.parent for f in files] == [pathlib.Path(p.linear_solver.scratch_dir)] * len(files)
    assert p.linear_solver.describe() == "preonly + cholesky"
    factor = p.linear_solver.ksp.getPC().getFactorMatrix()
    assert factor.getMumpsIcntl(22) == 1 and factor.getMumpsIcntl(7) == 5
    del factor                                   # the last reference is the solver's
    p.linear_solver.destroy()
    assert not list(tmp_path.iterdir())
    assert os.environ["MUMPS_OOC_TMPDIR"] == str(tmp_path)        # the user's, restored


def test_block_low_rank_factor_on_disk_goes_with_its_solver(slab, tmp_path, monkeypatch):
    """CG with MUMPS's block low-rank Cholesky (``pc_type = "cholesky"``) and its factor
    on disk (``mat_mumps_icntl_22 = 1``, the memory-lean form of issue 33's 1e6-dof runs):
    the files in a directory of the solver's own under $MUMPS_OOC_TMPDIR while it lives,
    gone with it, the user's variable restored; the answer is the direct solver's to CG's
    1e-10."""
    monkeypatch.setenv("MUMPS_OOC_TMPDIR", str(tmp_path))
    d = _dynamic(slab, "direct")
    i = _dynamic(slab, "iterative", petsc_options={"pc_type": "cholesky",
                                                    "mat_mumps_icntl_22": 1})
    for name in ("u", "v", "a"):
        assert _close(getattr(d, name).x.array, getattr(i, name).x.array), name
    assert i.linear_solver.describe() == "cg + cholesky" and i.n_factorizations == 1
    factor = i.linear_solver.ksp.getPC().getFactorMatrix()
    assert (factor.getMumpsIcntl(22), factor.getMumpsIcntl(35)) == (1, 2)
    del factor
    files = list(tmp_path.glob("gsi-mumps-*/mumps_*"))
    assert files and [f.parent for f in files] == \
        [pathlib.Path(i.linear_solver.scratch_dir)] * len(files)
    i.linear_solver.destroy()
    assert not list(tmp_path.iterdir())
    assert os.environ["MUMPS_OOC_TMPDIR"] == str(tmp_path)


_OOC_SCRIPT = """
from gsi import meshes
from gsi.fem.elasticity import Elasticity
slab = meshes.build("membrane", shape="circle", radius=0.3, thickness=0.03, h=0.06,
                    n_thickness=2)
p = Elasticity(slab, "steel", degree=2, solver="out_of_core")
p.clamp("support")
p.set_traction("contact", [0.0, 0.0, -2.0e4])
p.solve()
print(p.linear_solver.scratch_dir)
"""


def test_out_of_core_files_go_at_exit_and_a_killed_runs_at_the_next_start(tmp_path):
    """A run that ends without destroying its solver (PETSc leaves live objects alone at
    its end) leaves no factor behind; the directory of a killed process is removed by the
    next out-of-core solver of the host, another live process's is not."""
    env = dict(os.environ, TMPDIR=str(tmp_path), OMP_NUM_THREADS="1")
    env.pop("MUMPS_OOC_TMPDIR", None)
    root = pathlib.Path(__file__).resolve().parents[3]
    run = subprocess.run([sys.executable, "-c", _OOC_SCRIPT], env=env, cwd=root,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    used = pathlib.Path(run.stdout.strip().splitlines()[-1])
    assert used.parent == tmp_path and used.name.startswith("gsi-mumps-")
    assert not used.exists() and not list(tmp_path.glob("**/mumps_*"))
    # a killed run's directory (its pid gone) and a live one's (this test's parent)
    host = socket.gethostname().replace("-", "_")
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True).stdout.strip()
    killed = tmp_path / f"gsi-mumps-{host}-{dead}-abc"
    live = tmp_path / f"gsi-mumps-{host}-{os.getppid()}-abc"
    for d in (killed, live):
        d.mkdir()
        (d / "mumps_0_x").write_bytes(b"0" * 1000)
    run = subprocess.run([sys.executable, "-c", _OOC_SCRIPT], env=env, cwd=root,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert not killed.exists() and (live / "mumps_0_x").exists()


def test_iterative_builds_its_preconditioner_once_and_warm_starts(slab):
    PETSc.Log.begin()
    setups = PETSc.Log.Event("PCSetUp")
    p = Elasticity(slab, "steel", degree=2, scheme="newmark", dt=2e-5, solver="iterative")
    p.clamp("support")
    p.set_traction("contact", [0.0, 0.0, -2.0e4])
    p.step()
    p.step()
    after_two = setups.getPerfInfo()["count"]
    for _ in range(5):
        p.step()
    assert setups.getPerfInfo()["count"] == after_two   # PETSc's own count: no rebuild
    assert p.n_factorizations == 1
    assert p.linear_solver.describe() == "cg + hypre"
    assert p.linear_solver.ksp.getInitialGuessNonzero()
    # a second static solve of the same problem starts at the solution: it stays there,
    # with less work (down to the round-off floor ITERATIVE_ATOL ||b|| only)
    s = _static(slab, "iterative")
    u1 = s.u.x.array.copy()
    s.solve()
    assert s.iterations[1] < s.iterations[0]
    assert np.abs(s.u.x.array - u1).max() <= 1e-12 * np.abs(u1).max()


def test_iterative_preconditioner_by_problem_and_by_pc_type(slab):
    """BoomerAMG by default (systems form: no near-nullspace needed); pc_type = "gamg"
    gives GAMG with gsi's GAMG defaults and the six rigid-body modes; both agree."""
    h = _static(slab, "iterative")
    g = _static(slab, "iterative", petsc_options={"pc_type": "gamg"})
    assert h.linear_solver.describe() == "cg + hypre"
    assert not h.linear_solver.A.getNearNullSpace().handle         # none attached
    assert g.linear_solver.describe() == "cg + gamg"
    assert len(g.linear_solver.A.getNearNullSpace().getVecs()) == 6
    assert g.iterations[0] > h.iterations[0]
    assert _close(h.u.x.array, g.u.x.array)


def test_zero_load_gives_zero_without_iterating(slab):
    p = Elasticity(slab, "steel", degree=1, solver="iterative")
    p.clamp("support")
    p.u.x.array[:] = 1.0             # a warm start far from the answer
    p.solve()
    assert p.iterations == [0] and not np.any(p.u.x.array)


def test_auto_is_direct_below_the_measured_crossover(slab):
    p = Elasticity(slab, "steel", degree=2)
    assert p.solver == "auto" and p.solver_kind == "direct"
    n = AUTO_LARGE_DOFS["elasticity"]
    assert choose_solver("auto", n - 1, "elasticity") == "direct"
    assert choose_solver("auto", n, "elasticity") == "out_of_core"
    n = AUTO_LARGE_DOFS["heat"]
    assert choose_solver("auto", n - 1, "heat") == "direct"
    assert choose_solver("auto", n, "heat") == "iterative"
    assert choose_solver("direct", 10 * n, "heat") == "direct"
    with pytest.raises(GsiInputError, match=r"^structure.solver = 'mumps': must be one of"):
        Elasticity(slab, "steel", solver="mumps")


def test_petsc_options_reach_their_own_solver_only(slab):
    a = _static(slab, "iterative", petsc_options={"ksp_rtol": 1e-6})
    b = _static(slab, "iterative")
    assert a.linear_solver.prefix != b.linear_solver.prefix
    assert a.linear_solver.ksp.getTolerances()[0] == 1e-6
    assert b.linear_solver.ksp.getTolerances()[0] == ITERATIVE_RTOL
    assert a.iterations[0] < b.iterations[0]
    # gsi's options leave PETSc's database after the first solve
    left = [k for k in PETSc.Options().getAll() if k.startswith("gsi_")]
    assert left == []
    # the direct solver takes options too (MUMPS workspace +40 %), with the same answer
    d = _static(slab, "direct", petsc_options={"mat_mumps_icntl_14": 40})
    assert _close(d.u.x.array, b.u.x.array)


@pytest.mark.parametrize("options, message", [
    ({"ksp_rtoll": 1e-8}, r"^structure.petsc.ksp_rtoll = '1e-08': PETSc did not use this option"),
    ({"ksp_rtol": "abc"}, r"^structure.petsc.ksp_rtol = 'abc': PETSc refused it \(.*abc"),
    ({"pc_type": "nosuchpc"}, r"^structure.petsc.pc_type = 'nosuchpc': PETSc refused it"),
    ({"-ksp_rtol": 1e-8}, r"^structure.petsc.-ksp_rtol: not a PETSc option name; write it without"),
    ({"ksp_rtol": [1e-8]}, r"^structure.petsc.ksp_rtol = \[1e-08\]: must be a number, a word"),
    ({"ksp_type": "c g"}, r"^structure.petsc.ksp_type = 'c g': must be a number, a word"),
])
def test_bad_petsc_options_are_one_line_errors(slab, options, message):
    with pytest.raises(GsiInputError, match=message) as err:
        _static(slab, "iterative", petsc_options=options)
    assert "\n" not in str(err.value)
    left = [k for k in PETSc.Options().getAll() if k.startswith("gsi_")]
    assert left == []


def _case(structure):
    """A [[structures]] table through the schema, as the case loader reads it."""
    table = dict({"mesh": "membrane", "geometry": {"shape": "circle", "radius": 0.3}}, **structure)
    return load(Structure, table, "structures[0]")


@pytest.mark.parametrize("structure, message", [
    ({"solver": "mumps"}, r"^structures\[0\].solver = 'mumps': must be one of 'direct'"),
    ({"petsc": {"-ksp_rtol": 1e-8}}, r"^structures\[0\].petsc.-ksp_rtol: not a PETSc option"),
    ({"petsc": {"ksp_rtol": {"a": 1}}}, r"^structures\[0\].petsc.ksp_rtol = \{'a': 1\}: must be"),
    ({"contact": {"mode": "both"}, "thermal": {"petsc": {"ksp_rtol": True, "x y": 1}}},
     r"^structures\[0\].thermal.petsc.x y: not a PETSc option"),
    ({"contact": {"mode": "thermal", "n_sub": 1}, "petsc": {"ksp_rtol": 1e-8}},
     r"^structures\[0\].petsc: contact.mode = 'thermal' has no elasticity"),
])
def test_toml_solver_keys_are_checked_before_a_run(structure, message):
    with pytest.raises(GsiInputError, match=message):
        _case(structure)


def test_toml_solver_keys_reach_the_structure():
    st = _case({"solver": "iterative", "petsc": {"ksp_rtol": 1e-9, "ksp_monitor": False}})
    assert st.solver == "iterative" and st.petsc == {"ksp_rtol": 1e-9, "ksp_monitor": False}


def test_one_rank_direct_factorization_defaults(slab):
    """options.DIRECT_FACTORIZATION: elasticity's direct solve on one rank is MUMPS Cholesky
    with 50 % working space over MUMPS's estimate (ICNTL(14)); LU (MUMPS's own 20 %) when
    asked for, and for heat; the Cholesky answer is the LU one to round-off."""
    if PETSc.COMM_WORLD.getSize() != 1:
        pytest.skip("one rank")
    out = {}
    for fact in (None, "lu"):
        p = Elasticity(slab, "steel", degree=2, solver="direct", factorization=fact)
        p.clamp("support")
        p.set_traction("contact", [0.0, 0.0, -2.0e4])
        p.solve()
        factor = p.linear_solver.ksp.getPC().getFactorMatrix()
        out[fact] = (p.linear_solver.describe(), factor.getMumpsIcntl(14),
                     p.u.x.array.copy())
        del factor
    assert out[None][:2] == ("preonly + cholesky", 50)
    assert out["lu"][:2] == ("preonly + lu", 20)
    u_c, u_lu = out[None][2], out["lu"][2]
    assert np.abs(u_c - u_lu).max() <= 1e-10 * np.abs(u_lu).max()
    assert np.abs(u_lu).max() > 0
    h = Heat(slab, "steel", dt=1.0, solver="direct")
    h.fix_temperature("support", 20.0)
    h.step()
    assert h.linear_solver.describe() == "preonly + lu"
