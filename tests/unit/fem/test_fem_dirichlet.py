"""Prescribed values by tag (gsi.fem.dirichlet.Dirichlet), shared by Elasticity and Heat."""
import numpy as np
import pytest

from gsi import meshes
from gsi.errors import GsiInputError
from gsi.fem import compat
from gsi.fem.elasticity import Elasticity
from gsi.fem.heat import Heat


@pytest.fixture(scope="module")
def bar():
    return meshes.build("box", length_x=0.4, length_y=0.05, length_z=0.05, n=(8, 1, 1))


def _face_dofs(sm, V, tag, comps):
    """Owned unrolled dofs of the vertices on facet ``tag`` (independent of Dirichlet)."""
    x = V.tabulate_dof_coordinates()
    n_owned = compat.dof_index_map(V)[0].size_local
    axis, value = {"x0": (0, 0.0), "x1": (0, 0.4)}[tag]
    nodes = np.flatnonzero(np.isclose(x[:n_owned, axis], value))
    bs = V.dofmap.index_map_bs
    return np.sort(np.concatenate([nodes * bs + c for c in comps]))


def test_elasticity_supports_and_their_dofs(bar):
    el = Elasticity(bar, "steel")
    el.clamp("x0")
    el.clamp("x1", components=(0,), value=(1e-4,))
    el.clamp("x1", components=(2,))
    assert el.supports == ("x0", "x1") and el.has_prescribed_motion()
    assert np.array_equal(el.dirichlet.dofs("x0"), _face_dofs(bar, el.V, "x0", (0, 1, 2)))
    assert np.array_equal(el.dirichlet.dofs("x1"), _face_dofs(bar, el.V, "x1", (0, 2)))
    assert np.array_equal(el.dirichlet.dofs(), np.union1d(el.dirichlet.dofs("x0"),
                                                          el.dirichlet.dofs("x1")))
    el.solve()
    u = el.u.x.array
    assert np.allclose(u[el.dirichlet.dofs("x1")], np.where(
        el.dirichlet.dofs("x1") % 3 == 0, 1e-4, 0.0), atol=1e-18)
    with pytest.raises(GsiInputError, match="structure.reaction tag = 'y0'"):
        el.reaction("y0")


def test_heat_fixed_tags_and_the_unconstrained_body(bar):
    h = Heat(bar, "steel", dt=1.0, T_initial=20.0)
    assert h.fixed_tags == () and h.bc_dofs().size == 0 and not h.dirichlet.moves()
    h.fix_temperature("x0", 100.0)
    assert h.fixed_tags == ("x0",) and h.dirichlet.moves()
    assert np.array_equal(h.bc_dofs(), _face_dofs(bar, h.V, "x0", (0,)))
    h.step()
    assert np.allclose(h.T.x.array[h.bc_dofs()], 100.0)
    with pytest.raises(GsiInputError, match="dirichlet_heat_flow tag = 'x1'"):
        h.dirichlet_heat_flow("x1")
    C, K = h.matrices()
    ones = C.createVecRight()
    ones.set(1.0)
    out = K.createVecLeft()
    K.mult(ones, out)              # conduction only: K annihilates a uniform field
    assert np.abs(out.array).max() < 1e-9 * abs(K.norm())
