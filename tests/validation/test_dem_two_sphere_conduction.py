"""Two touching spheres at fixed overlap, 100 and 0 degC (docs/design.md, "Validation cases", case 4).

Lumped two-body problem with equal m c_p and conductance H:
d(T1 - T2)/dt = -2 H/(m c_p) (T1 - T2), so T1,2 = 50 +- 50 exp(-2 H t/(m c_p)).
The explicit Euler update gives exactly (T1 - T2)_n = 100 (1 - 2 H dt/(m c_p))^n,
compared to round-off; the exponential is matched within the Euler error
n x^2/2 (x = 2 H dt/(m c_p)).  A sphere on a plane at T_w: T_w - T decays with
(1 - H dt/(m c_p))^n, H from the wall contact radius a^2 = 2 R d - d^2.
"""
import math

import numpy as np
import pytest

from gsi.dem import Material, Simulation

D = "docs/design.md"  # where the references are written down

R = 1e-3
# copper heat properties; a soft E (particles are held fixed) keeps dt = 1 us below 0.3 t_R
COPPER = Material(E=1e9, nu=0.34, rho=8960, e=0.5, mu=0.3, k=400.0, cp=385.0)


def _H(model, a2, k=400.0, h_c=0.2):
    kk = 4 * k * k / (2 * k)
    return {"area": kk * math.sqrt(math.pi * a2), "radius": kk * math.sqrt(a2),
            "constant": h_c}[model]


@pytest.mark.parametrize("model", ["area"])
def test_two_spheres_relax_to_mean(model, record_validation):
    dt = 1e-6
    sim = Simulation({"cu": COPPER}, heat=model, h_c=0.2, gravity=(0, 0, 0), dt=dt,
                     skin=1e-4, domain=((-0.01,) * 3, (0.01,) * 3))
    delta = 0.02 * R
    L = 2 * R - delta
    ids = sim.add_particles([[0, 0, 0], [L, 0, 0]], R, material="cu", T=[100.0, 0.0])
    sim.fix(ids)
    a2 = R * R - (L / 2) ** 2
    H = _H(model, a2)
    mc = COPPER.rho * 4 / 3 * math.pi * R ** 3 * COPPER.cp
    x = 2 * H * dt / mc
    assert sim.heat_stability() == pytest.approx(H * dt / mc, rel=1e-12)
    for n in (10000, 30000, 60000):
        sim.step(n - sim.step_count)
        dT = sim.T[0] - sim.T[1]
        record_validation(f"two spheres at fixed overlap ({model}): T1 - T2 after {n} steps",
                          reference=100 * (1 - x) ** n, measured=dT, tolerance=1e-9, unit="K",
                          source=f'{D}, "Validation cases" 4: discrete (1 - 2H dt/mc)^n')
        assert dT == pytest.approx(100 * (1 - x) ** n, rel=1e-9)
        exact = 100 * math.exp(-x * n)
        assert abs(dT - exact) <= exact * (n * x * x / 2 * 1.01) + 1e-12
        assert sim.T.mean() == pytest.approx(50.0, rel=1e-13)
    assert sim.T[0] - sim.T[1] < 90.0            # it did relax
    assert np.all(sim.x == [[0, 0, 0], [L, 0, 0]])  # held in place


def test_sphere_on_hot_plane():
    dt = 1e-6
    sim = Simulation({"cu": COPPER}, heat="area", gravity=(0, 0, 0), dt=dt, skin=1e-4,
                     domain=((-0.01,) * 3, (0.01,) * 3))
    wall = sim.add_plane((0, 0, 0), (0, 0, 1), material="cu", temperature=100.0)
    d = 0.01 * R
    ids = sim.add_particles([[0, 0, R - d]], R, material="cu", T=0.0)
    sim.fix(ids)
    H = _H("area", 2 * R * d - d * d)
    mc = COPPER.rho * 4 / 3 * math.pi * R ** 3 * COPPER.cp
    sim.step(20000)
    assert 100 - sim.T[0] == pytest.approx(100 * (1 - H * dt / mc) ** 20000, rel=1e-9)
    # the heat the plane gave equals the particle's gain
    assert wall.heat_to_particles == pytest.approx(mc * sim.T[0], rel=1e-12)
