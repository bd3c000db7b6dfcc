"""Free walls (gsi.dem.wall_drivers.FreeWall) conserve momentum with the particles.

The servo lid and the free piston on a bed are validated by their demos
(tests/demos/test_driven_wall_demos.py: lid stress within 1 % of the target, floor = lid
+ bed weight within 1 %, floor = (M + m_bed) g within 0.5 %).

- A free wall struck by one sphere (no gravity): particle + wall momentum is conserved
  to round-off (equal and opposite impulses at the same instant); a hinged flap struck
  off its axis conserves the angular momentum about the hinge.
"""

import numpy as np
import pytest

from gsi.dem import Material, Simulation
from gsi.dem.wall_drivers import FreeWall

MATS = {"glass": Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.5)}


@pytest.mark.parametrize("kind", ["plane", "mesh"])
def test_free_wall_struck_by_a_sphere_conserves_momentum(kind, record_validation):
    mat = MATS["glass"]
    sim = Simulation({"m": mat}, gravity=(0, 0, 0), dt=5e-6, skin=2e-4,
                     domain=((-0.01, -0.01, -0.01), (0.01, 0.01, 0.01)))
    r = 1e-3
    if kind == "plane":
        w = sim.add_plane((0, 0, 0), (1, 0, 0), material="m")
    else:
        s = 0.005
        w = sim.add_mesh_wall([[0, -s, -s], [0, s, -s], [0, s, s], [0, -s, s]],
                              [[0, 1, 2], [0, 2, 3]], material="m")
    fw = sim.drivers.add(FreeWall(w, mass=2e-5, gravity=sim.g, direction=(1, 0, 0)))
    sim.add_particles([[2e-3, 3e-4, 0]], r, material="m", v=[[-1.0, 0.3, 0.0]],
                      omega=[[0.0, 0.0, 50.0]])
    m = sim.mass[0]
    p0 = m * sim.v[0, 0]
    sim.step(400)                               # struck at ~1 ms (20 steps); apart at 2 ms
    assert fw.velocity < -0.4 and sim.ncontact[0] == 0
    p1 = m * sim.v[0, 0] + fw.momentum(sim.dt) * fw.d[0]
    record_validation(f"free wall ({kind}) struck by a sphere: momentum conserved",
                      reference=p0, measured=p1, tolerance=1e-12, unit="kg m/s",
                      source="equal and opposite impulses")
    assert p1 == pytest.approx(p0, rel=1e-12, abs=0)


def test_hinged_flap_struck_off_axis_conserves_angular_momentum():
    sim = Simulation({"glass": MATS["glass"]}, gravity=(0, 0, 0), dt=5e-6, skin=2e-4,
                     domain=((-0.02, -0.02, -0.02), (0.02, 0.02, 0.02)))
    s = 0.005
    w = sim.add_mesh_wall([[0, -s, -s], [0, s, -s], [0, s, s], [0, -s, s]],
                          [[0, 1, 2], [0, 2, 3]], material="glass")
    c, ax = np.array([0.0, 0.0, -s]), np.array([0.0, 1.0, 0.0])
    fw = sim.drivers.add(FreeWall(w, inertia=1e-9, axis=ax, centre=c, gravity=sim.g))
    sim.add_particles([[2e-3, 3e-4, 2e-3]], 1e-3, material="glass", v=[[-1.0, 0.3, 0.1]],
                      omega=[[0.0, 20.0, 50.0]])

    def ang():
        rel = sim.x[0] - c
        return (np.cross(rel, sim.mass[0] * sim.v[0]) + sim.inertia[0] * sim.omega[0]) @ ax \
            + fw.momentum(sim.dt)

    L0 = ang()
    sim.step(600)
    assert fw.velocity < -60 and sim.ncontact[0] == 0      # swung away about -y
    assert ang() == pytest.approx(L0, rel=1e-12, abs=0)
