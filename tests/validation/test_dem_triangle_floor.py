"""A sphere on a triangulated floor feels the same force on a face, an edge or a vertex
as on the analytic plane (docs/design.md, "Contact geometry": no double push), and the wall
accumulators balance: vertex_impulse sums to -impulse_on_particles, vertex_heat to
-heat_to_particles (docs/design.md, "Balance" under "Coupling").
"""
import math

import numpy as np
import pytest

from gsi.dem import Material, Simulation

R = 1e-3
MAT = Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.5, k=1.0, cp=840.0)


def grid_floor(n=4, h=1e-3, z=0.0):
    """n x n squares of side h, each split into 2 triangles (interior vertices: 6 triangles)."""
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
    v = np.column_stack([i.ravel() * h, j.ravel() * h, np.full(i.size, z)])
    tri = []
    for a in range(n):
        for b in range(n):
            p = a * (n + 1) + b
            tri += [[p, p + n + 1, p + n + 2], [p, p + n + 2, p + 1]]
    return v, np.array(tri)


def fan_floor(m=8, rad=3e-3):
    """A fan of m triangles around a centre vertex at the origin (centre: m triangles)."""
    ang = 2 * math.pi * np.arange(m) / m
    v = np.vstack([[0, 0, 0], np.column_stack([rad * np.cos(ang), rad * np.sin(ang), np.zeros(m)])])
    tri = [[0, 1 + k, 1 + (k + 1) % m] for k in range(m)]
    return v, np.array(tri)


def one_step_force(x, floor=None, delta=1e-5):
    sim = Simulation({"m": MAT}, gravity=(0, 0, 0), dt=1e-7, skin=2e-4,
                     domain=((-0.01, -0.01, -0.01), (0.01, 0.01, 0.01)))
    if floor is None:
        wall = sim.add_plane((0, 0, 0), (0, 0, 1), material="m")
    else:
        wall = sim.add_mesh_wall(*floor, material="m")
    sim.add_particles([[x[0], x[1], R - delta]], R, material="m")
    sim.step(1)
    return sim.force[0].copy(), wall.force.copy(), sim


@pytest.mark.parametrize("where,xy,floor", [
    ("face", (1.3e-3, 2.6e-3), "grid"),
    ("edge_axis", (2.0e-3, 1.5e-3), "grid"),
    ("edge_diagonal", (1.5e-3, 1.5e-3), "grid"),
    ("vertex_6", (2.0e-3, 2.0e-3), "grid"),
    ("vertex_fan_8", (0.0, 0.0), "fan"),
    ("edge_fan", (1.2e-3, 0.0), "fan"),
    # a fine grid: a few hundred candidates, the contact's past the 64th, where the
    # de-duplication recomputes closest points instead of reading its mask (mesh_dedup)
    ("vertex_fine", (2.0e-3, 2.0e-3), "fine"),
    ("edge_fine", (2.05e-3, 2.0e-3), "fine"),
    ("face_fine", (2.03e-3, 2.06e-3), "fine"),
])
def test_same_force_on_face_edge_vertex(where, xy, floor):
    geometry = {"grid": grid_floor, "fan": fan_floor,
                "fine": lambda: grid_floor(n=40, h=1e-4)}[floor]()
    # on the fine grid the contact circle (radius sqrt(2 R delta)) must stay inside the
    # features next to the contact point, or it reaches other triangles' edges
    delta = 1e-7 if floor == "fine" else 1e-5
    f_plane, w_plane, _ = one_step_force(xy, delta=delta)
    f_mesh, w_mesh, sim = one_step_force(xy, geometry, delta=delta)
    if floor == "fine":
        assert sim.wall_contacts.count[0] == 1
        assert sim.wall_contacts.cand[0, 0] - sim.pairs.tri_start[0] >= 64
    E_eff = 1 / (2 * (1 - 0.3 ** 2) / MAT.E)
    assert f_plane[2] == pytest.approx(4 / 3 * E_eff * math.sqrt(R) * delta ** 1.5, rel=1e-3)
    np.testing.assert_allclose(f_mesh, f_plane, rtol=1e-9, atol=1e-12 * abs(f_plane[2]))
    np.testing.assert_allclose(w_mesh, w_plane, rtol=1e-9, atol=1e-12 * abs(f_plane[2]))


def test_resting_on_vertex_carries_weight_and_accumulators_balance():
    sim = Simulation({"m": MAT}, heat="area", gravity=(0, 0, -9.81), dt=2e-6, skin=2e-4,
                     domain=((-0.01, -0.01, -0.01), (0.01, 0.01, 0.01)))
    v, t = grid_floor()
    wall = sim.add_mesh_wall(v, t, material="m", vertex_temperature=np.linspace(50, 100, len(v)))
    sim.add_particles([[2e-3, 2e-3, R - 1e-6]], R, material="m", T=0.0)
    sim.step(20000)
    weight = sim.mass[0] * 9.81
    assert wall.force[2] == pytest.approx(-weight, rel=1e-3)
    imp = wall.vertex_impulse
    scale = np.abs(wall.impulse_on_particles).max()
    np.testing.assert_allclose(imp.sum(0), -wall.impulse_on_particles, rtol=0, atol=1e-13 * scale)
    assert wall.impulse_on_particles[2] == pytest.approx(weight * sim.time, rel=2e-2)
    heat = wall.heat_to_particles
    assert heat > 0
    assert wall.vertex_heat.sum() == pytest.approx(-heat, rel=1e-12)
    assert heat == pytest.approx(sim.mass[0] * MAT.cp * sim.T[0], rel=1e-12)
    # the contact is at vertex 12 = (2, 2) mm, whose temperature is 75 degC
    assert wall.vertex_heat.argmin() == 12
    wall.reset_accumulators()
    assert not wall.vertex_impulse.any() and wall.heat_to_particles == 0.0


def test_rolling_down_triangulated_incline():
    """Across many face/edge/vertex switches of a fine triangulation (0.7 mm triangles,
    the sphere crosses ~20 of them) a sphere still rolls with a = 5/7 g sin(theta)."""
    th, g = math.radians(20.0), 9.81
    sim = Simulation({"m": MAT}, gravity=(g * math.sin(th), 0, -g * math.cos(th)), dt=2e-6,
                     skin=2e-4, domain=((-0.01, -0.01, -0.01), (0.05, 0.01, 0.01)))
    h = 0.7e-3
    v, t = grid_floor(n=60, h=h)
    v[:, 0] -= 0.005
    v[:, 1] -= 15 * h
    sim.add_mesh_wall(v, t, material="m")
    m = MAT.rho * 4 / 3 * math.pi * R ** 3
    E_eff = 1 / (2 * (1 - MAT.nu ** 2) / MAT.E)
    d = (m * g * math.cos(th) / (4 / 3 * E_eff * math.sqrt(R))) ** (2 / 3)
    sim.add_particles([[0, 3e-4, R - d]], R, material="m")
    ts, xs = [], []
    for _ in range(40):
        sim.step(1000)
        ts.append(sim.time)
        xs.append(sim.x[0, 0])
    ts, xs = np.array(ts), np.array(xs)
    keep = ts > 0.016
    a = 2 * np.polyfit(ts[keep], xs[keep], 2)[0]
    assert sim.x[0, 0] > 10 * h
    assert a == pytest.approx(5 / 7 * g * math.sin(th), rel=1e-2)
    assert sim.omega[0, 1] * R == pytest.approx(sim.v[0, 0], rel=1e-2)
