"""Walls that respond (gsi.dem.wall_drivers) and their case keys (gsi.case.driven_motion):
the servo's schedule and gain rule, the builders, and the one-line errors."""
import math

import numpy as np
import pytest

from gsi.case.driven_motion import SchedulePoint
from gsi.case.walls import Motion, Wall
from gsi.dem import Material, Simulation
from gsi.dem.wall_drivers import (FreeWall, Oscillation, Servo, bed_of, projected_area,
                                  wall_stiffness)
from gsi.errors import GsiInputError

MAT = Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.5)


def _sim():
    return Simulation({"m": MAT}, gravity=(0, 0, -9.81), dt=2e-5, skin=2e-4,
                      domain=((-0.02, -0.02, -0.01), (0.02, 0.02, 0.03)))


def test_servo_schedule_from_the_case_is_piecewise_linear():
    sim = _sim()
    w = Wall(kind="plane", material="m", point=(0, 0, 0.02), normal=(0, 0, -1),
             motion=Motion(kind="servo", stress_schedule=[SchedulePoint(t=0.0, value=0.0),
                                                          SchedulePoint(t=0.1, value=400.0)],
                           area=4e-4, max_speed=0.1))
    w.add_to(sim)
    d = sim.drivers.items[0]
    assert isinstance(d, Servo) and d.stress
    assert d.target_force(0.05) == pytest.approx(200.0 * 4e-4)
    assert d.target_force(1.0) == pytest.approx(400.0 * 4e-4)       # held after the end
    assert d.peak_force == pytest.approx(400.0 * 4e-4)


def test_servo_gain_rule_and_refusal():
    sim = _sim()
    lid = sim.add_plane((0, 0, 0.01), (0, 0, -1), material="m")
    sim.add_particles([[0, 0, 0.0]], 1e-3, material="m")
    K = wall_stiffness(bed_of(sim), lid, 1.0, 4e-4)
    # N_c = A/(2 sqrt(3) r^2) contacts, Hertz k = (6 E*^2 r f)^(1/3) at f = F/N_c
    n_c = 4e-4 / (2 * math.sqrt(3) * 1e-6)
    E_eff = 1 / ((1 - MAT.nu ** 2) / MAT.E * 2)
    assert K == pytest.approx(n_c * (6 * E_eff ** 2 * 1e-3 * 1.0 / n_c) ** (1 / 3), rel=1e-12)
    s = Servo(lid, target=1.0, area=4e-4, stress=False, max_speed=0.1)
    assert s.set_gain(sim.dt, bed_of(sim)) * K * sim.dt == pytest.approx(0.5)
    bad = Servo(lid, target=1.0, area=4e-4, stress=False, max_speed=0.1, gain=2.0 / (K * sim.dt))
    with pytest.raises(GsiInputError, match=r"servo.gain = .*above the stability limit"):
        bad.set_gain(sim.dt, bed_of(sim))


def test_projected_area_of_a_tilted_plate():
    sim = _sim()
    c, s = math.cos(0.3), math.sin(0.3)
    w = sim.add_mesh_wall([[-0.01, -0.01, 0], [0.01, -0.01, 0], [0.01, 0.01, 0.02 * s / c],
                           [-0.01, 0.01, 0.02 * s / c]], [[0, 1, 2], [0, 2, 3]], material="m")
    assert projected_area(w.vertices, w.triangles, np.array([0.0, 0.0, 1.0])) == \
        pytest.approx(4e-4, rel=1e-12)


@pytest.mark.parametrize("kwargs, key", [
    (dict(amplitude=0.0, frequency=10.0), "amplitude"),
    (dict(amplitude=1e-3, frequency=10.0, axis=(0, 0, 1), centre=(0, 0, 0)), "axis"),
    (dict(amplitude=1e-3, frequency=10.0, direction=(0, 0, 0)), "direction"),
])
def test_oscillation_errors_name_the_key(kwargs, key):
    sim = _sim()
    plane = sim.add_plane((0, 0, 0), (0, 0, 1), material="m")
    with pytest.raises(GsiInputError, match=key):
        Oscillation(plane, **kwargs)


def test_free_wall_errors_and_oscillation_start():
    sim = _sim()
    plane = sim.add_plane((0, 0, 0), (0, 0, 1), material="m")
    with pytest.raises(GsiInputError, match="free wall.mass"):
        FreeWall(plane, gravity=sim.g)
    osc = Oscillation(plane, amplitude=1e-3, frequency=10.0, phase=0.7)
    assert osc.s(0.0) == 0.0                      # starts where it was built
    assert osc.gamma(sim.g) == pytest.approx(1e-3 * (20 * math.pi) ** 2 / 9.81)


def test_oscillation_updated_every_k_steps_is_exact_at_updates_and_on_the_chord():
    sim = _sim()
    plane = sim.add_plane((0, 0, 0), (0, 0, 1), material="m")
    k = 20
    osc = sim.drivers.add(Oscillation(plane, amplitude=1e-3, frequency=10.0, update_every=k))
    sim.add_particles([[0, 0, 0.01]], 1e-3, material="m")
    for _ in range(30):               # calls that end inside a chunk: the chunk carries on
        sim.step(7)
        n = sim.step_count
        t0, t1 = (n // k) * k * sim.dt, (n // k + 1) * k * sim.dt
        w = (sim.time - t0) / (t1 - t0)
        chord = (1 - w) * osc.s(t0) + w * osc.s(t1)
        assert plane.point[2] == pytest.approx(chord, abs=1e-15)
    with pytest.raises(GsiInputError, match="oscillation.update_every"):
        Oscillation(plane, amplitude=1e-3, frequency=10.0, update_every=0)


def test_driven_walls_restart_bit_identically_from_a_checkpoint():
    def build():
        sim = _sim()
        sim.add_plane((0, 0, 0), (0, 0, 1), material="m")
        lid = sim.add_plane((0, 0, 0.0045), (0, 0, -1), material="m")
        side = sim.add_plane((-0.004, 0, 0), (1, 0, 0), material="m")
        sim.drivers.add(Servo(lid, target=2e-3, stress=False, area=1e-5, max_speed=0.05,
                              update_every=3))
        sim.drivers.add(FreeWall(side, mass=1e-4, gravity=sim.g, spring=1.0))
        sim.drivers.add(Oscillation(sim.planes[0], amplitude=1e-4, frequency=30.0,
                                    update_every=7))
        sim.add_particles([[0, 0, 1.1e-3], [0, 0, 3.3e-3], [-2e-3, 0, 1.1e-3]], 1e-3,
                          material="m", v=[[0, 0, 0], [0, 0, 0], [-0.2, 0, 0]])
        return sim

    a = build()
    a.step(250)
    saved = a.state()
    a.step(400)
    b = build()
    b.set_state(saved)
    b.step(400)
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(a.plane_state.point, b.plane_state.point)
    for da, db in zip(a.drivers.items, b.drivers.items):
        np.testing.assert_array_equal(da.state(), db.state())
    assert a.drivers.items[1].position != 0.0          # the free wall moved


def test_servo_plate_presses_a_sphere_to_its_target_force():
    """A mesh plate (force target, projected area by default) squeezes a sphere on a
    floor: at rest the plate carries the target and the floor target + weight."""
    sim = _sim()
    floor = sim.add_plane((0, 0, 0), (0, 0, 1), material="m")
    s = 0.004
    plate = sim.add_mesh_wall([[-s, -s, 0.0021], [s, -s, 0.0021], [s, s, 0.0021],
                               [-s, s, 0.0021]], [[0, 1, 2], [0, 2, 3]], material="m")
    servo = sim.drivers.add(Servo(plate, target=1e-3, max_speed=0.05, direction=(0, 0, -1)))
    assert servo.area == pytest.approx(4 * s * s)
    sim.add_particles([[0, 0, 1e-3]], 1e-3, material="m")
    sim.step(1200)               # touches after ~550 steps (the gap closes at G N_t)
    W = sim.mass[0] * 9.81
    assert servo.normal_force == pytest.approx(1e-3, rel=1e-3)
    assert -floor.force[2] == pytest.approx(1e-3 + W, rel=1e-3)


@pytest.mark.parametrize("zeta", [0.0, 0.1])
def test_free_wall_on_a_spring_and_damper_is_the_damped_oscillator(zeta):
    """No contact (a particle far away), no gravity along the wall's direction: the wall
    is a mass on a spring and damper, x(t) = v0/w_d exp(-zeta w t) sin(w_d t); leapfrog
    (the particles' scheme) is second order, its explicit damper first order in dt."""
    sim = _sim()
    wall = sim.add_plane((0, 0, 0), (1, 0, 0), material="m")
    M, k, v0 = 1e-3, 100.0, 0.01
    w = math.sqrt(k / M)
    c = 2 * zeta * M * w
    fw = sim.drivers.add(FreeWall(wall, mass=M, gravity=sim.g, spring=k, damper=c,
                                  velocity=v0))
    sim.add_particles([[0.01, 0, 0.02]], 1e-3, material="m")
    sim.step(250)                                   # a quarter period at zeta = 0
    wd = w * math.sqrt(1 - zeta ** 2)
    x = v0 / wd * math.exp(-zeta * w * sim.time) * math.sin(wd * sim.time)
    assert fw.position == pytest.approx(x, rel=1e-4 if zeta == 0 else 2e-3)


def test_hinged_free_wall_swings_as_a_pendulum():
    """A plate on a hinge (axis y) with its weight acting r below the axis, I = m r^2: a
    small swing theta = w0/W sin(W t), W = sqrt(m g r/I) = sqrt(g/r)."""
    sim = _sim()
    s = 0.004
    plate = sim.add_mesh_wall([[-s, -s, -s], [s, -s, -s], [s, s, -s], [-s, s, -s]],
                              [[0, 1, 2], [0, 2, 3]], material="m")
    m, r, w0 = 1e-3, 1e-3, 0.099
    fw = sim.drivers.add(FreeWall(plate, inertia=m * r * r, axis=(0, 1, 0), centre=(0, 0, 0),
                                  mass_for_gravity=m, centre_of_mass=(0, 0, -r),
                                  gravity=sim.g, velocity=w0))
    sim.add_particles([[0, 0, 0.015]], 1e-3, material="m")
    W = math.sqrt(9.81 / r)
    sim.step(800)
    assert fw.position == pytest.approx(w0 / W * math.sin(W * sim.time), rel=1e-3)
