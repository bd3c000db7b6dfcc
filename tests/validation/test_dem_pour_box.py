"""A pour into a box comes to rest with no particle escaping."""

from gsi.dem import Box, Material, Simulation, Uniform


def test_pour_comes_to_rest():
    L = 0.012
    sim = Simulation({"m": Material(E=5e6, nu=0.3, rho=2500, e=0.3, mu=0.5)},
                     gravity=(0, 0, -9.81), dt=2e-6, skin=2e-4,
                     domain=((0, 0, 0), (L, L, 0.04)), seed=3)
    for p, n in [((0, 0, 0), (0, 0, 1)), ((0, 0, 0), (1, 0, 0)), ((L, 0, 0), (-1, 0, 0)),
                 ((0, 0, 0), (0, 1, 0)), ((0, L, 0), (0, -1, 0))]:
        sim.add_plane(p, n, material="m")
    ins = sim.add_inserter(Box((0, 0, 0.02), (L, L, 0.03)), 20000.0,
                           radius=Uniform(0.6e-3, 0.8e-3), material="m",
                           velocity=(0, 0, -0.5), max_count=120)
    ke_max = 0.0
    for _ in range(30):
        sim.step(2500)
        ke_max = max(ke_max, sim.kinetic_energy())
    assert ins.n_attempted == 120 and sim.n == ins.n_inserted > 100
    assert sim.n_lost == 0
    assert sim.kinetic_energy() < 1e-4 * ke_max
    lo = sim.x - sim.radius[:, None]
    hi = sim.x + sim.radius[:, None]
    tol = 0.05 * sim.radius.min()         # contact overlaps are tiny
    assert (lo > -tol).all() and (hi[:, :2] < L + tol).all()
    assert (sim.x[:, 2] < 0.012).all()    # all fell into the box
