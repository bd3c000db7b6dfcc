"""Heat boundary conditions against exact steady 1D solutions (linear profiles, which P1
reproduces to round-off): a bar held at T_0 on x = 0 and, on x = L,

* convection h to T_amb: q = (T_0 - T_amb) / (L/k + 1/h), T(x) = T_0 - q x / k;
* a prescribed flux q_in into the bar: T(x) = T_0 + q_in x / k;
* nodal heat loads Q (W) at the end-face vertices: the fixed face removes exactly Q.

The steady state is reached with one backward-Euler step of dt = 1e9 L^2 / a (the
capacity term is then 1e-9 of the conduction term).
"""
import numpy as np
import pytest

from gsi import meshes
from gsi.fem.heat import Heat
from gsi.fem.materials import MATERIALS

L, B = 0.5, 0.05
MAT = MATERIALS["concrete"]


def _bar():
    sm = meshes.build("box", length_x=L, length_y=B, length_z=B, n=(8, 1, 1))
    p = Heat(sm, MAT, dt=1e9 * L**2 / MAT.diffusivity, theta=1.0, T_initial=0.0)
    p.fix_temperature("x0", 300.0)
    return p


def test_steady_convection_end():
    p = _bar()
    h, T_amb = 25.0, 290.0
    p.set_convection("x1", h, T_amb)
    p.step()
    q = (300.0 - T_amb) / (L / MAT.k + 1.0 / h)
    x = p.V.tabulate_dof_coordinates()[:, 0]
    assert np.abs(p.T.x.array - (300.0 - q * x / MAT.k)).max() < 1e-6
    # heat leaves through the convective face and enters through the fixed face
    assert p.heat_flow("x1") == pytest.approx(-q * B * B, rel=1e-6)
    assert p.heat_flow("x0") == pytest.approx(q * B * B, rel=1e-6)
    assert p.heat_flow("y0") == 0.0


def test_steady_prescribed_flux():
    p = _bar()
    q_in = 400.0
    p.set_flux("x1", q_in)
    p.step()
    x = p.V.tabulate_dof_coordinates()[:, 0]
    assert np.abs(p.T.x.array - (300.0 + q_in * x / MAT.k)).max() < 1e-6
    assert p.dirichlet_heat_flow("x0") == pytest.approx(-q_in * B * B, rel=1e-6)


def test_nodal_heat_leaves_through_the_fixed_face():
    p = _bar()
    # global ids of the end-face vertices, through the vertex -> dof map
    node_x = p.V.tabulate_dof_coordinates()[p.vmap.node_dof]
    ids = p.vmap.global_ids[np.isclose(node_x[:, 0], L)]
    Q = np.array([1.0, 2.0, 3.0, 4.0])[: ids.size]
    p.add_nodal_heat(ids, Q)
    assert p.nodal_heat() == pytest.approx(Q.sum())
    p.step()
    assert p.dirichlet_heat_flow("x0") == pytest.approx(-Q.sum(), rel=1e-6)
    assert p.min_max()[1] > 300.0
