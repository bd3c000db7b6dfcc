"""Quadratic (P2) load weights of a mesh wall (gsi/dem/walls.py ``parent_nodes``).

A six-node triangle split at its edge midpoints into four wall triangles, each carrying
its parent: a fixed sphere pressing at parent coordinates l must put its impulse and heat
on the six nodes with exactly the P2 basis values
N = (l_a(2l_a-1), l_b(2l_b-1), l_c(2l_c-1), 4 l_a l_b, 4 l_b l_c, 4 l_c l_a),
which reproduce every quadratic field: sum_k N_k u(x_k) = u(p). Without a parent the
same wall keeps the linear weights of the sub-triangle (which do not).
"""
import numpy as np
import pytest

from gsi.dem import Material, MeshWall, Simulation
from gsi.errors import GsiInputError

R = 1e-3
MAT = Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.5, k=1.0, cp=840.0)
# a generic (not right-angled) parent triangle in z = 0, nodes a, b, c, ab, bc, ca
XA, XB, XC = np.array([0.0, 0.0, 0.0]), np.array([6e-3, 1e-3, 0.0]), np.array([2e-3, 5e-3, 0.0])
NODES = np.array([XA, XB, XC, (XA + XB) / 2, (XB + XC) / 2, (XC + XA) / 2])
A, B, C, AB, BC, CA = range(6)
SUB = np.array([[A, AB, CA], [AB, B, BC], [CA, BC, C], [AB, BC, CA]])
E = np.eye(3)
LAM = {A: E[0], B: E[1], C: E[2], AB: (E[0] + E[1]) / 2, BC: (E[1] + E[2]) / 2,
       CA: (E[2] + E[0]) / 2}


def p2_basis(l):
    la, lb, lc = l
    return np.array([la * (2 * la - 1), lb * (2 * lb - 1), lc * (2 * lc - 1),
                     4 * la * lb, 4 * lb * lc, 4 * lc * la])


def quadratic(x):
    return 3.0 + 2e2 * x[..., 0] - 5e2 * x[..., 1] + 4e4 * x[..., 0] ** 2 \
        - 7e4 * x[..., 0] * x[..., 1] + 1e5 * x[..., 1] ** 2


def press(l, quadratic_weights=True, steps=20):
    sim = Simulation({"m": MAT}, gravity=(0, 0, 0), dt=1e-7, skin=2e-4, heat="area",
                     domain=((-0.01, -0.01, -0.01), (0.02, 0.02, 0.01)))
    kw = {}
    if quadratic_weights:
        kw = dict(parent_nodes=np.tile(np.arange(6), (4, 1)),
                  parent_coords=np.array([[LAM[k] for k in s] for s in SUB]))
    wall = sim.add_mesh_wall(MeshWall(NODES, SUB, material="m", vertex_temperature=np.full(6, 50.0),
                                      **kw))
    p = np.asarray(l) @ NODES[:3]
    ids = sim.add_particles([p + [0, 0, R - 1e-5]], R, material="m", T=20.0)
    sim.fix(ids)
    sim.step(steps)
    return wall, p


@pytest.mark.parametrize("l", [(0.21, 0.13, 0.66), (0.6, 0.3, 0.1), (0.3, 0.35, 0.35),
                               (0.5, 0.25, 0.25), (0.05, 0.9, 0.05)])
def test_impulse_and_heat_go_to_the_p2_basis_values(l):
    wall, p = press(l)
    imp_p = wall.impulse_on_particles
    assert imp_p[2] > 0 and wall.heat_to_particles > 0
    N = p2_basis(l)
    assert wall.vertex_impulse == pytest.approx(-np.outer(N, imp_p), rel=1e-12, abs=1e-12 * imp_p[2])
    assert wall.vertex_heat == pytest.approx(-N * wall.heat_to_particles, rel=1e-12,
                                             abs=1e-12 * wall.heat_to_particles)
    # consistent load: sum_k P_k u(x_k) = F u(p) for a quadratic u
    P = wall.vertex_impulse[:, 2]
    assert P @ quadratic(NODES) == pytest.approx(-imp_p[2] * quadratic(p), rel=1e-12)


def test_linear_weights_without_a_parent_are_not_p2_consistent():
    """The control: the sub-triangle's hat weights have the same resultant but miss a
    quadratic field by far more than round-off -- the test above can fail."""
    l = (0.21, 0.13, 0.66)
    wall, p = press(l, quadratic_weights=False)
    imp_p = wall.impulse_on_particles
    P = wall.vertex_impulse[:, 2]
    assert P.sum() == pytest.approx(-imp_p[2], rel=1e-12)
    err = abs(P @ quadratic(NODES) + imp_p[2] * quadratic(p)) / abs(imp_p[2] * quadratic(p))
    assert err > 1e-3


@pytest.mark.parametrize("kw,msg", [
    (dict(parent_nodes=np.zeros((4, 6))), "give both or neither"),
    (dict(parent_nodes=np.zeros((4, 5)), parent_coords=np.zeros((4, 3, 3))), r"must be \(4, 6\)"),
    (dict(parent_nodes=np.full((4, 6), 6), parent_coords=np.full((4, 3, 3), 1 / 3)),
     r"vertex indices in \[0, 6\)"),
    (dict(parent_nodes=np.zeros((4, 6)), parent_coords=np.full((4, 3, 3), 0.5)),
     "summing to 1"),
])
def test_bad_parent_map_is_a_one_line_input_error(kw, msg):
    with pytest.raises(GsiInputError, match=msg):
        MeshWall(NODES, SUB, material="m", **kw)
