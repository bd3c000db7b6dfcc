"""The simulation's public bookkeeping: removed and lost particles, a mesh wall moved
between steps (the step loop rebuilds the lists when a vertex moved half the skin)."""
import numpy as np

from gsi.dem import Material, Simulation

MAT = {"m": Material(E=5e6, nu=0.3, rho=2500)}
DOM = ((0, 0, 0), (0.02, 0.02, 0.02))
SKIN = 4e-4


def _sim():
    sim = Simulation(MAT, dt=1e-5, skin=SKIN, domain=DOM, gravity=(0, 0, 0))
    sim.add_particles([[0.005, 0.005, 0.01], [0.015, 0.015, 0.01]], 1e-3, material="m")
    return sim


def test_removed_particles_count_as_lost_only_when_said():
    sim = _sim()
    sim.remove_particles([True, False])
    assert sim.n == 1 and sim.n_lost == 0
    sim.remove_particles([True], lost=True)
    assert sim.n == 0 and sim.n_lost == 1


def test_a_wall_moved_half_the_skin_rebuilds_the_lists_at_the_next_step():
    sim = _sim()
    x = np.array([[0.0, 0.0, 0.002], [0.02, 0.0, 0.002], [0.0, 0.02, 0.002]])
    wall = sim.add_mesh_wall(x, [[0, 1, 2]], material="m")
    sim.step(1)
    assert sim.n_rebuilds == 1
    wall.set_vertices(x + [0.0, 0.0, 0.4 * SKIN])      # within half the skin: lists stand
    sim.step(1)
    assert sim.n_rebuilds == 1
    wall.set_vertices(x + [0.0, 0.0, 0.6 * SKIN])      # beyond: rebuilt before the step
    assert sim.n_rebuilds == 1
    sim.step(1)
    assert sim.n_rebuilds == 2
    assert np.array_equal(sim.mesh_state.x0, sim.mesh_state.x)
