"""Wall velocity enters the contact.

- A sphere placed at rest on a belt (plane or triangle plate) moving at u: friction
  accelerates and spins it until it rolls without slip; angular momentum about the
  contact line is conserved, so the final speed is 2/7 u (solid sphere).
- A triangle wall rotating at omega about z: its vertices turn exactly by omega t and
  move with v = omega x r; a sphere resting on the turntable is dragged along the
  tangential direction of the rotation.
"""
import math

import numpy as np
import pytest

from gsi.dem import Material, Simulation

R = 1e-3
MAT = Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.5)


def _on_belt(kind, u=0.1):
    sim = Simulation({"m": MAT}, gravity=(0, 0, -9.81), dt=2e-6, skin=2e-4,
                     domain=((-0.02, -0.02, -0.01), (0.02, 0.02, 0.01)))
    if kind == "plane":
        sim.add_plane((0, 0, 0), (0, 0, 1), material="m", velocity=(u, 0, 0))
    else:
        s = 0.05
        w = sim.add_mesh_wall([[-s, -s, 0], [s, -s, 0], [s, s, 0], [-s, s, 0]],
                              [[0, 1, 2], [0, 2, 3]], material="m")
        w.set_motion(velocity=(u, 0, 0))
    m = MAT.rho * 4 / 3 * math.pi * R ** 3
    E_eff = 1 / (2 * (1 - MAT.nu ** 2) / MAT.E)
    delta = (m * 9.81 / (4 / 3 * E_eff * math.sqrt(R))) ** (2 / 3)
    sim.add_particles([[0, 0, R - delta]], R, material="m")
    sim.step(10000)
    return sim


@pytest.mark.parametrize("kind", ["plane", "mesh"])
def test_belt_final_speed_two_sevenths(kind):
    u = 0.1
    sim = _on_belt(kind, u)
    assert sim.v[0, 0] == pytest.approx(2 / 7 * u, rel=1e-2)
    # rolling on the belt: contact point moves with the belt
    assert sim.v[0, 0] - sim.omega[0, 1] * R == pytest.approx(u, rel=1e-2)


def test_turntable_vertices_and_drag():
    om = 20.0
    sim = Simulation({"m": MAT}, gravity=(0, 0, -9.81), dt=2e-6, skin=2e-4,
                     domain=((-0.02, -0.02, -0.01), (0.02, 0.02, 0.01)))
    s = 0.015
    v0 = np.array([[-s, -s, 0], [s, -s, 0], [s, s, 0], [-s, s, 0]], float)
    w = sim.add_mesh_wall(v0, [[0, 1, 2], [0, 2, 3]], material="m")
    w.set_motion(omega=(0, 0, om), centre=(0, 0, 0))
    np.testing.assert_allclose(w.vertex_velocity, np.cross([0, 0, om], v0), rtol=1e-14)
    sim.add_particles([[5e-3, 0, R - 1e-6]], R, material="m")
    sim.step(1000)
    ang = om * sim.time
    rot = np.array([[math.cos(ang), -math.sin(ang), 0], [math.sin(ang), math.cos(ang), 0], [0, 0, 1]])
    np.testing.assert_allclose(w.vertices, v0 @ rot.T, atol=1e-15)
    assert sim.v[0, 1] > 0 and abs(sim.v[0, 1]) > 10 * abs(sim.v[0, 0])
