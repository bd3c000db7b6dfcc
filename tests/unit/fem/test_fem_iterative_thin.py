"""The iterative solver on thin walls (issue 33): the P2 silo shell (R / t = 50) and the
clamped circular plate (a / t = 25) of benchmarks/shell_precond.py, coarse, solved with
``solver = "iterative"`` (CG + BoomerAMG in its systems form, gsi's default) and with
GAMG + rigid-body modes (``pc_type = "gamg"``), against the direct solver: a static solve
from rest, two generalized-alpha steps and two heat steps.

CG stops at ||b - A x|| <= 1e-12 ||b - A x_0|| (gsi.fem.options.ITERATIVE_RTOL), so the
error of x is at most cond(A) 1e-12 ||x||; the static stiffness of these thin walls has
cond(A) of order 1e6-1e8 at these sizes, so the answers are held to AGREE = 1e-8 of the
largest value, as tests/unit/fem/test_fem_solvers.py. Measured (1,584-dof shell, 3,870-dof
plate): the static displacement within 2.7e-10 (shell, GAMG) and 3.2e-11 (plate),
the dynamic fields within 7.4e-12, the temperatures within 1.3e-13; BoomerAMG needed
577 / 283 / 12 iterations (static / dynamic step / heat step) on the shell and 110 / 65 /
14 on the plate, GAMG 1625 / 840 / 17 and 978 / 705 / 16. GAMG runs with ``-m slow``.
"""
import numpy as np
import pytest

from gsi import meshes
from gsi.fem.elasticity import Elasticity
from gsi.fem.heat import Heat
from gsi.meshes import shell

AGREE = 1e-8


@pytest.fixture(scope="module", params=["shell", "plate"])
def thin(request):
    if request.param == "shell":
        h = shell.h_for_dofs(2e3, n_thickness=1, components=3)
        return meshes.build("shell", h=h, n_thickness=1), 1.25e-4
    return meshes.build("membrane", shape="circle", radius=0.5, thickness=0.02, h=0.16,
                        n_thickness=2), 2.5e-4


def _run(sm, dt, solver, petsc=None):
    """(static u, static reaction, dynamic u/v/a, heat T, problems) with ``solver``."""
    kw = dict(solver=solver, petsc_options=petsc)
    s = Elasticity(sm, "steel", degree=2, gravity=(0.0, 0.0, -9.81), **kw)
    s.clamp("support")
    s.set_traction("contact", [1.0e3, 0.0, -2.0e4])
    s.solve()
    d = Elasticity(sm, "steel", degree=2, scheme="generalized_alpha", dt=dt, rho_inf=0.3,
                   gravity=(0.0, 0.0, -9.81), **kw)
    d.clamp("support")
    for k in range(2):
        d.set_traction("contact", [0.0, 1.0e3 * k, -2.0e4])
        d.step()
    h = Heat(sm, "steel", dt=1.0, T_initial=20.0, degree=2, **kw)
    h.fix_temperature("support", 80.0)
    h.set_convection("outer", 25.0, 20.0)
    h.set_flux("contact", 2.0e3)
    for _ in range(2):
        h.step()
    fields = {"static u": s.u.x.array.copy(), "reaction": np.asarray(s.reaction("support")),
              "dynamic u": d.u.x.array.copy(), "dynamic v": d.v.x.array.copy(),
              "dynamic a": d.a.x.array.copy(), "heat T - 20": h.T.x.array - 20.0}
    return fields, (s, d, h)


@pytest.fixture(scope="module")
def direct(thin):
    return _run(*thin, "direct")[0]


@pytest.mark.parametrize("petsc, pc", [
    (None, "hypre"), pytest.param({"pc_type": "gamg"}, "gamg", marks=pytest.mark.slow)])
def test_iterative_matches_direct_on_thin_walls(thin, direct, petsc, pc):
    fields, problems = _run(*thin, "iterative", petsc)
    for p in problems:
        assert p.solver_kind == "iterative" and p.n_factorizations == 1
        assert p.linear_solver.describe() == f"cg + {pc}"
        assert min(p.iterations) > 1
    for name, ref in direct.items():
        err = np.abs(fields[name] - ref).max() / np.abs(ref).max()
        assert err <= AGREE, f"{name}: {err:.2e}"



def test_bddc_refused_on_one_rank_and_for_heat(thin):
    """``pc_type = "bddc"`` (BDDC on the MATIS step matrix, a subdomain per rank: see
    gsi.fem.options) is elasticity's, on 2 or more ranks (its match with the direct
    solver: tests/mpi/test_fem_solvers_mpi.py); elsewhere a one-line input error."""
    from gsi.errors import GsiInputError
    s = Elasticity(thin[0], "steel", degree=2, solver="iterative",
                   petsc_options={"pc_type": "bddc"})
    s.clamp("support")
    with pytest.raises(GsiInputError, match="pc_type = 'bddc': needs 2 or more MPI ranks"):
        s.solve()
    h = Heat(thin[0], "steel", dt=1.0, T_initial=20.0, degree=2, solver="iterative",
             petsc_options={"pc_type": "bddc"})
    h.fix_temperature("support", 80.0)
    with pytest.raises(GsiInputError, match="pc_type = 'bddc'.*elasticity only"):
        h.step()
