"""Walls that respond to the particles (gsi.dem.wall_drivers): servo and free walls.

- Servo lid on a bed in a box with frictionless side walls: the lid holds the target
  stress (its mean over the last third of the run within 1 %), and the floor carries the
  lid force plus the bed's weight (statics: the side walls carry no vertical load).
- Free piston of mass M resting on the settled bed: the floor carries (M + m_bed) g.
- A free wall struck by one sphere (no gravity): particle + wall momentum is conserved
  to round-off (equal and opposite impulses at the same instant); a hinged flap struck
  off its axis conserves the angular momentum about the hinge.
"""
import math

import numpy as np
import pytest

from gsi.dem import Box, Material, Simulation, lattice_fill
from gsi.dem.wall_drivers import FreeWall, Servo

L = 0.02                # box width (m)
R = 2e-3                # particle radius (m)
MATS = {"glass": Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.5),
        "smooth": Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.0)}


def _settled_bed():
    """64 spheres (r 1.8-2 mm) settled for 0.4 s on a floor, frictionless side walls."""
    sim = Simulation(MATS, gravity=(0, 0, -9.81), dt=4e-5, skin=5e-4,
                     domain=((0, 0, -0.01), (L, L, 0.08)))
    sim.add_plane((0, 0, 0), (0, 0, 1), material="glass")
    for p, n in (((0, 0, 0), (1, 0, 0)), ((L, 0, 0), (-1, 0, 0)), ((0, 0, 0), (0, 1, 0)),
                 ((0, L, 0), (0, -1, 0))):
        sim.add_plane(p, n, material="smooth")
    rng = np.random.default_rng(0)
    x = lattice_fill(Box((0, 0, 0), (L, L, 4 * 2.2 * R)), R, spacing=2.2 * R)
    sim.add_particles(x + rng.uniform(-1e-4, 1e-4, x.shape), R * rng.uniform(0.9, 1.0, len(x)),
                      material="glass")
    sim.step(int(0.4 / sim.dt))
    return sim


def _run(sim, driver, seconds):
    """Step one at a time; (lid load along its normal, floor force z) per step."""
    rows = []
    for _ in range(int(seconds / sim.dt)):
        sim.step(1)
        rows.append((driver.load, sim.planes[0].force[2]))
    a = np.array(rows)
    return a[2 * len(a) // 3:]          # the last third


def test_servo_lid_holds_the_stress_and_the_floor_carries_lid_plus_bed(record_validation):
    sim = _settled_bed()
    W = sim.mass.sum() * 9.81
    top = (sim.x[:, 2] + sim.radius).max()
    lid = sim.add_plane((0, 0, top + 1e-3), (0, 0, -1), material="smooth")
    area = L * L
    sigma = 3 * W / area                        # Pa: three times the bed's own weight
    servo = sim.drivers.add(Servo(lid, target=sigma, area=area, max_speed=0.05))
    last = _run(sim, servo, 0.3)
    lid_force = -last[:, 0].mean()              # N: the bed's push on the lid, along -d
    floor = -last[:, 1].mean()
    assert servo.gain * servo.stiffness * sim.dt == pytest.approx(0.5)   # the stated rule
    record_validation("servo lid: mean stress over the last third = target", reference=sigma,
                      measured=lid_force / area, tolerance=1e-2, unit="Pa",
                      source="the controller's set point")
    record_validation("servo lid: floor force = lid force + bed weight (frictionless sides)",
                      reference=lid_force + W, measured=floor, tolerance=1e-2, unit="N",
                      source="statics of the bed")
    assert lid_force / area == pytest.approx(sigma, rel=1e-2)
    assert floor == pytest.approx(lid_force + W, rel=1e-2)


def test_free_piston_on_a_settled_bed_floor_carries_both_weights(record_validation):
    sim = _settled_bed()
    W = sim.mass.sum() * 9.81
    top = (sim.x[:, 2] + sim.radius).max()
    lid = sim.add_plane((0, 0, top), (0, 0, -1), material="smooth")
    M = 0.02                                    # kg, about 4 bed weights
    sim.drivers.add(FreeWall(lid, mass=M, gravity=sim.g))
    last = _run(sim, sim.drivers.items[0], 0.4)
    floor = -last[:, 1].mean()
    record_validation("free piston on a settled bed: floor force = (M + m_bed) g",
                      reference=M * 9.81 + W, measured=floor, tolerance=5e-3, unit="N",
                      source="statics of bed and piston")
    assert floor == pytest.approx(M * 9.81 + W, rel=5e-3)


@pytest.mark.parametrize("kind", ["plane", "mesh"])
def test_free_wall_struck_by_a_sphere_conserves_momentum(kind, record_validation):
    mat = MATS["glass"]
    sim = Simulation({"m": mat}, gravity=(0, 0, 0), dt=2e-6, skin=2e-4,
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
    sim.step(3000)                              # struck at ~0.5 ms; apart after ~1.2 ms
    assert fw.velocity < -0.4 and sim.ncontact[0] == 0
    p1 = m * sim.v[0, 0] + fw.momentum(sim.dt) * fw.d[0]
    record_validation(f"free wall ({kind}) struck by a sphere: momentum conserved",
                      reference=p0, measured=p1, tolerance=1e-12, unit="kg m/s",
                      source="equal and opposite impulses")
    assert p1 == pytest.approx(p0, rel=1e-12, abs=0)


def test_hinged_flap_struck_off_axis_conserves_angular_momentum():
    sim = Simulation({"glass": MATS["glass"]}, gravity=(0, 0, 0), dt=2e-6, skin=2e-4,
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
    sim.step(1500)
    assert fw.velocity < -60 and sim.ncontact[0] == 0      # swung away about -y
    assert ang() == pytest.approx(L0, rel=1e-12, abs=0)
