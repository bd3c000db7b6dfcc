"""Mesh convergence of the clamped circular plate (docs/design.md, "Validation cases", case 6b) with the iterative
solver (CG + BoomerAMG, gsi's iterative default), against plate theory.

Same plate as tests/validation/test_fem_clamped_circular_plate.py (a / t = 25, P2 tetrahedra,
two element layers through the thickness, uniform pressure): Mindlin's centre deflection
w = q a^4 / (64 D) + q a^2 / (4 kappa G t), D = E t^3 / (12 (1 - nu^2)) (Timoshenko &
Woinowsky-Krieger, Theory of Plates, §63). The 3D solution approaches it from below as h
shrinks; measured (direct and iterative solvers agree to 1e-8): -1.80 % at h = a/10
(2.4e4 dofs), -0.77 % at a/20 (9.1e4), -0.49 % at a/30 (2.0e5), and the finest mesh here,
h = a/35 (2.7e5 dofs), is within 0.5 %: -0.43 % (92 CG + GAMG iterations; 2026-12-02;
with CG + BoomerAMG, gsi's default since, -0.43 % again, 162 iterations from u = 0,
the test 264-573 s on the loaded host, 2026-12-05). With the block low-rank Cholesky
preset (CG + MUMPS BLR, epsilon 1e-5, 1 rank): the same -1.80 / -0.77 / -0.43 % at
2.4e4 / 9.1e4 / 2.7e5 dofs, in 5 / 6 / 7 CG iterations from u = 0 and about 16 s for
the three meshes, so that form runs in the default suite.
"""
import numpy as np
import pytest

from gsi import meshes
from gsi.fem.elasticity import Elasticity
from gsi.fem.materials import StructuralMaterial

A, T, E, NU, Q = 0.5, 0.02, 200e9, 0.3, 1e4


def _deflection(div: int, petsc=None):
    sm = meshes.build("membrane", shape="circle", radius=A, thickness=T, h=A / div, n_thickness=2)
    p = Elasticity(sm, StructuralMaterial(E=E, nu=NU, rho=7800.0), degree=2, solver="iterative",
                   petsc_options=petsc)
    p.clamp("support")
    p.set_traction("contact", [0.0, 0.0, -Q])
    p.solve()
    w = -p.comm.allreduce(p.u.x.array.reshape(-1, 3)[:, 2].min(), op=__import__("mpi4py").MPI.MIN)
    return w, p


#: the iterative solvers: gsi's default (CG + BoomerAMG; hundreds of iterations on this
#: thin plate, so slow) and the block low-rank Cholesky preset (CG + MUMPS BLR,
#: gsi.fem.options.BLR_EPSILON; a few iterations at every size)
SOLVERS = [pytest.param(None, "CG + BoomerAMG", marks=pytest.mark.slow, id="boomeramg"),
           pytest.param({"pc_type": "cholesky"}, "CG + BLR Cholesky", id="blr")]


@pytest.mark.parametrize("petsc, label", SOLVERS)
def test_clamped_plate_converges_to_mindlin_with_the_iterative_solver(petsc, label,
                                                                      record_validation):
    D = E * T**3 / (12 * (1 - NU**2))
    G, kappa = E / (2 * (1 + NU)), 5.0 / 6.0
    w_mindlin = Q * A**4 / (64 * D) + Q * A**2 / (4 * kappa * G * T)
    errors, its = [], []
    for div in (10, 20, 35):
        w, p = _deflection(div, petsc)
        assert p.solver_kind == "iterative"
        errors.append(w / w_mindlin - 1.0)
        its.append(p.iterations[0])
        # the rim carries the whole pressure resultant (to the solver's tolerance)
        area = np.pi * A**2
        assert p.reaction("support")[2] == pytest.approx(Q * area, rel=1e-2)
    assert errors[0] < errors[1] < errors[2] < 0.0          # monotone, from below
    record_validation(f"clamped plate, iterative solver ({label}): centre deflection "
                      f"at h = a/35 ({p.n_dofs} dofs, {its[-1]} CG iterations)",
                      reference=w_mindlin, measured=w, tolerance=0.005, unit="m",
                      source="Mindlin plate, Timoshenko & Woinowsky-Krieger §63 "
                             "(docs/design.md, case 6b)")
    assert abs(errors[-1]) <= 0.005, (errors, its)
