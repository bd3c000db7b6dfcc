"""Neighbour lists against brute force; contact history survives rebuilds and deletions."""
import numpy as np

from gsi.dem import Box, Material, Simulation, random_fill

MAT = {"m": Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.9)}


def test_half_list_equals_brute_force():
    L = 0.018
    sim = Simulation(MAT, gravity=(0, 0, 0), dt=2e-6, skin=3e-4, domain=((0, 0, 0), (L, L, L)))
    rng = np.random.default_rng(0)
    x, r = random_fill(Box((0, 0, 0), (L, L, L)), 1e-3, count=220, rng=rng)
    sim.add_particles(x, r * rng.uniform(0.8, 1.0, len(r)), material="m",
                      v=rng.normal(0, 0.5, x.shape))
    sim.step(200)
    nb_start, nb_j = sim._nb[2], sim._nb[3]
    got = [(i, int(j)) for i in range(sim.n) for j in nb_j[nb_start[i]:nb_start[i + 1]]]
    assert len(got) == len(set(got))                  # each pair once
    got = {(min(i, j), max(i, j)) for i, j in got}
    x0, r = sim._a["x0"][: sim.n], sim.radius      # the list is built at x0
    d = np.linalg.norm(x0[:, None] - x0[None], axis=2)
    want = {(i, j) for i in range(sim.n) for j in range(i + 1, sim.n)
            if d[i, j] < r[i] + r[j] + sim.skin}
    assert sim.n_rebuilds > 1
    assert got == want and len(want) > 40


def test_history_survives_rebuild_and_deletion():
    """Sheared touching pairs build springs; deleting an idle particle (rows shift) and
    rebuilding keeps every spring attached to the same pair of ids."""
    R, d = 1e-3, 2e-5
    L = 0.05
    sim = Simulation(MAT, gravity=(0, 0, 0), dt=2e-6, skin=3e-4, domain=((0, 0, 0), (L, L, L)))
    x, v = [], []
    for k in range(20):
        base = np.array([0.004 + 0.006 * (k % 5), 0.01 + 0.008 * (k // 5), 0.02])
        x += [base + [0, 0, 0.005], base, base + [2 * R - d, 0, 0]]   # idle one first
        v += [[0, 0, 0], [0, 0.01, 0], [0, -0.01, 0.0]]
    sim.add_particles(np.array(x), R, material="m", v=np.array(v))
    sim.step(50)

    def springs():
        nb_start, nb_j, hist, pact = sim._nb[2:6]
        ids = sim.ids
        return {(int(ids[i]), int(ids[nb_j[k]])): hist[k].copy()
                for i in range(sim.n) for k in range(nb_start[i], nb_start[i + 1]) if pact[k]}

    before = springs()
    assert len(before) == 20 and all(np.abs(h).max() > 0 for h in before.values())
    rb = sim.n_rebuilds
    sim._delete(np.isin(sim.ids, [0, 3, 30]))     # three idle particles
    sim._rebuild()
    after = springs()
    assert sim.n_rebuilds == rb + 1
    assert set(after) == set(before)
    for key, h in before.items():
        np.testing.assert_array_equal(after[key], h)
