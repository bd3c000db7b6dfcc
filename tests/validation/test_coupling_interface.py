"""The FE contact surface as a DEM wall (gsi/coupling/interface.py), exact properties.

* P1 and P2: the wall follows the FE displacement exactly at its vertices (a field the
  space represents exactly is gathered to round-off), and the wall covers the surface
  (same area, outward normals).
* Loads: a point force split by the barycentric weights of the wall triangle that holds
  it reaches the structure with the same resultant and the same moment (P1: the
  consistent load; P2: the refined-triangle weights, a partition of unity that
  reproduces linear fields).
* DEM contact: a sphere resting on the wall pushes the FE with exactly -F, and the load
  vector b the FE holds is the consistent one: b . u_h = -F . u(p) for every field u_h of
  the space (P1: linear, P2: quadratic fields), p the contact point.
"""
import numpy as np
import pytest

from gsi import meshes
from gsi.coupling.interface import SurfaceInterface
from gsi.fem.elasticity import Elasticity


@pytest.fixture(scope="module")
def plate():
    return meshes.build("membrane", shape="circle", radius=0.3, thickness=0.01, h=0.08,
                        n_thickness=1)


@pytest.fixture(scope="module", params=[1, 2])
def interface(request, plate):
    p = Elasticity(plate, "rubber", degree=request.param)
    p.clamp("support")
    return SurfaceInterface(p)


def test_wall_covers_the_contact_surface(interface):
    itf = interface
    x = itf.x0
    a, b, c = (x[itf.triangles[:, k]] for k in range(3))
    n = np.cross(b - a, c - a)
    assert 0.5 * np.linalg.norm(n, axis=1).sum() == pytest.approx(itf.surface.area(), rel=1e-12)
    assert np.all(n[:, 2] > 0)                      # outward (up) like the surface
    assert np.allclose(x[:, 2], 0.01)
    expected = itf.n_vertices + (itf.n_midpoints if itf.elasticity.degree == 2 else 0)
    assert itf.n_nodes == expected
    if itf.elasticity.degree == 2:
        assert itf.n_midpoints > itf.n_vertices and len(itf.triangles) == 4 * itf.surface.n_triangles


def test_gathered_displacement_is_exact_for_fields_of_the_space(interface):
    itf = interface
    el = itf.elasticity
    if el.degree == 2:
        f = lambda x: np.vstack([x[0] ** 2, x[1] * x[2], x[0] * x[1] - 3 * x[1]])
        ref = lambda x: np.c_[x[:, 0] ** 2, x[:, 1] * x[:, 2], x[:, 0] * x[:, 1] - 3 * x[:, 1]]
    else:
        f = lambda x: np.vstack([x[0] + 2 * x[1], -x[2], 0.5 * x[0] - x[1]])
        ref = lambda x: np.c_[x[:, 0] + 2 * x[:, 1], -x[:, 2], 0.5 * x[:, 0] - x[:, 1]]
    el.u.interpolate(f)
    el.v.interpolate(f)
    assert itf.displacement() == pytest.approx(ref(itf.x0), abs=1e-15)
    assert itf.velocity() == pytest.approx(ref(itf.x0), abs=1e-15)
    assert itf.positions() == pytest.approx(itf.x0 + ref(itf.x0), abs=1e-15)
    el.u.x.array[:] = 0.0
    el.v.x.array[:] = 0.0


def test_point_force_keeps_resultant_and_moment(interface):
    itf = interface
    el = itf.elasticity
    rng = np.random.default_rng(3)
    P = np.zeros((itf.n_nodes, 3))
    F_tot, M_tot = np.zeros(3), np.zeros(3)
    for k in rng.choice(len(itf.triangles), 10, replace=False):
        w = rng.dirichlet([1, 1, 1])
        tri = itf.triangles[k]
        p = w @ itf.x0[tri]
        F = rng.normal(size=3)
        P[tri] += np.outer(w, F)
        F_tot += F
        M_tot += np.cross(p, F)
    el.clear_nodal_loads()
    itf.add_nodal_loads(P)
    assert el.load_sum() == pytest.approx(F_tot, rel=1e-12)
    # moment of the nodal loads the FE holds, from the owned dof coordinates
    from gsi.fem import compat
    imap, bs = compat.dof_index_map(el.V)
    X = el.V.tabulate_dof_coordinates()[: imap.size_local]
    Fn = el.nodal.values.reshape(-1, 3)
    M = el.comm.allreduce(np.cross(X, Fn).sum(axis=0))
    assert M == pytest.approx(M_tot, rel=1e-12, abs=1e-13)
    el.clear_nodal_loads()


def test_sphere_on_the_wall_loads_the_structure_with_minus_its_contact_force(interface):
    from gsi.dem import Material, Simulation
    itf = interface
    el = itf.elasticity
    wood = Material(E=5e5, nu=0.45, rho=400.0, e=0.5, mu=0.8)
    sim = Simulation({"wood": wood}, dt=2e-4, skin=4e-3, domain=((-0.4,) * 3, (0.4,) * 3))
    wall = itf.make_wall(sim, material="wood")
    sim.add_particles([[0.013, -0.021, 0.01 + 0.0099]], 0.01, material="wood")
    sim.step(50)
    P = wall.vertex_impulse / (50 * sim.dt)
    el.clear_nodal_loads()
    itf.add_nodal_loads(P)
    F_p = wall.impulse_on_particles / (50 * sim.dt)
    assert F_p[2] > 0
    assert el.load_sum() == pytest.approx(-F_p, rel=1e-12, abs=1e-15 * abs(F_p[2]))
    el.clear_nodal_loads()


def test_sphere_load_is_the_consistent_nodal_load_of_the_space(interface):
    """b . u_h = -F . u(p): P1 for a linear u, P2 for a quadratic u (exact in the space).
    The P1-iso-P2 hat weights of the refined wall (before the P2 parent map) missed
    the quadratic case by 0.45 %."""
    from gsi.dem import Material, Simulation
    from gsi.fem import compat
    itf = interface
    el = itf.elasticity
    if el.degree == 2:
        f = lambda x: np.vstack([x[0] ** 2 - x[1], 3 * x[0] * x[1] + x[2], x[1] ** 2 + 2 * x[0]])
    else:
        f = lambda x: np.vstack([x[0] - x[1], 3 * x[0] + x[2], 2 * x[1] + 1.0])
    wood = Material(E=5e5, nu=0.45, rho=400.0, e=0.5, mu=0.8)
    sim = Simulation({"wood": wood}, dt=2e-4, skin=4e-3, domain=((-0.4,) * 3, (0.4,) * 3))
    wall = itf.make_wall(sim, material="wood")
    p = np.array([0.0137, -0.0213, 0.01])
    sim.fix(sim.add_particles([p + [0, 0, 0.0099]], 0.01, material="wood"))
    sim.step(20)
    T = 20 * sim.dt
    el.clear_nodal_loads()
    itf.add_nodal_loads(wall.vertex_impulse / T)
    F = -wall.impulse_on_particles / T              # on the structure
    el.u.interpolate(f)
    imap, bs = compat.dof_index_map(el.V)
    work = el.comm.allreduce(float(el.u.x.array[: imap.size_local * bs] @ el.nodal.values))
    assert work == pytest.approx(float(F @ f(p[:, None])[:, 0]), rel=1e-12)
    el.u.x.array[:] = 0.0
    el.clear_nodal_loads()


def test_bad_loads_shape_is_a_one_line_input_error(interface):
    from gsi.errors import GsiInputError
    with pytest.raises(GsiInputError, match=r"coupling loads shape \(3, 3\): must be"):
        interface.add_nodal_loads(np.zeros((3, 3)))
