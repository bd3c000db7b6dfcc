"""Rolling resistance, constant directional torque (CDT).

Reference: a sphere rolling without slip on a flat plane under gravity with rolling
torque M = mu_r R |F_n| = mu_r R m g opposing its rotation decelerates uniformly,
m a = F_t, I a/R = -R F_t - mu_r R m g  =>  a = -mu_r g/(1 + I/(m R^2)) = -5/7 mu_r g,
and comes to rest (the torque is limited so that it never reverses the rotation).
"""
import math

import numpy as np
import pytest

from gsi.dem import Material, Simulation

D = "docs/design.md"  # where the references are written down

R, G = 1e-3, 9.81


def test_cdt_deceleration_and_stop(record_validation):
    mu_r, v0 = 0.1, 0.05
    mat = {"m": Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.5, mu_r=mu_r)}
    sim = Simulation(mat, rolling=True, gravity=(0, 0, -G), dt=2e-6, skin=2e-4,
                     domain=((-0.01, -0.01, -0.01), (0.05, 0.01, 0.01)))
    sim.add_plane((0, 0, 0), (0, 0, 1), material="m")
    m = 2500 * 4 / 3 * math.pi * R ** 3
    E_eff = 1 / (2 * (1 - 0.09) / 5e6)
    delta = (m * G / (4 / 3 * E_eff * math.sqrt(R))) ** (2 / 3)
    sim.add_particles([[0, 0, R - delta]], R, material="m", v=[[v0, 0, 0]],
                      omega=[[0, v0 / (R - delta), 0]])
    t, vx = [], []
    for _ in range(25):
        sim.step(1000)
        t.append(sim.time)
        vx.append(sim.v[0, 0])
    a = np.polyfit(t, vx, 1)[0]
    record_validation("rolling resistance (constant directional torque): deceleration",
                      reference=-5 / 7 * mu_r * G, measured=a, tolerance=1e-2, unit="m/s^2",
                      source="-5/7 mu_r g")
    assert a == pytest.approx(-5 / 7 * mu_r * G, rel=1e-2)
    sim.step(30000)                    # t = 0.11 s > v0/|a| = 0.073 s
    assert abs(sim.v[0, 0]) < 1e-3 * v0
    assert abs(sim.omega[0, 1]) * R < 1e-3 * v0


def test_no_rolling_resistance_keeps_rolling():
    mat = {"m": Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.5, mu_r=0.1)}
    sim = Simulation(mat, rolling=False, gravity=(0, 0, -G), dt=2e-6, skin=2e-4,
                     domain=((-0.01, -0.01, -0.01), (0.05, 0.01, 0.01)))
    sim.add_plane((0, 0, 0), (0, 0, 1), material="m")
    sim.add_particles([[0, 0, R - 1e-6]], R, material="m", v=[[0.05, 0, 0]],
                      omega=[[0, 0.05 / R, 0]])
    sim.step(20000)
    assert sim.v[0, 0] == pytest.approx(0.05, rel=2e-3)
