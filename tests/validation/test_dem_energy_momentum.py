"""Conservation checks (docs/design.md, "Validation cases", case 2 and the momentum check of issue 3).

- e = 1, mu = 0: the total energy of particles bouncing in a closed box of planes,
  kinetic + gravitational + elastic (Hertz potential 8/15 E* sqrt(R*) delta^(5/2) of
  each contact), is constant (velocity Verlet keeps the error bounded and small).
- Particle–particle collisions only (no walls, no gravity), with damping, friction and
  rolling resistance: each pair force acts once with opposite signs on the two
  particles and the torques balance about any point (lever arms R - delta/2 on a line
  of length R_i + R_j - delta), so total linear and angular momentum are constant to
  round-off.
"""
import numpy as np
import pytest

from gsi.dem import Box, Material, Simulation, random_fill

D = "docs/design.md"  # where the references are written down


L = 8e-3
E_MOD, NU = 5e6, 0.3


def elastic_energy(sim):
    """Hertz potential of all pair and plane contacts (J)."""
    E_eff = 1 / (2 * (1 - NU ** 2) / E_MOD)
    x, r = sim.x, sim.radius
    U = 0.0
    for i in range(sim.n):
        for j in range(i + 1, sim.n):
            d = r[i] + r[j] - np.linalg.norm(x[j] - x[i])
            if d > 0:
                U += 8 / 15 * E_eff * np.sqrt(r[i] * r[j] / (r[i] + r[j])) * d ** 2.5
        for ax in range(3):
            for d in (r[i] - x[i, ax], r[i] - (L - x[i, ax])):
                if d > 0:
                    U += 8 / 15 * E_eff * np.sqrt(r[i]) * d ** 2.5
    return U


def total_energy(sim):
    return sim.kinetic_energy() + sim.potential_energy() + elastic_energy(sim)


def _box_sim(gravity, e=1.0, mu=0.0, **kw):
    mat = {"m": Material(E=E_MOD, nu=NU, rho=2500, e=e, mu=mu, **kw)}
    sim = Simulation(mat, gravity=gravity, dt=2e-6, skin=2e-4,
                     domain=((-1e-3,) * 3, (L + 1e-3,) * 3))
    for ax in range(3):
        nrm = np.zeros(3)
        nrm[ax] = 1
        sim.add_plane(np.zeros(3), nrm, material="m")
        sim.add_plane(np.full(3, L), -nrm, material="m")
    rng = np.random.default_rng(1)
    x, r = random_fill(Box((0, 0, 0), (L, L, L)), 0.7e-3, count=20, rng=rng)
    sim.add_particles(x, r, material="m", v=rng.normal(0, 0.3, (20, 3)))
    return sim


@pytest.mark.parametrize("gravity", [(0, 0, 0), (0, 0, -9.81)], ids=["no_gravity", "gravity"])
def test_energy_constant_elastic_frictionless(gravity, record_validation):
    sim = _box_sim(gravity)
    E0 = total_energy(sim)
    contacts = 0
    for _ in range(40):
        sim.step(500)
        contacts += sim.contact_count()
    E1 = total_energy(sim)
    record_validation(f"energy drift, e = 1, mu = 0 ({'gravity' if gravity[2] else 'no gravity'})",
                      reference=E0, measured=E1, tolerance=1e-4, unit="J",
                      source=f'{D}, "Validation cases" 2')
    assert contacts > 0                       # collisions did happen
    assert sim.n_rebuilds > 5
    assert abs(E1 - E0) / E0 < 1e-4


def test_momentum_conserved_pair_collisions():
    mat = {"m": Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.5, mu_r=0.1)}
    sim = Simulation(mat, rolling=True, gravity=(0, 0, 0), dt=2e-6, skin=2e-4,
                     domain=((-0.1,) * 3, (0.1,) * 3))
    rng = np.random.default_rng(2)
    x, r = random_fill(Box((-4e-3,) * 3, (4e-3,) * 3), 0.6e-3, count=30, rng=rng)
    v = -x / np.linalg.norm(x, axis=1)[:, None] * 0.5 + rng.normal(0, 0.1, x.shape)
    sim.add_particles(x, r, material="m", v=v, omega=rng.normal(0, 50, x.shape))

    def momenta():
        m, I = sim.mass, 0.4 * sim.mass * sim.radius ** 2
        p = (m[:, None] * sim.v).sum(0)
        L = (np.cross(sim.x, m[:, None] * sim.v) + I[:, None] * sim.omega).sum(0)
        return p, L, (m * np.linalg.norm(sim.v, axis=1)).sum()

    p0, L0, scale = momenta()
    contacts = 0
    for _ in range(20):
        sim.step(250)
        contacts += sim.contact_count()
    p1, L1, _ = momenta()
    assert contacts > 20
    assert sim.kinetic_energy() < 0.9 * 0.5 * (sim.mass * (v ** 2).sum(1)).sum()  # dissipative
    np.testing.assert_allclose(p1, p0, atol=1e-12 * scale)
    np.testing.assert_allclose(L1, L0, atol=1e-12 * scale * 0.01)
