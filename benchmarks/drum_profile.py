"""Profile of one DEM step in the seed-003 drum (Hertz, rolling resistance, heat, a
turning mesh wall, no plane): where the step goes, per thread count.

    python benchmarks/drum_profile.py [--particles 5000] [--steps 1000] [--threads 1,2]

The drum of :mod:`gsi.drum` is filled, settled and turned ``--spin-up`` turns (default
0.05); then, for each thread count, ``--steps`` steps are timed (wall clock) and the
force pass is timed alone (a compiled loop of force passes, no Python in between):

- ``pairs``: the force pass with the triangle candidates removed;
- ``triangles``: the full force pass minus ``pairs``;
- ``integration``: the fused pass (forces, kick, drift, scan) minus the full force pass;
- ``rebuild``: one neighbour rebuild times the rebuilds per step of the timed steps;
- ``rest``: the measured step minus all of these (wall motion, the serial sums of the
  mesh contacts, Python).

The last line holds ``particles= threads= step_ms= rate=`` of the last thread count and
the shares of the rows.
"""
import argparse
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def force_pass_seconds(sim, mode, *, mesh=True, calls=200):
    """Seconds per force pass (``contact_forces`` in ``mode``), best of 5 compiled loops of
    ``calls`` passes; without ``mesh`` the triangle candidates and contacts are hidden.
    The state is saved before and restored after (mode 0 moves nothing; modes 1-2 move
    the particles by ``calls`` steps, harmless for a timing)."""
    import numba
    import numpy as np
    P, pairs, pl, M, wc = sim._bundles()
    if not mesh:
        pairs = pairs._replace(tri_start=np.zeros_like(pairs.tri_start))
        wc = wc._replace(count=np.zeros_like(wc.count))
    nslab = len(pairs.slab_start) - 1
    acc = np.zeros((nslab, len(pl.point), 7))
    scan_out = np.zeros((nslab, 3))
    f = sim.engine.contact_forces

    @numba.njit
    def loop(k, mode, dt, P, pairs, pl, M, wc, table, acc, g0, g1, g2, lo, hi, so):
        for _ in range(k):
            f(mode, dt, P, pairs, pl, M, wc, table, acc, g0, g1, g2, lo, hi, 1e4, so)

    g = sim.g
    args = (mode, sim.dt, P, pairs, pl, M, wc, sim.table, acc, g[0], g[1], g[2], sim.lo,
            sim.hi, scan_out)
    saved = sim.state()
    loop(1, *args)
    best = float("inf")
    for _ in range(5):
        t = time.perf_counter()
        loop(calls, *args)
        best = min(best, (time.perf_counter() - t) / calls)
    sim.set_state(saved)
    return best


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--particles", type=int, default=5000)
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--spin-up", type=float, default=0.05, help="turns before timing")
    args = ap.parse_args(argv)
    import numba
    from gsi.drum import drum_geometry, prepare
    sim, _, _ = prepare(drum_geometry(args.particles), spin_up=args.spin_up)
    line = ""
    for threads in [int(t) for t in args.threads.split(",")]:
        numba.set_num_threads(threads)
        sim.step(20)
        rb = sim.n_rebuilds
        t = time.perf_counter()
        sim.step(args.steps)
        t_step = (time.perf_counter() - t) / args.steps
        per_step = (sim.n_rebuilds - rb) / args.steps
        t_rb = float("inf")
        for _ in range(2):
            t = time.perf_counter()
            sim._rebuild()
            t_rb = min(t_rb, time.perf_counter() - t)
        t_pairs = force_pass_seconds(sim, 0, mesh=False)
        t_full = force_pass_seconds(sim, 0)
        t_fused = force_pass_seconds(sim, 2)
        rows = [("pairs", t_pairs), ("triangles", t_full - t_pairs),
                ("integration", t_fused - t_full), ("rebuild", t_rb * per_step)]
        rows.append(("rest", t_step - sum(v for _, v in rows)))
        print(f"threads {threads}: {sim.n} particles, step {t_step * 1e3:.3f} ms "
              f"({sim.n / t_step:.3g} particle-steps/s), {per_step:.4f} rebuilds per step "
              f"of {t_rb * 1e3:.1f} ms, {len(sim.pairs.j)} candidate pairs, "
              f"{len(sim.pairs.tri)} triangle candidates", flush=True)
        for name, v in rows:
            print(f"| {name} | {v * 1e3:.3f} ms | {100 * v / t_step:.1f} % |")
        line = (f"particles={sim.n} threads={threads} step_ms={t_step * 1e3:.4g} "
                f"rate={sim.n / t_step:.4g} "
                + " ".join(f"{k}_share={v / t_step:.3f}" for k, v in rows))
    print(line)


if __name__ == "__main__":
    main()
