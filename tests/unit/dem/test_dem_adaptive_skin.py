"""The adaptive skin (gsi.dem.lists.adaptive_skin): fewer list builds, the same contacts."""
import numpy as np

from gsi.dem import Material, Simulation
from gsi.dem.lists import STEPS_PER_BUILD, adaptive_skin

MAT = Material(E=1e7, nu=0.3, rho=2500.0, e=0.5, mu=0.5)


def test_adaptive_skin_rule():
    v = np.array([[0.0, 0.0, -2.0], [0.1, 0.0, 0.0]])
    dt = 1e-5
    assert adaptive_skin(1e-4, 1e-4, dt, v) == 1e-4                  # fixed
    assert adaptive_skin(1e-4, 1e-3, dt, v) == 2 * STEPS_PER_BUILD * 2.0 * dt
    assert adaptive_skin(1e-4, 3e-4, dt, v) == 3e-4                  # capped
    assert adaptive_skin(1e-4, 1e-3, dt, np.zeros((2, 3))) == 1e-4   # at rest
    wall = np.array([[5.0, 0.0, 0.0]])                               # a fast wall counts
    assert adaptive_skin(1e-4, 1e-3, dt, v, wall) == 1e-3


def _rain(skin_max):
    """Spheres falling onto a moving triangulated floor: positions after 400 steps."""
    sim = Simulation({"m": MAT}, gravity=(0, 0, -9.81), dt=2e-6, skin=4e-5, skin_max=skin_max,
                     domain=((0, 0, -0.01), (0.02, 0.02, 0.03)), seed=3)
    rng = np.random.default_rng(5)
    g = np.stack(np.meshgrid(np.arange(4), np.arange(4), np.arange(3), indexing="ij"), -1)
    x = g.reshape(-1, 3) * 2.5e-3 + [4e-3, 4e-3, 1.2e-3] + rng.uniform(-2e-4, 2e-4, (48, 3))
    sim.add_particles(x, 1e-3, material="m", v=np.tile([0.0, 0.0, -5.0], (48, 1)))
    floor = np.array([[0, 0, 0], [0.02, 0, 0], [0.02, 0.02, 0], [0, 0.02, 0]], float)
    wall = sim.add_mesh_wall(floor, np.array([[0, 1, 2], [0, 2, 3]]), material="m")
    wall.set_motion(velocity=(0.05, 0.0, 0.0))
    sim.step(400)
    return sim


def test_adaptive_skin_builds_less_and_finds_the_same_contacts():
    fixed, adaptive = _rain(None), _rain(1e-3)
    assert adaptive.n_rebuilds < fixed.n_rebuilds / 3
    assert fixed.contact_count() == adaptive.contact_count()
    # the same trajectories up to the summation order of the forces
    np.testing.assert_allclose(adaptive.x, fixed.x, rtol=0, atol=1e-9)
