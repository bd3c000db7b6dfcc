"""Sphere on an incline (docs/design.md, "Validation cases", case 3), gravity tilted by theta.

References: a solid sphere rolls without slip with a = 5/7 g sin(theta) when
tan(theta) <= 7/2 mu; otherwise it slides with a = g (sin(theta) - mu cos(theta)).
The sphere starts at rest at its static Hertz overlap; a is twice the quadratic
coefficient of a least-squares fit of x(t).
"""
import math

import numpy as np
import pytest

from gsi.dem import Material, Simulation

D = "docs/design.md"  # where the references are written down

R, RHO, E, NU, G = 1e-3, 2500.0, 5e6, 0.3, 9.81


def roll(theta_deg, mu, t_end=0.08):
    th = math.radians(theta_deg)
    mat = {"m": Material(E=E, nu=NU, rho=RHO, e=0.5, mu=mu)}
    g = (G * math.sin(th), 0.0, -G * math.cos(th))
    sim = Simulation(mat, gravity=g, dt=2e-6, skin=2e-4,
                     domain=((-0.01, -0.01, -0.01), (0.1, 0.01, 0.01)))
    sim.add_plane((0, 0, 0), (0, 0, 1), material="m")
    m = RHO * 4 / 3 * math.pi * R ** 3
    E_eff = 1 / (2 * (1 - NU ** 2) / E)
    delta = (m * G * math.cos(th) / (4 / 3 * E_eff * math.sqrt(R))) ** (2 / 3)
    sim.add_particles([[0, 0, R - delta]], R, material="m")
    t, xs = [], []
    n = int(round(t_end / sim.dt / 40))
    for _ in range(40):
        sim.step(n)
        t.append(sim.time)
        xs.append(sim.x[0, 0])
    t, xs = np.array(t), np.array(xs)
    keep = t > 0.2 * t_end
    a = 2 * np.polyfit(t[keep], xs[keep], 2)[0]
    return a, sim


def test_rolling_without_slip(record_validation):
    a, sim = roll(20.0, 0.5)
    record_validation("incline 20 deg, rolling without slip: acceleration",
                      reference=5 / 7 * G * math.sin(math.radians(20)), measured=a,
                      tolerance=1e-2, unit="m/s^2", source=f'{D}, "Validation cases" 3: 5/7 g sin(theta)')
    assert a == pytest.approx(5 / 7 * G * math.sin(math.radians(20)), rel=1e-2)
    # no slip: the contact point is at rest, v_x = omega_y R
    assert sim.omega[0, 1] * R == pytest.approx(sim.v[0, 0], rel=1e-2)


def test_sliding(record_validation):
    th = math.radians(30)
    a, sim = roll(30.0, 0.1)
    record_validation("incline 30 deg, mu 0.1, sliding: acceleration",
                      reference=G * (math.sin(th) - 0.1 * math.cos(th)), measured=a,
                      tolerance=1e-2, unit="m/s^2",
                      source=f'{D}, "Validation cases" 3: g (sin(theta) - mu cos(theta))')
    assert a == pytest.approx(G * (math.sin(th) - 0.1 * math.cos(th)), rel=1e-2)
    assert sim.omega[0, 1] * R < 0.9 * sim.v[0, 0]     # it slips
