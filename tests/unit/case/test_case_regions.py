"""Regions: sampling stays inside every kind and axis, lattice clipping, volume-fraction
fills, and the domain check."""
import math

import numpy as np
import pytest

from gsi.case.regions import Region
from gsi.case.sources import ParticleSource, Size
from gsi.config.schema import load
from gsi.dem.insertion import lattice_capacity, lattice_fill, random_fill
from gsi.errors import GsiInputError

AXES = [(0, 0, 1), (1, 0, 0), (0, -1, 0), (1, 2, -0.5)]


def _cyl_coords(x, centre, axis):
    """Axial coordinate s and distance rho from the axis, computed here independently."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    d = x - np.asarray(centre, float)
    s = d @ a
    rho = np.sqrt(np.maximum((d * d).sum(1) - s * s, 0.0))
    return s, rho


@pytest.mark.parametrize("axis", AXES)
def test_cylinder_sampling_inside_any_axis(axis):
    reg = Region.cylinder((0.1, -0.2, 0.3), 0.02, 0.05, axis=axis)
    rng = np.random.default_rng(3)
    r = rng.uniform(1e-3, 4e-3, 20000)
    x = reg.sample(rng, r)
    s, rho = _cyl_coords(x, reg.centre, axis)
    assert (rho + r <= 0.02 + 1e-12).all()
    assert (s - r >= -1e-12).all() and (s + r <= 0.05 + 1e-12).all()
    # uniform in the allowed region: the axial mean of equal radii sits mid-length,
    # and half the points lie within radius (R - r)/sqrt(2) of the axis
    r0 = np.full(20000, 2e-3)
    s0, rho0 = _cyl_coords(reg.sample(rng, r0), reg.centre, axis)
    assert s0.mean() == pytest.approx(0.025, abs=3e-4)
    assert (rho0 < 0.018 / math.sqrt(2)).mean() == pytest.approx(0.5, abs=0.015)
    lo, hi = reg.bounds()
    assert (x - r[:, None] >= lo - 1e-12).all() and (x + r[:, None] <= hi + 1e-12).all()
    assert reg.contains(x, r).all()
    assert not reg.contains(reg.centre + 0.03 * np.cross(reg.shape.axis, reg.shape.e1)[None], 0.0).any()


def test_box_and_sphere_sampling_inside():
    rng = np.random.default_rng(4)
    r = rng.uniform(1e-3, 3e-3, 20000)
    box = Region.box((0, 0, 0), (0.02, 0.03, 0.01))
    x = box.sample(rng, r)
    assert ((x - r[:, None]) >= 0).all() and ((x + r[:, None]) <= [0.02, 0.03, 0.01]).all()
    sph = Region.sphere((0.5, 0.5, 0.5), 0.01)
    x = sph.sample(rng, r)
    d = np.linalg.norm(x - 0.5, axis=1)
    assert (d + r <= 0.01 + 1e-12).all()
    # uniform in the ball of radius R - r: P(d < (R - r)/2) = 1/8
    x0 = sph.sample(rng, np.full(20000, 2e-3))
    assert (np.linalg.norm(x0 - 0.5, axis=1) < 0.004).mean() == pytest.approx(0.125, abs=0.01)
    assert sph.volume == pytest.approx(4 / 3 * math.pi * 1e-6)


@pytest.mark.parametrize("region", [Region.cylinder((0, 0, 0), 0.01, 0.02, axis=(1, 1, 0)),
                                    Region.sphere((0, 0, 0), 0.012)])
def test_lattice_fill_is_the_box_lattice_clipped(region):
    r = 1e-3
    x = lattice_fill(region.shape, r)
    assert region.contains(x, r).all()
    # the clipped lattice keeps every site of the bounding-box lattice that fits
    lo, hi = region.bounds()
    axes = [np.arange(a + r, b - r + 1e-15, 2.02 * r) for a, b in zip(lo, hi)]
    full = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
    assert len(x) == int(region.contains(full, r).sum()) > 100
    d = np.linalg.norm(x[:, None] - x[None], axis=2) + np.eye(len(x))
    assert d.min() >= 2 * r
    assert lattice_capacity(region.shape, r) == len(x)


def test_lattice_capacity_of_a_box_counts_sites():
    box = Region.box((0, 0, 0), (0.0203, 0.0101, 0.005))
    assert lattice_capacity(box.shape, 1e-3) == len(lattice_fill(box.shape, 1e-3))


@pytest.mark.parametrize("region", [Region.box((0, 0, 0), (0.03, 0.03, 0.03)),
                                    Region.cylinder((0, 0, 0), 0.017, 0.03, axis=(0, 1, 0)),
                                    Region.sphere((0, 0, 0), 0.019)])
def test_volume_fraction_fill_gives_the_fraction(region):
    phi = 0.2
    x, r = random_fill(region.shape, Size(kind="uniform", min=0.8e-3, max=1.2e-3).distribution(),
                       volume_fraction=phi, rng=np.random.default_rng(5))
    got = (4 / 3 * math.pi * r ** 3).sum() / region.volume
    # the fill stops at the first particle that reaches the target: overshoot < one particle
    assert phi <= got <= phi + 4 / 3 * math.pi * 1.2e-3 ** 3 / region.volume
    assert region.contains(x, r).all()


def test_volume_fraction_source_lattice_and_random():
    from gsi.dem import Material, Simulation
    sim = Simulation({"m": Material(E=5e6, nu=0.3, rho=2500)}, dt=1e-5, skin=2e-4,
                     domain=((-0.05,) * 3, (0.05,) * 3))
    reg = {"kind": "sphere", "centre": [0, 0, 0], "radius": 0.02}
    size = {"kind": "normal", "mean": 1e-3, "std": 1e-4}
    src = load(ParticleSource, dict(material="m", fill="random", volume_fraction=0.15,
                                    region=reg, size=size), "particles[0]")
    ids = src.add_to(sim, rng=np.random.default_rng(0))
    got = (4 / 3 * math.pi * sim.radius ** 3).sum() / src.region.volume
    assert len(ids) == sim.n and got == pytest.approx(0.15, abs=4 / 3 * math.pi * 1.3e-9 / src.region.volume)
    assert len(ids) == pytest.approx(src.planned_count(), rel=0.05)
    lat = load(ParticleSource, dict(material="m", fill="lattice", count=50,
                                    region={"kind": "box", "lo": [0.025, -0.02, -0.02],
                                            "hi": [0.045, 0.02, 0.02]},
                                    size={"kind": "single", "radius": 1e-3}), "particles[1]")
    ids2 = lat.add_to(sim, rng=np.random.default_rng(0))
    z = sim.x[sim.index(ids2), 2]
    # filled from the bottom: 50 sites of a 9 x 19 layer all sit in the lowest layer
    assert len(ids2) == 50 and np.ptp(z) == 0.0 and z[0] == pytest.approx(-0.019)


def test_region_keys_and_domain_check():
    with pytest.raises(GsiInputError, match=r"^particles\[0\]\.region\.length: missing"):
        load(Region, {"kind": "cylinder", "centre": [0, 0, 0], "radius": 1.0}, "particles[0].region")
    with pytest.raises(GsiInputError, match=r"^region\.lo: not a key of a sphere region"):
        load(Region, {"kind": "sphere", "centre": [0, 0, 0], "radius": 1.0, "lo": [0, 0, 0]}, "region")
    reg = Region.cylinder((0, 0, 0.05), 0.02, 0.1, axis=(0, 0, 1))
    with pytest.raises(GsiInputError, match=r"^particles\[2\]\.region\.centre = .*outside dem\.domain"):
        reg.check("particles[2].region", domain_lo=(-0.1, -0.1, 0), domain_hi=(0.1, 0.1, 0.1))
    reg.check("particles[2].region", domain_lo=(-0.1, -0.1, 0), domain_hi=(0.1, 0.1, 0.2))
    big = Region.sphere((0, 0, 0), 50.0)
    with pytest.raises(GsiInputError, match=r"^r\.radius: .*did you give mm\? lengths are in m"):
        big.check("r", domain_lo=(-0.1,) * 3, domain_hi=(0.1,) * 3)
