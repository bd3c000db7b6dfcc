"""Contact surface: triangles, gathered fields and scattered loads."""
import numpy as np
import pytest

from gsi import meshes
from gsi.fem.elasticity import Elasticity
from gsi.fem.heat import Heat
from gsi.fem.surface import ContactSurface


@pytest.fixture(scope="module")
def plate():
    return meshes.build("membrane", length_x=0.4, length_y=0.3, thickness=0.01, h=0.05)


def test_triangles_cover_the_top_face_outward(plate):
    p = Elasticity(plate, "steel")
    s = ContactSurface(elasticity=p)
    assert s.area() == pytest.approx(0.12, rel=1e-12)
    assert np.allclose(s.normals(), [0.0, 0.0, 1.0])
    assert np.allclose(s.x0[:, 2], 0.01)
    assert np.all(np.diff(s.global_ids) > 0)
    assert s.triangles.min() == 0 and s.triangles.max() == s.n_vertices - 1


def test_gathered_displacement_is_the_fe_field_at_the_vertices(plate):
    p = Elasticity(plate, "steel")
    p.clamp("support")
    s = ContactSurface(elasticity=p)
    p.u.interpolate(lambda x: np.vstack([x[0] ** 2, x[1] * x[2], x[0] + 3 * x[1]]))
    d = s.displacement()
    x = s.x0
    assert d == pytest.approx(np.c_[x[:, 0] ** 2, x[:, 1] * x[:, 2], x[:, 0] + 3 * x[:, 1]],
                              abs=1e-14)
    assert s.positions() == pytest.approx(x + d)


def test_barycentric_point_force_is_applied_exactly(plate):
    """A point force split by barycentric weights over a triangle reaches the structure
    as -F in total; a heat load likewise."""
    p = Elasticity(plate, "steel")
    h = Heat(plate, "steel", dt=1.0)
    s = ContactSurface(elasticity=p, heat=h)
    k = s.n_triangles // 2
    tri = s.triangles[k]
    w = np.array([0.2, 0.3, 0.5])
    F = np.array([0.4, -1.0, -7.0])
    loads = np.zeros((s.n_vertices, 3))
    loads[tri] = -np.outer(w, F)               # the structure takes -F (docs/design.md, "Coupling")
    s.add_nodal_loads(loads)
    assert p.load_sum() == pytest.approx(-F, rel=1e-12)
    q = np.zeros(s.n_vertices)
    q[tri] = 5.0 * w
    s.add_nodal_heat(q)
    assert h.nodal_heat() == pytest.approx(5.0, rel=1e-12)


def test_several_tags_make_one_surface():
    """contact.tags = ["z1", "x0"]: one triangle set of both faces; a tag given twice
    counts once; the P2 interface splits the union at its edge midpoints."""
    from gsi.coupling.interface import SurfaceInterface
    box = meshes.build("box", length_x=0.2, length_y=0.1, length_z=0.05, n=(4, 2, 1))
    p = Elasticity(box, "steel", degree=2)
    s = ContactSurface(elasticity=p, tag=["z1", "x0"])
    assert s.area() == pytest.approx(0.2 * 0.1 + 0.1 * 0.05, rel=1e-12)
    assert ContactSurface(elasticity=p, tag=["z1", "z1"]).n_triangles == \
        ContactSurface(elasticity=p, tag="z1").n_triangles
    itf = SurfaceInterface(p, tag=("z1", "x0"))
    assert itf.tags == ("z1", "x0") and len(itf.triangles) == 4 * s.n_triangles
    # the shared edge's vertices appear once
    assert s.n_vertices == len(np.unique(s.triangles))
