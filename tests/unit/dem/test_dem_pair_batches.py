"""The engine's batched pair pass (gsi/dem/engine.py ``slab_task``: ``gather_row``,
``batch_laws``, ``finish_batch``) against the one-pair-at-a-time ``pair_contacts``.

The batched pass evaluates the laws of up to ``CH`` touching pairs in one vectorized loop
and then adds each pair to both particles in the order of ``pair_contacts``, so the forces,
torques, heat rates, contact counts and springs must be the same bits as a reference pass
that calls ``pair_contacts`` row by row in the same order (slabs of the first colour,
then of the second; within a slab, its rows in order).  The bed mixes two materials at
random (runs of different pair-table rows in a batch), has rolling resistance and heat
conduction on, and holds one large sphere with more candidates than a batch has lanes
(its row takes ``pair_contacts`` inside the engine as well).  The state is that of a
running bed (100 steps), so the springs are not zero.
"""
import numpy as np
import pytest

from gsi.dem import Material, Simulation
from gsi.dem.integrate import clear_forces

R_BIG = 0.008
MATS = {"a": Material(E=5e6, nu=0.3, rho=2500.0, e=0.5, mu=0.5, mu_r=0.1, k=1.0, cp=800.0),
        "b": Material(E=2e7, nu=0.25, rho=1500.0, e=0.7, mu=0.3, mu_r=0.05, k=5.0, cp=500.0)}


def bed(contact, rolling, heat):
    """A polydisperse bed of two materials around an 8 mm sphere with a shell of 110
    small spheres on it (every other one touching): added first, the big sphere holds
    all its pairs (one slab: the lower row stores a pair)."""
    sim = Simulation(MATS, contact=contact, rolling=rolling, heat=heat, gravity=(0, 0, -9.81),
                     dt=1e-6, skin=4e-4, domain=((0, 0, 0), (0.03, 0.03, 0.1)),
                     **({"k_n": 2e3} if contact == "linear" else {}))
    c = np.array([0.015, 0.015, 0.015])
    sim.add_particles([c], R_BIG, material="a", T=350.0)
    n = 110
    k = np.arange(n) + 0.5
    z = 1.0 - 2.0 * k / n
    phi = np.pi * (1.0 + 5.0 ** 0.5) * k
    u = np.stack([np.sqrt(1.0 - z * z) * np.cos(phi), np.sqrt(1.0 - z * z) * np.sin(phi), z], 1)
    gap = np.where(np.arange(n) % 2 == 0, -np.geomspace(1e-6, 1e-4, n), 1e-4)
    shell = c + u * (R_BIG + 0.001 + gap)[:, None]
    g = np.stack(np.meshgrid(np.arange(10), np.arange(10), np.arange(12), indexing="ij"),
                 -1).reshape(-1, 3)
    x = 0.0015 + 0.0027 * g + np.random.default_rng(1).uniform(-2e-4, 2e-4, g.shape)
    x = np.concatenate([shell, x[np.linalg.norm(x - c, axis=1) > R_BIG + 0.0035]])
    r = np.concatenate([np.full(n, 0.001),
                        np.random.default_rng(2).uniform(0.0009, 0.0013, len(x) - n)])
    kind = np.random.default_rng(3).integers(0, 2, len(x))
    T = np.random.default_rng(4).uniform(300.0, 400.0, len(x))
    v = np.random.default_rng(5).uniform(-0.05, 0.05, x.shape)
    for m, name in enumerate(MATS):
        sel = kind == m
        sim.add_particles(x[sel], r[sel], material=name, v=v[sel], T=T[sel])
    sim.step(100)                 # contacts with springs and rotation
    return sim


def reference_pass(sim):
    """``compute_forces`` with the pair contacts taken one at a time (no walls here)."""
    E = sim.engine
    P, pairs = sim.particles, sim.pairs
    nt = sim.table.shape[0]
    tab = sim.table.reshape((nt * nt, sim.table.shape[2]))
    clear_forces(P, *sim.g)
    nslab = len(pairs.slab_start) - 1
    for colour in range(2):
        for sl in range(colour, nslab, 2):
            for i in pairs.slab_list[pairs.slab_start[sl]:pairs.slab_start[sl + 1]]:
                fx, fy, fz, tx, ty, tz, qi, nc = E.pair_contacts(i, P, pairs, tab,
                                                                 P.type[i] * nt, 0.0)
                P.ncontact[i] += nc
                P.force[i] += (fx, fy, fz)
                P.torque[i] += (tx, ty, tz)
                P.q[i] += qi


@pytest.mark.parametrize("contact,rolling,heat", [("hertz", True, "area"),
                                                  ("linear", False, "radius")])
def test_batched_pairs_are_bitwise_the_single_pairs(contact, rolling, heat):
    sim = bed(contact, rolling, heat)
    P, pairs = sim.particles, sim.pairs
    assert len(sim.plane_state.point) == 0 and len(sim.mesh_state.tri) == 0
    CH = sim.engine.CH
    counts = np.diff(pairs.start)
    assert counts.max() > CH                              # the big sphere's own path
    assert (counts[counts <= CH] > 0).sum() > 100         # and many batched rows
    assert len(np.unique(P.type)) == 2
    assert np.abs(pairs.hist).max() > 0.0                 # springs in play
    state = [a.copy() for a in (*P, *pairs)]

    def restore():
        for a, b in zip((*P, *pairs), state):
            a[...] = b

    sim.engine.compute_forces(sim.g, *sim._bundles(), sim.table)
    got = [a.copy() for a in (P.force, P.torque, P.q, P.ncontact, pairs.hist, pairs.active)]
    restore()
    reference_pass(sim)
    want = [P.force, P.torque, P.q, P.ncontact, pairs.hist, pairs.active]
    for name, a, b in zip(("force", "torque", "q", "ncontact", "hist", "active"), got, want):
        assert np.array_equal(a, b), name
    assert np.abs(P.q).max() > 0.0 and P.ncontact[0] >= 10    # the big sphere touches
