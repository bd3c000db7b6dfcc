"""Profile of one DEM step in the seed-003 drum (Hertz, rolling resistance, heat, a
turning mesh wall, no plane): where the step goes, per thread count.

    python benchmarks/drum_profile.py [--particles 5000] [--steps 1000] [--threads 1,2]
                                      [--no-sort]

The drum of :mod:`gsi.studies.drum` is filled, settled and turned ``--spin-up`` turns (default
0.05); then, for each thread count, ``--steps`` steps are timed (wall clock) and the
force pass is timed alone (a compiled loop of force passes, no Python in between):

- ``pairs``: the force pass with the triangle candidates removed;
- ``triangles``: the full force pass minus ``pairs``;
- ``integration``: the fused pass (forces, kick, drift, scan) minus the full force pass;
- ``walls and scans``: the engine's own step loop (``advance``, 10 steps a call) minus
  the fused pass: wall motion, the serial sums of the mesh contacts, the scans;
- ``rebuild``: one neighbour rebuild times the rebuilds per step of the timed steps;
- ``rest``: the measured step minus all of these (Python between the engine's calls,
  the restarts after a rebuild).

Each compiled timing is the best of 20 batches of 10 calls, the state restored before
every batch.

The last line holds ``particles= threads= step_ms= rate=`` of the last thread count and
the shares of the rows.
"""
import argparse
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def _best_of(sim, call, *, calls, batches):
    """Seconds per call of ``call()`` (best of ``batches`` batches of ``calls`` calls), the
    state restored before every batch (outside the timing)."""
    saved = sim.state()
    call(1)
    best = float("inf")
    for _ in range(batches):
        sim.set_state(saved)
        t = time.perf_counter()
        call(calls)
        best = min(best, (time.perf_counter() - t) / calls)
    sim.set_state(saved)
    return best


def force_pass_seconds(sim, mode, *, mesh=True, calls=10, batches=20):
    """Seconds per force pass (``mode``: 0 forces only, 2 fused with the integration,
    see :func:`_pass_loop`), a compiled loop of ``calls`` passes; without ``mesh`` the triangle
    candidates and contacts are hidden."""
    import numpy as np

    def call(k):
        P, pairs, pl, M, wc = sim.bundles()
        if not mesh:
            pairs = pairs._replace(tri_start=np.zeros_like(pairs.tri_start))
            wc = wc._replace(count=np.zeros_like(wc.count))
        nslab = len(pairs.slab_start) - 1
        acc = np.zeros((nslab, len(pl.point), 7))
        scan_out = np.zeros((nslab, 3))
        g = sim.g
        _pass_loop(sim.engine)(
            k, mode, sim.dt, P, pairs, pl, M, wc, sim.table, acc, g[0], g[1], g[2], sim.lo,
            sim.hi, scan_out)
    return _best_of(sim, call, calls=calls, batches=batches)


def advance_seconds(sim, *, calls=10, batches=20):
    """Seconds per step of the engine's own step loop (``advance``, ``calls`` steps per
    call, stopped early if a rebuild falls due): the step without Python and rebuilds."""
    done = [0]

    def call(k):
        P, pairs, pl, M, wc = sim.bundles()
        d, _, _ = sim.engine.advance(k, False, sim.dt, sim.g, (0.5 * sim.skin) ** 2,
                                     sim.v_max ** 2, sim.lo, sim.hi, P, pairs, pl, M, wc,
                                     sim.table, sim.log.state)
        done[0] = d
        if d < k:
            raise RuntimeError("a rebuild fell due inside the timed steps; use fewer")
    return _best_of(sim, call, calls=calls, batches=batches)


_LOOPS = {}


def _pass_loop(engine):
    """A compiled loop of ``k`` force passes of the engine (one per contact model):
    ``mode`` 0 the forces only (``advance(FORCES_ONLY)``), 2 ``k`` steps of ``advance``
    (each pass fused with the integration; the engine has no separate force pass)."""
    import numba
    import numpy as np
    from gsi.dem.engine import advance, FORCES_ONLY
    from gsi.dem.contact_log import empty_log_state
    key = tuple(engine.model)
    if key not in _LOOPS:
        model = engine.model
        lg = empty_log_state()

        @numba.njit
        def loop(k, mode, dt, P, pairs, pl, M, wc, table, acc, g0, g1, g2, lo, hi, so):
            g = np.array([g0, g1, g2])
            if mode == 0:
                for _ in range(k):
                    advance(FORCES_ONLY, False, 0.0, g, 0.0, 0.0, lo, hi, P, pairs, pl, M, wc,
                            table, lg, model)
            else:
                advance(k, False, dt, g, 1e30, 1e30, lo, hi, P, pairs, pl, M, wc, table, lg,
                        model)
        _LOOPS[key] = loop
    return _LOOPS[key]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--particles", type=int, default=5000)
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--spin-up", type=float, default=0.05, help="turns before timing")
    ap.add_argument("--no-sort", action="store_true",
                    help="keep the particle rows in id order (default: sorted at each build, "
                         "as drum_vs_liggghts.py runs)")
    ap.add_argument("--skin", type=float, default=None,
                    help="Verlet skin in particle radii (default gsi's 0.4)")
    args = ap.parse_args(argv)
    import numba
    from gsi.studies.drum import drum_geometry, prepare
    from gsi.studies.drum import PARTICLE_RADIUS
    skin = None if args.skin is None else args.skin * PARTICLE_RADIUS
    sim, _, _ = prepare(drum_geometry(args.particles), spin_up=args.spin_up, skin=skin)
    sim.sort_particles = not args.no_sort      # as benchmarks/drum_vs_liggghts.py
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
            sim.rebuild_lists()
            t_rb = min(t_rb, time.perf_counter() - t)
        t_pairs = force_pass_seconds(sim, 0, mesh=False)
        t_full = force_pass_seconds(sim, 0)
        t_fused = force_pass_seconds(sim, 2)
        t_adv = advance_seconds(sim)
        rows = [("pairs", t_pairs), ("triangles", t_full - t_pairs),
                ("integration", t_fused - t_full),
                ("walls and scans (advance - fused pass)", t_adv - t_fused),
                ("rebuild", t_rb * per_step)]
        rows.append(("rest (Python, restarts)", t_step - sum(v for _, v in rows)))
        print(f"threads {threads}: {sim.n} particles, step {t_step * 1e3:.3f} ms "
              f"({sim.n / t_step:.3g} particle-steps/s), {per_step:.4f} rebuilds per step "
              f"of {t_rb * 1e3:.1f} ms, {len(sim.pairs.j)} candidate pairs, "
              f"{len(sim.pairs.tri)} triangle candidates", flush=True)
        for name, v in rows:
            print(f"| {name} | {v * 1e3:.3f} ms | {100 * v / t_step:.1f} % |")
        line = (f"particles={sim.n} threads={threads} skin_r={sim.skin / PARTICLE_RADIUS:.3g} "
                f"step_ms={t_step * 1e3:.4g} "
                f"rate={sim.n / t_step:.4g} "
                + " ".join(f"{k.split()[0]}_share={v / t_step:.3f}" for k, v in rows))
    print(line)


if __name__ == "__main__":
    main()
