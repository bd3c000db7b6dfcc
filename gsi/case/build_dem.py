"""The DEM of a case: :func:`build_simulation` (its materials, walls and particles)."""
from __future__ import annotations

import numpy as np


def build_simulation(case, *, dt: float):
    """The DEM of a case: materials, walls (with their motions at t = 0) and particles.

    Returns ``(sim, wall_handles, groups)``: ``wall_handles`` maps each ``[[walls]]`` name
    to the DEM walls it made, ``groups`` each ``[[particles]]`` name to its ids (fills,
    files) or its inserter (streams).
    """
    from gsi.dem.simulation import Simulation

    if case.run.threads:
        import numba
        numba.set_num_threads(min(case.run.threads, numba.config.NUMBA_NUM_THREADS))
    r_min = case.smallest_radius()
    sim = Simulation(
        materials=case.dem_materials(), contact=case.dem.contact, k_n=case.dem.k_n,
        rolling=case.dem.rolling, heat=None if case.dem.heat == "none" else case.dem.heat,
        h_c=case.dem.h_c, pipe_length=case.dem.pipe_length,
        pipe_resistance=case.dem.pipe_resistance, gravity=case.dem.gravity, dt=dt,
        skin=case.dem.skin if case.dem.skin is not None else 0.4 * r_min,
        domain=(case.dem.domain_lo, case.dem.domain_hi), force_dt=case.dem.force_dt,
        pair_overrides=case.pair_overrides(), seed=case.run.seed, dt_checked=True,
        # dem.skin not given: adaptive between 0.4 and 1 x the smallest radius
        skin_max=r_min if case.dem.skin is None else None,
        frictional_heating=case.dem.frictional_heating)
    radiation = case.radiation_options()
    if radiation is not None:
        sim.set_radiation(**radiation)
    handles = {}
    for i, w in enumerate(case.walls):
        handles[w.name] = w.add_to(sim, base_dir=case.base_dir, path=f"walls[{i}]")
        w.apply_motion(handles[w.name], 0.0)
    rng = np.random.default_rng(case.run.seed)
    groups = {}
    for i, p in enumerate(case.particles):
        groups[p.name] = p.add_to(sim, rng=rng, base_dir=case.base_dir, path=f"particles[{i}]")
    return sim, handles, groups
