"""docs/design.md, "Validation cases", case 6a: uniform-traction patch test -- a linear displacement field is exact.

Block under uniform traction s on x = Lx, held by symmetry planes (u_x = 0 on x = 0,
u_y = 0 on y = 0, u_z = 0 on z = 0) so that it contracts freely. Exact solution:
u = (s x / E, -nu s y / E, -nu s z / E); it is linear, so P1 and P2 reproduce it to
round-off on any mesh, here a gmsh-free structured box and a gmsh slab.
"""
import numpy as np
import pytest

from gsi import meshes
from gsi.fem.elasticity import Elasticity
from gsi.fem.materials import StructuralMaterial

D = "docs/design.md"  # where the references are written down


@pytest.mark.parametrize("degree", [1, 2])
def test_uniform_traction_patch_is_exact(degree, record_validation):
    E, nu, s = 70e9, 0.33, 2.5e6
    sm = meshes.build("box", length_x=2.0, length_y=1.0, length_z=0.5, n=(4, 3, 2))
    p = Elasticity(sm, StructuralMaterial(E=E, nu=nu, rho=2700.0), degree=degree)
    p.clamp("x0", components=[0])
    p.clamp("y0", components=[1])
    p.clamp("z0", components=[2])
    p.set_traction("x1", [s, 0.0, 0.0])
    p.solve()
    x = p.V.tabulate_dof_coordinates()
    U = p.u.x.array.reshape(-1, 3)
    exact = np.c_[s * x[:, 0] / E, -nu * s * x[:, 1] / E, -nu * s * x[:, 2] / E]
    record_validation(f"patch test P{degree}: max displacement error / max displacement",
                      reference=0.0, measured=float(np.abs(U - exact).max() / np.abs(exact).max()),
                      tolerance=1e-10, kind="abs", source=f'{D}, "Validation cases" 6a')
    assert np.abs(U - exact).max() <= 1e-10 * np.abs(exact).max()
    # stress is uniaxial s: von Mises = s in every cell
    vm = p.von_mises().x.array
    assert np.abs(vm - s).max() <= 1e-8 * s
    # the supports carry the applied force: reaction = -s * area
    assert p.reaction() == pytest.approx([-s * 1.0 * 0.5, 0.0, 0.0], abs=1e-6 * s)


def test_patch_on_unstructured_gmsh_slab():
    """Same exactness on an unstructured, extruded gmsh mesh (membrane builder)."""
    E, nu, s, t = 200e9, 0.3, 1e6, 0.02
    sm = meshes.build("membrane", length_x=0.3, length_y=0.2, thickness=t, h=0.05)
    p = Elasticity(sm, StructuralMaterial(E=E, nu=nu, rho=7800.0))
    # bottom face held in z, rim held laterally, top face pulled in z: a uniaxial-strain
    # state whose exact displacement is linear
    p.clamp("outer", components=[2])
    p.clamp("support", components=[0, 1])
    p.set_traction("contact", [0.0, 0.0, s])
    p.solve()
    x = p.V.tabulate_dof_coordinates()
    U = p.u.x.array.reshape(-1, 3)
    # e_zz = s / M with the P-wave modulus M = E (1 - nu) / ((1 + nu)(1 - 2 nu)); u_x = u_y = 0
    M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    assert np.abs(U[:, 2] - s * x[:, 2] / M).max() <= 1e-10 * s * t / M
    assert np.abs(U[:, :2]).max() <= 1e-10 * s * t / M
