"""The pair loop's runs of 64 candidates (gsi/dem/engine.py ``pair_contacts``).

The loop tests a particle's candidates 64 at a time into a bit mask, then computes the
touching ones.  A large sphere among many small ones has more than 64 candidates: here a
fixed sphere of 10 mm with 150 spheres of 1 mm around it, every other one touching
(overlaps 1-100 um) and the rest inside the neighbour skin but apart.  The small spheres
do not reach each other, so each one's force and torque after a step must be those of the
same sphere alone with the big one (one candidate), and the big one counts 75 contacts.
"""
import numpy as np

from gsi.dem import Material, Simulation

R_BIG = 0.01
R = 0.001
MATS = {"m": Material(E=5e6, nu=0.3, rho=2500.0, e=0.5, mu=0.5)}


def shell(n):
    """n small spheres on a Fibonacci spiral around the origin: even ones touching the big
    sphere, odd ones 0.1 mm off it (inside the 0.4 mm skin)."""
    k = np.arange(n) + 0.5
    z = 1.0 - 2.0 * k / n
    phi = np.pi * (1.0 + 5.0 ** 0.5) * k
    u = np.stack([np.sqrt(1.0 - z * z) * np.cos(phi), np.sqrt(1.0 - z * z) * np.sin(phi), z], 1)
    gap = np.where(np.arange(n) % 2 == 0, -np.geomspace(1e-6, 1e-4, n), 1e-4)
    return u * (R_BIG + R + gap)[:, None]


def run(x_small, v_small):
    sim = Simulation(MATS, contact="hertz", gravity=(0.0, 0.0, 0.0), dt=2e-7, skin=0.4 * R,
                     domain=((-0.03,) * 3, (0.03,) * 3))
    sim.add_particles([[0.0, 0.0, 0.0]], R_BIG, material="m")
    sim.fix(sim.ids[:1])
    sim.add_particles(x_small, R, material="m", v=v_small)
    sim.step(3)
    order = np.argsort(sim.ids)
    return sim, sim.force[order], sim.torque[order], sim.ncontact[order]


def test_more_than_64_candidates_match_single_contacts():
    n = 150
    x = shell(n)
    v = np.random.default_rng(3).uniform(-0.01, 0.01, (n, 3))
    sim, f, t, nc = run(x, v)
    counts = np.diff(sim.pairs.start)
    assert counts.max() > 128           # three runs of the mask at the big sphere
    assert nc[0] == n // 2
    assert (nc[1:] == (np.arange(n) % 2 == 0)).all()
    scale = np.abs(f[1:]).max()
    assert scale > 0.0
    for k in range(n):
        _, f1, t1, _ = run(x[k:k + 1], v[k:k + 1])
        assert np.allclose(f[k + 1], f1[1], rtol=1e-12, atol=1e-12 * scale), k
        assert np.allclose(t[k + 1], t1[1], rtol=1e-12, atol=1e-12 * scale * R), k
