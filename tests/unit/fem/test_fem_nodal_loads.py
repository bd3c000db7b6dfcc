"""Nodal point loads (the coupling's entry point), vertex maps and the factor-once rule."""
import numpy as np
import pytest
from petsc4py import PETSc

from gsi import meshes
from gsi.errors import GsiInputError
from gsi.fem import compat
from gsi.fem.problem import VertexDofMap
from gsi.fem.elasticity import Elasticity
from gsi.fem.heat import Heat
from gsi.fem.surface import ContactSurface


@pytest.fixture(scope="module")
def plate():
    return meshes.build("membrane", shape="circle", radius=0.5, thickness=0.01, h=0.08)


@pytest.mark.parametrize("degree", [1, 2])
def test_vertex_dof_map_points_at_the_vertex(plate, degree):
    V = compat.vector_space(plate.mesh, degree)
    vmap = VertexDofMap(V)
    xd = V.tabulate_dof_coordinates()
    xg = compat.geometry_x(plate.mesh)
    assert np.allclose(xd[vmap.node_dof], xg, atol=1e-14)
    # every vertex owned exactly once
    assert vmap.n_global == plate.mesh.topology.index_map(0).size_global


def test_point_loads_sum_to_applied_total(plate):
    p = Elasticity(plate, "steel")
    p.clamp("support")
    rng = np.random.default_rng(7)
    n_global = p.vmap.n_global
    ids = rng.choice(n_global, size=50, replace=False)
    F = rng.normal(size=(50, 3)) * 100.0
    p.add_nodal_loads(ids, F)
    p.add_nodal_loads(ids[:5], F[:5])          # loads accumulate
    total = F.sum(axis=0) + F[:5].sum(axis=0)
    assert p.load_sum() == pytest.approx(total, rel=1e-12, abs=1e-9)
    p.solve()
    # statics: the supports take the applied load
    assert p.reaction() == pytest.approx(-total, rel=1e-8, abs=1e-6)
    p.clear_nodal_loads()
    assert p.load_sum() == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)


def test_point_load_lands_on_its_vertex(plate):
    p = Elasticity(plate, "steel")
    gid = 17
    p.add_nodal_loads([gid], [[1.0, 2.0, 3.0]])
    node = np.flatnonzero(p.vmap.global_ids == gid)[0]
    dof = p.vmap.node_dof[node]
    F = p.load_vector().array.reshape(-1, 3)
    assert F[dof] == pytest.approx([1.0, 2.0, 3.0])
    assert np.count_nonzero(F) == 3


def test_bad_vertex_ids_and_loads_raise(plate):
    p = Elasticity(plate, "steel")
    with pytest.raises(GsiInputError):
        p.add_nodal_loads([p.vmap.n_global], [[0.0, 0.0, 1.0]])
    with pytest.raises(GsiInputError):
        p.add_nodal_loads([0], [[np.nan, 0.0, 1.0]])


def test_factorization_happens_once_per_run(plate):
    PETSc.Log.begin()
    # PETSc's own count of numerical factorizations: elasticity's is Cholesky
    # (options.DIRECT_FACTORIZATION), heat's LU
    events = [PETSc.Log.Event("MatLUFactorNum"), PETSc.Log.Event("MatCholFctrNum")]

    def count():
        return sum(e.getPerfInfo()["count"] for e in events)

    before = count()
    p = Elasticity(plate, "steel", scheme="generalized_alpha", dt=1e-4, rho_inf=0.9,
                   rayleigh=(1.0, 1e-6))
    p.clamp("support")
    s = ContactSurface(elasticity=p)
    for k in range(12):
        p.clear_nodal_loads()
        s.add_nodal_loads(np.tile([0.0, 0.0, -float(k)], (s.n_vertices, 1)))
        p.set_traction("contact", [0.0, 0.0, -10.0 * k])
        p.step()
    assert p.n_factorizations == 1
    assert count() - before == 1
    h = Heat(plate, "steel", dt=1.0)
    h.fix_temperature("support", 20.0)
    for _ in range(5):
        h.step()
    assert h.n_factorizations == 1
    assert count() - before == 2


def test_supports_cannot_change_after_factorization(plate):
    p = Elasticity(plate, "steel")
    p.clamp("support")
    p.solve()
    with pytest.raises(GsiInputError):
        p.clamp("outer")


def test_input_errors_are_one_line(plate):
    for kwargs in (dict(scheme="euler"), dict(scheme="newmark"), dict(degree=3),
                   dict(rayleigh=(-1.0, 0.0))):
        with pytest.raises(GsiInputError) as err:
            Elasticity(plate, "steel", **kwargs)
        assert "\n" not in str(err.value)
    with pytest.raises(GsiInputError):
        Elasticity(plate, "steel").clamp("nowhere")
    with pytest.raises(GsiInputError):
        Heat(plate, "steel", dt=1.0, theta=1.2)
