"""Size distributions, fills and continuous insertion."""
import math

import numpy as np
import pytest

from gsi.dem import (Box, Cylinder, Discrete, Material, Normal, Simulation, Uniform,
                     lattice_fill, random_fill)
from gsi.dem.insertion import Sphere
from gsi.errors import GsiInputError


def test_distributions_bounds_and_moments():
    rng = np.random.default_rng(0)
    u = Uniform(1e-3, 2e-3).sample(rng, 20000)
    assert u.min() >= 1e-3 and u.max() <= 2e-3 and u.mean() == pytest.approx(1.5e-3, rel=1e-2)
    n = Normal(1e-3, 1e-4, lo=0.9e-3, hi=1.2e-3).sample(rng, 20000)
    assert n.min() >= 0.9e-3 and n.max() <= 1.2e-3
    d = Discrete([1e-3, 2e-3], [3, 1]).sample(rng, 20000)
    assert set(np.unique(d)) == {1e-3, 2e-3}
    assert (d == 1e-3).mean() == pytest.approx(0.75, abs=0.02)
    with pytest.raises(GsiInputError, match="radius"):
        Uniform(2e-3, 1e-3)
    with pytest.raises(GsiInputError, match="weights"):
        Discrete([1e-3], [1, 2])


def test_lattice_fill_spacing_and_bounds():
    x = lattice_fill(Box((0, 0, 0), (1e-2, 1e-2, 5e-3)), 1e-3, spacing=2.5e-3)
    assert len(x) == 4 * 4 * 2
    assert x.min() >= 1e-3 and x[:, :2].max() <= 9e-3


@pytest.mark.parametrize("region", [Box((0, 0, 0), (0.02, 0.02, 0.02)),
                                    Cylinder((0.0, 0.0, 0.0), 0.01, 0.02)])
def test_random_fill_no_overlap_inside(region):
    rng = np.random.default_rng(1)
    x, r = random_fill(region, Uniform(0.8e-3, 1e-3), volume_fraction=0.15, rng=rng)
    vol = (4 / 3 * math.pi * r ** 3).sum()
    assert vol >= 0.15 * region.volume
    d = np.linalg.norm(x[:, None] - x[None], axis=2) + np.eye(len(x))
    assert (d >= (r[:, None] + r[None]) - 1e-15).all()
    if isinstance(region, Cylinder):
        assert (np.hypot(x[:, 0], x[:, 1]) + r <= 0.01 + 1e-12).all()
    else:
        assert ((x - r[:, None]) >= 0).all() and ((x + r[:, None]) <= 0.02).all()


def test_random_fill_too_dense_raises():
    with pytest.raises(GsiInputError, match="random_fill: placed"):
        random_fill(Box((0, 0, 0), (0.01, 0.01, 0.01)), 1e-3, count=400,
                    rng=np.random.default_rng(0), max_tries=50)


def test_inserter_rate_and_max_count():
    sim = Simulation({"m": Material(E=5e6, nu=0.3, rho=2500)}, gravity=(0, 0, 0), dt=1e-5,
                     skin=2e-4, domain=((0, 0, 0), (0.1, 0.1, 0.1)), seed=0)
    ins = sim.add_inserter(Box((0, 0, 0), (0.1, 0.1, 0.1)), 1000.0, radius=1e-3,
                           material="m", velocity=(0, 0, 1e-3), max_count=25)
    sim.step(1550)                  # 15.5 ms -> 15 due
    assert ins.n_attempted == 15 and sim.n == 15
    np.testing.assert_allclose(sim.v, [[0, 0, 1e-3]] * 15)
    sim.step(5000)
    assert ins.n_attempted == 25 and sim.n == 25      # capped


@pytest.mark.parametrize("region", [Cylinder((0.05, 0.02, 0.05), 0.02, 0.06, axis=(0, 1, 0)),
                                    Sphere((0.05, 0.05, 0.05), 0.02)])
def test_inserter_in_any_region_places_whole_spheres_inside(region):
    sim = Simulation({"m": Material(E=5e6, nu=0.3, rho=2500)}, gravity=(0, 0, 0), dt=1e-5,
                     skin=2e-4, domain=((0, 0, 0), (0.1, 0.1, 0.1)), seed=0)
    ins = sim.add_inserter(region, 2e4, radius=Uniform(1e-3, 2e-3), material="m", max_count=40)
    sim.step(300)                   # 3 ms -> 40 due (the cap)
    assert ins.n_attempted == 40 and ins.n_inserted == sim.n > 30
    assert sorted(ins.ids.tolist()) == sorted(sim.ids.tolist())
    if isinstance(region, Sphere):
        d = np.linalg.norm(sim.x - 0.05, axis=1)
        assert (d + sim.radius <= 0.02 + 1e-12).all()
    else:
        rho = np.hypot(sim.x[:, 0] - 0.05, sim.x[:, 2] - 0.05)
        y = sim.x[:, 1] - 0.02
        assert (rho + sim.radius <= 0.02 + 1e-12).all()
        assert (y - sim.radius >= -1e-12).all() and (y + sim.radius <= 0.06 + 1e-12).all()
