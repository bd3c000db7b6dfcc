"""Profile of one DEM step on the settled settle bed: share of step time per kernel.

    python benchmarks/settle.py --save-state settled.npz     # once: the settled bed
    python benchmarks/settle_profile.py settled.npz THREADS STEPS [LABEL]

Environment: ``CLOCK=wall`` or ``CLOCK=cpu`` (default: process CPU time on one
thread, robust on a shared machine; wall clock on more, where CPU time would count the
threads' spinning at barriers), ``SORT=1`` sorts the particle rows
(``sort_particles``).  Works with this engine and with the flat-argument engine of gsi
d6047ed (for before/after tables; run with that commit's ``gsi`` on ``PYTHONPATH``).

Rows: the force pass of pairs alone (planes removed), plus planes, plus the fused
integration (the force pass alone without planes, with planes, fused with the
integration; see :func:`repeater`; each the best
of 7 batches of force passes in a compiled loop, the state restored before each batch),
the neighbour rebuild (best of two, times the rebuilds per step of the run) and the
rest of the measured step (serial wall sums, wall motion, Python).
"""
import os
import sys
import time

import numpy as np
import numba

from gsi.dem import Simulation, Material


def repeater(engine):
    """A compiled loop of n force passes of ``engine`` (no Python between them): the
    engine object of :mod:`gsi.dem.engine` (its model bound), or a generated engine
    module of gsi before 2026-12-03 (for before/after tables from an old checkout).

    The engine of 2026-12-04 has no separate force pass: ``mode`` 0 is
    ``advance(FORCES_ONLY)`` (the forces at the current state, after a clear), ``mode`` 2
    is ``advance(n)`` (n steps, each a force pass fused with the integration, plus the
    step's serial wall sums)."""
    import gsi.dem.engine as eng
    if hasattr(engine, "model") and not hasattr(eng, "contact_forces"):
        from gsi.dem.contact_log import empty_log_state
        adv, forces_only, model, lg = eng.advance, eng.FORCES_ONLY, engine.model, empty_log_state()

        @numba.njit
        def rep_new(n, mode, dt, P, pairs, pl, M, wc, table, acc, g, lo, hi, so):
            if mode == 0:
                for _ in range(n):
                    adv(forces_only, False, 0.0, g, 0.0, 0.0, lo, hi, P, pairs, pl, M, wc,
                        table, lg, model)
            else:
                adv(n, False, dt, g, 1e30, 1e30, lo, hi, P, pairs, pl, M, wc, table, lg, model)
        return rep_new
    if hasattr(engine, "model"):
        cf_model = eng.contact_forces
        model = engine.model

        @numba.njit
        def rep_model(n, mode, dt, P, pairs, pl, M, wc, table, acc, g, lo, hi, so):
            for _ in range(n):
                cf_model(mode, dt, P, pairs, pl, M, wc, table, model, acc, g[0], g[1], g[2],
                         lo, hi, 1e4, so)
        return rep_model
    cf = engine.contact_forces

    @numba.njit
    def rep(n, mode, dt, P, pairs, pl, M, wc, table, acc, g, lo, hi, so):
        for _ in range(n):
            cf(mode, dt, P, pairs, pl, M, wc, table, acc, g[0], g[1], g[2], lo, hi, 1e4, so)
    return rep


def flat_repeater(engine):
    """:func:`repeater` for the flat-argument engine of d6047ed (its arguments as one tuple)."""
    cf = engine.contact_forces

    @numba.njit
    def rep(n, args):
        for _ in range(n):
            cf(*args)
    return rep


def make(state):
    d = np.load(state)
    glass = Material(E=5e6, nu=0.3, rho=2500.0, e=0.5, mu=0.5)
    sim = Simulation({"glass": glass}, contact="hertz", gravity=(0, 0, -9.81), dt=2e-6,
                     skin=4e-4, domain=((0, 0, 0), (0.084, 0.084, 0.3)),
                     **({"sort_particles": True} if os.environ.get("SORT") == "1" else {}))
    sim.add_particles(d["x"], 0.001, material="glass", v=d["v"], omega=d["omega"])
    for point, normal in [((0, 0, 0), (0, 0, 1)), ((0, 0, 0), (1, 0, 0)),
                          ((0.084, 0, 0), (-1, 0, 0)), ((0, 0, 0), (0, 1, 0)),
                          ((0, 0.084, 0), (0, -1, 0))]:
        sim.add_plane(point, normal, material="glass")
    return sim


def main():
    state, threads, steps = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    numba.set_num_threads(threads)
    global CLK
    clock = os.environ.get("CLOCK", "cpu" if threads == 1 else "wall")
    CLK = time.perf_counter if clock == "wall" else time.process_time
    sim = make(state)
    sim.step(200)
    E = sim.engine
    new = hasattr(sim, "pairs")
    nslab = (len(sim.pairs.slab_start) if new else len(sim._nb[0])) - 1
    g = sim.g
    lo, hi = sim.lo, sim.hi

    def cf(mode, planes=True, k=steps):
        """time k calls of contact_forces (s per call)"""
        if new:
            P, pairs, pl, M, wc = sim.bundles()
            if not planes:
                from gsi.dem.state import empty_planes
                pl = empty_planes()
                wc = wc._replace(plane_hist=np.zeros((sim.n, 0, 3)))
            acc = np.zeros((nslab, len(pl.point), 7)); so = np.zeros((nslab, 3))
        else:
            a = list(sim._args())
            (x, v, w, f, tq, q, radius, mass, inertia, T, mcp_inv, ptype, fixed, ncontact, x0, table,
             slab_start, slab_list, nb_start, nb_j, hist, pact,
             pl_p, pl_n, pl_v, pl_type, pl_T, pl_hasT, pl_hist, pl_mask, pl_force, pl_torque, pl_imp, pl_heat,
             mv_x, mv_v, mv_T, mv_x0, mv_wall, mt, mt_edge, mt_wall, mw_type, mw_hasT, mw_rigid,
             mw_vel, mw_omega, mw_centre, mc_start, mc_tri, mc_hist, wc_n, wc_tri, wc_kind,
             wc_fid, wc_k, wc_w, wc_f, wc_q, wc_pt, overflow, mw_force, mw_torque, mt_force,
             mv_imp, mv_heat, mw_imp_p, mw_heat_p, mt_p6, mt_lam) = a
            if not planes:
                pl_p, pl_n, pl_v = np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3))
                pl_type, pl_T, pl_hasT = np.zeros(0, np.int32), np.zeros(0), np.zeros(0, np.uint8)
                pl_hist = np.zeros((sim.n, 0, 3))
            acc = np.zeros((nslab, len(pl_p), 7)); so = np.zeros((nslab, 3))
            n = sim.n
            flat = (n, sim.dt, x, v, w, f, tq, q, radius, mass, inertia, T, ptype, ncontact,
                    table, slab_start, slab_list, nb_start, nb_j, hist, pact,
                    pl_p, pl_n, pl_v, pl_type, pl_T, pl_hasT, pl_hist, pl_mask,
                    mv_x, mv_v, mv_T, mt, mt_edge, mt_wall, mw_type, mw_hasT,
                    mc_start, mc_tri, mc_hist, wc_n, wc_tri, wc_kind, wc_fid, wc_k, wc_w,
                    wc_f, wc_q, wc_pt, overflow, acc, mode, g[0], g[1], g[2], fixed,
                    mcp_inv, x0, lo, hi, 1e4, so)
        if new:
            rep = repeater(E)
            args = (mode, sim.dt, P, pairs, pl, M, wc, sim.table, acc, g, lo, hi, so)
            passes = lambda n: rep(n, *args)
        else:
            rep = flat_repeater(E)
            passes = lambda n: rep(n, flat)
        arrs = [sim.x, sim.v, sim.omega, sim.force, sim.torque]
        arrs.append(sim.pairs.hist if new else sim._nb[4])
        saved = [a.copy() for a in arrs]

        def restore():
            for a, b in zip(arrs, saved):
                a[:] = b
        restore()
        passes(1)                                    # compile
        best = 1e9
        for _ in range(7):
            restore()
            t0 = CLK()
            passes(k // 7)
            best = min(best, (CLK() - t0) / (k // 7))
        restore()
        return best


    # whole step time: best of 7 chunks
    rb = sim.n_rebuilds
    t_step = 1e9
    for rep in range(7):
        t0 = CLK(); sim.step(steps // 7); t_step = min(t_step, (CLK() - t0) / (steps // 7))
    nrb = sim.n_rebuilds - rb
    t0 = CLK(); sim.rebuild_lists(); t_rb = CLK() - t0
    t0 = CLK(); sim.rebuild_lists(); t_rb = min(t_rb, CLK() - t0)
    xsave = sim.x.copy(); vsave = sim.v.copy()
    sim.step(1)
    t_pairs = cf(0, planes=False)
    t_force = cf(0)
    t_fused = cf(2)
    sim.x[:] = xsave; sim.v[:] = vsave
    t_rebuild = t_rb * nrb / steps
    rows = [("pair contacts", t_pairs), ("plane contacts", t_force - t_pairs),
            ("integration (fused: kick, drift, clear, scan)", t_fused - t_force),
            ("neighbour rebuild (amortized)", t_rebuild),
            ("serial wall sums, wall motion, Python", t_step - t_fused - t_rebuild)]
    print(f"# {sys.argv[4] if len(sys.argv) > 4 else ''} {'new' if new else 'old'} threads={threads} n={sim.n} step={t_step*1e3:.3f} ms "
          f"rate={sim.n / t_step:.4g} rebuilds/step={nrb/steps:.4f} rebuild={t_rb*1e3:.1f} ms")
    for name, t in rows:
        print(f"| {name} | {t*1e3:.3f} ms | {100*t/t_step:.1f} % |")
    keys = ("pairs", "planes", "integration", "rebuild", "rest")
    print(f"threads={threads} step_ms={t_step * 1e3:.4g} "
          + " ".join(f"{k}_share={t / t_step:.3f}" for k, (_, t) in zip(keys, rows)))


if __name__ == "__main__":
    main()
