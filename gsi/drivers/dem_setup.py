"""Build a :class:`gsi.dem.Simulation` from a validated case (materials, particles, walls).

Shared by every driver: the case's ``[dem]``, ``[materials.*]``, ``[[particles]]`` and
``[[walls]]`` tables mean the same thing in a pour, a hopper or a silo case.
"""
from __future__ import annotations

import math
import warnings

import numpy as np

from gsi.errors import GsiInputError


def make_material(m):
    from gsi.dem.materials import Material
    return Material(E=m.E, nu=m.nu, rho=m.rho, e=m.e, mu=m.mu, mu_r=m.mu_r, k=m.k, cp=m.cp)


def size_distribution(size):
    from gsi.dem import distributions as d
    if size.kind == "single":
        return d.Constant(size.radius)
    if size.kind == "uniform":
        return d.Uniform(size.min, size.max)
    if size.kind == "normal":
        return d.Normal(size.mean, size.std, lo=size.smallest, hi=size.largest)
    return d.Discrete(np.asarray(size.values), np.asarray(size.weights))


def smallest_radius(case) -> float:
    return min(p.size.smallest for p in case.particles) if case.particles else math.inf


def default_dt(case) -> float:
    """0.2 x the smallest Rayleigh time over the particle sources (s)."""
    from gsi.dem.materials import rayleigh_time
    return 0.2 * min(rayleigh_time(p.size.smallest, make_material(case.materials[p.material]))
                     for p in case.particles)


def check_dt(case) -> float:
    """The time step the case will use; raise GsiInputError above the Rayleigh time."""
    from gsi.dem.materials import rayleigh_time
    dt = case.run.dt if case.run.dt is not None else default_dt(case)
    for i, p in enumerate(case.particles):
        m = case.materials[p.material]
        t_r = rayleigh_time(p.size.smallest, make_material(m))
        if dt > t_r and not case.dem.force_dt:
            raise GsiInputError(
                f"run.dt = {dt:g}: must be <= the Rayleigh time {t_r:.3g} s of particles[{i}] "
                f"(r = {p.size.smallest:g} m); use dt <= {0.2 * t_r:.3g} or set dem.force_dt = true")
        if dt > 0.3 * t_r:
            warnings.warn(f"run.dt = {dt:g} s is above 0.3 x the Rayleigh time {t_r:.3g} s of "
                          f"particles[{i}]: contacts are resolved coarsely; "
                          f"dt <= {0.2 * t_r:.3g} s is safe", stacklevel=2)
    return dt


def build_simulation(case, *, dt: float | None = None, seed: int | None = None):
    """A Simulation with the case's materials, walls and initial particles (streams are
    registered as inserters)."""
    from gsi.dem import insertion
    from gsi.dem.simulation import Simulation

    dt = check_dt(case) if dt is None else dt
    if case.run.threads:
        import numba
        numba.set_num_threads(min(case.run.threads, numba.config.NUMBA_NUM_THREADS))
    rng = np.random.default_rng(case.run.seed if seed is None else seed)
    r_min = smallest_radius(case)
    skin = case.dem.skin if case.dem.skin is not None else 0.4 * r_min
    sim = Simulation(
        materials={name: make_material(m) for name, m in case.materials.items()},
        contact=case.dem.contact, k_n=case.dem.k_n, rolling=case.dem.rolling,
        heat=None if case.dem.heat == "none" else case.dem.heat, h_c=case.dem.h_c,
        gravity=case.dem.gravity, dt=dt, skin=skin,
        domain=(case.dem.domain_lo, case.dem.domain_hi), force_dt=case.dem.force_dt,
        seed=case.run.seed if seed is None else seed)

    for w in case.walls:
        kw = dict(material=w.material, temperature=w.temperature)
        if w.kind == "plane":
            sim.add_plane(w.point, w.normal, velocity=w.velocity, **kw)
        elif w.kind == "box":
            lo, hi = np.asarray(w.lo), np.asarray(w.hi)
            planes = [(lo, (0, 0, 1)), (lo, (1, 0, 0)), (hi, (-1, 0, 0)), (lo, (0, 1, 0)),
                      (hi, (0, -1, 0))] + ([(hi, (0, 0, -1))] if w.lid else [])
            for point, normal in planes:
                sim.add_plane(point, normal, **kw)
        else:
            wall = sim.add_mesh_wall_file(case.base_dir / w.file, scale=w.scale,
                                          material=w.material)
            if any(w.velocity) or any(w.omega):
                wall.set_motion(velocity=w.velocity, omega=w.omega, centre=w.centre)

    for i, p in enumerate(case.particles):
        dist = size_distribution(p.size)
        reg = p.region
        region = (insertion.Box(reg.lo, reg.hi) if reg.kind == "box" else
                  insertion.Cylinder(reg.centre, reg.radius, reg.height))
        if p.fill == "stream":
            sim.add_inserter(region, p.rate, radius=dist, material=p.material,
                             velocity=p.velocity, T=p.temperature, max_count=p.count)
            continue
        if p.fill == "lattice":
            if reg.kind != "box":
                raise GsiInputError(f"particles[{i}].fill = 'lattice': needs a box region")
            x = insertion.lattice_fill(region, p.size.largest)
            if p.count is not None:
                x = x[:p.count]
            r = dist.sample(rng, len(x))
        else:
            x, r = insertion.random_fill(region, dist, count=p.count, rng=rng,
                                         existing_x=sim.x, existing_r=sim.radius)
        v = np.tile(np.asarray(p.velocity, dtype=float), (len(x), 1))
        sim.add_particles(x, r, material=p.material, v=v,
                          T=np.full(len(x), p.temperature))
    return sim
