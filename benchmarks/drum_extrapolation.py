"""Benchmark "drum_extrapolation": long-time heat extrapolation (seed 003) against gsi's
own full DEM of the rotating drum.

The drum of :mod:`gsi.studies.drum` (seed 003 Tables 3-4; 80,000 particles in R = 0.30 m at
5 s per turn, Fr = 0.048, cascading; smaller drums at the same Froude number): fill,
settle (drum at rest), hot left half / cold right half, one turn of spin-up, then one
period t0..t1 logged with each sampling (every n steps, rows split at dt_split) and
replayed for ``--periods`` periods, while the same DEM continues as the reference.

Prints the set-up (size, Froude number and regime), the DEM seconds per period, and per
sampling the collision-file seconds (the logged DEM period), its size and bytes per
collision, the pairing seconds, the replay seconds per period, the speed-up per period
and the errors per period (eq. 9 absolute and relative on 200 Voronoi cells, and on
N/400 cells -- 400 particles per cell, as the seed's 80,000 in 200 --, each beside its
sampling level, the eq.-9 error of two fields with the same temperatures in each cell but
not the same particles (gsi.extrapolation.cell_sampling_level), eq. 10, the drift of
sum m c_p T); the last line holds ``particles= dem_s_per_period=
extrap_s_per_period= speedup_per_period= eps_abs_max= eps_rel_max= energy_err_max=``
(the sampling with the largest every; the error maxima over all samplings and periods)
and the other figures.

Usage::

    python benchmarks/drum_extrapolation.py [--quick] [--particles N] [--periods P]
        [--period-turns F] [--every 1,10] [--dt-split S] [--threads T] [--out DIR]
        [--state PATH [--setup-only]] [--halves-at-t0] [--twin AMP]

The set-up before t0 (fill, settle, one turn) is most of the DEM of a run at 80,000
particles; ``--state PATH`` saves it every 5,000 steps and resumes it, so it may be
spread over several runs (``--setup-only`` stops at t0), and a state of fewer spin-up
turns is extended to ``--spin-up`` (copy the file first to keep it); the measured part
(the logged period, the reference periods, pairing and replay) always runs whole, in one
process.

``--quick`` is the CI size, 5,000 particles.  Times are wall-clock seconds and, as the
machine may be shared, process CPU seconds (with ``--threads 1`` the CPU time of the one
computing thread).
"""
import argparse
import os
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the CI size: 5,000 particles")
    ap.add_argument("--particles", type=int, default=None, help="default 80,000 (5,000 quick)")
    ap.add_argument("--periods", type=int, default=6, help="extrapolated periods (default 6)")
    ap.add_argument("--period-turns", type=float, default=1.0,
                    help="period tau in drum turns (default 1, the seed's reference)")
    ap.add_argument("--every", default="1,10", help="sampling factors n (default 1,10)")
    ap.add_argument("--dt-split", type=float, default=0.01,
                    help="Delta t_c^max (s), default 0.01 (100 steps); the seed's is 0.001 "
                         "(10 steps, gsi.studies.drum.DT_SPLIT): the same errors on the quick "
                         "drum and a log 8 times larger (benchmarks/drum_sweep.py)")
    ap.add_argument("--twin", type=float, default=None, metavar="AMP",
                    help="also run a second DEM from t1 with every position moved by up to "
                         "AMP m, and give eq. 9 between the two DEMs (the error that chaos "
                         "alone makes)")
    ap.add_argument("--spin-up", type=float, default=1.0, help="turns before t0 (default 1)")
    ap.add_argument("--threads", type=int, default=None, help="numba threads (default all)")
    ap.add_argument("--state", default=None,
                    help="a .npz path: the set-up (fill, settle, spin-up) is saved there every "
                         "5,000 steps and resumed from it, so it can be spread over several "
                         "runs (gsi.studies.drum.prepare); a state of fewer spin-up turns is "
                         "extended; the measured part always runs whole")
    ap.add_argument("--skin", type=float, default=None,
                    help="Verlet skin in particle radii (default gsi's 0.4; neighbour lists "
                         "only: results agree to round-off)")
    ap.add_argument("--halves-at-t0", action="store_true",
                    help="set the hot (x below the median) and cold halves of the particles "
                         "at t0 instead of at the end of the settling (gsi.studies.drum's t_init), so the bed has not mixed its heat "
                         "during the spin-up; heat does not move particles, so the mechanics "
                         "and the contact log are the same")
    ap.add_argument("--setup-only", action="store_true",
                    help="stop at t0 (with --state: the set-up saved, for a later run)")
    ap.add_argument("--out", default=None,
                    help="directory for the collision files and reference.npz (the full DEM "
                         "and the replays at every t_n)")
    args = ap.parse_args(argv)
    if args.out:          # made now: a path that cannot be made fails before the hour of DEM
        os.makedirs(args.out, exist_ok=True)
    import numba
    import numpy as np
    if args.threads:
        numba.set_num_threads(args.threads)
    from gsi.studies.drum import drum_geometry, prepare
    from gsi.extrapolation import (finite_max, compare_with_dem, period_errors,
                                   voronoi_seeds)
    n = args.particles or (5000 if args.quick else 80_000)
    g = drum_geometry(n)
    print(f"drum: {n} particles, R = {g.radius:.4g} m, L = {g.length:.4g} m, "
          f"{g.period:.4g} s per turn ({g.steps_per_turn} steps), Fr = {g.froude:.4g} "
          f"({g.regime}); threads {numba.get_num_threads()}", flush=True)
    t = time.perf_counter()
    timing = {}
    from gsi.studies.drum import PARTICLE_RADIUS
    skin = None if args.skin is None else args.skin * PARTICLE_RADIUS
    sim, hot, _ = prepare(g, spin_up=args.spin_up, state=args.state, timing=timing, skin=skin,
                          say=lambda m: print("  " + m, flush=True))
    t_prep = time.perf_counter() - t
    print(f"fill + settle + {args.spin_up:g} turn: {t_prep:.1f} s in this run (incl. "
          f"compilation); {sim.n} particles at t0 = {sim.time:.4g} s", flush=True)
    if timing.get("spin_steps"):
        spin_s = timing["spin_seconds"] * g.steps_per_turn / timing["spin_steps"]
        print(f"spin-up: {timing['spin_steps']} steps of the turning drum in "
              f"{timing['spin_seconds']:.1f} s (summed over the runs that made the set-up): "
              f"{spin_s:.1f} s per turn", flush=True)
    if args.halves_at_t0:
        from gsi.studies.drum import T_COLD, T_HOT
        # the turning bed leans to the rising side: two halves of the particles, split at
        # their median x (at the end of the settling that is x = 0)
        x_mid = float(np.median(sim.x[:, 0]))
        hot = np.zeros_like(hot)
        hot[sim.ids] = sim.x[:, 0] < x_mid
        sim.T[:] = np.where(hot[sim.ids], T_HOT, T_COLD)
        print(f"halves set at t0: {int(hot.sum())} hot (x < {x_mid:.4g} m, the median) at "
              f"{T_HOT} K, {int((~hot).sum())} cold at {T_COLD} K", flush=True)
    if args.setup_only:
        line = f"particles={n} t0={sim.time:.6g}"
        if timing.get("spin_steps"):
            line += f" spin_s_per_turn={spin_s:.4g}"
        print(line)
        return {"particles": n, "t0": sim.time}
    steps = int(round(args.period_turns * g.steps_per_turn))
    samplings = [(int(e), args.dt_split) for e in args.every.split(",")]
    with tempfile.TemporaryDirectory() as tmp:
        out = args.out or tmp
        r = compare_with_dem(sim, period_steps=steps, periods=args.periods,
                             samplings=samplings, hot=hot, log_dir=out, twin=args.twin,
                             say=lambda m: print("  " + m, flush=True))
    dem = r["dem"]
    if args.out:
        # the full DEM and the replays at every t_n, for other error measures later
        arrays = {"dem_T": dem["T"], "dem_x": dem["x"], "hot": hot[r["runs"][0]["log"].ids]}
        for run in r["runs"]:
            arrays[f"extra{run['every']}_T"] = run["T"]
            arrays[f"extra{run['every']}_x"] = run["x"]
        np.savez(os.path.join(args.out, "reference.npz"), **arrays)
    print(f"DEM: {dem['seconds']:.2f} s per period ({dem['cpu']:.2f} s CPU; {steps} "
          f"steps); sum m c_p T drift {dem['energy_drift'].max():.2e}")
    tw = dem.get("twin")
    if tw is not None:
        for k in range(args.periods):
            print(f"  twin DEM (positions at t1 moved by up to {tw['amplitude']:.3g} m), "
                  f"t{k + 2}: eps_abs {tw['eps_abs'][k]:.4f} K against the DEM (sampling "
                  f"level {tw['eps_level'][k]:.4f} K)")
    last = None
    for run in r["runs"]:
        log = run["log"]
        speed = dem["seconds"] / run["replay_seconds"]
        speed_cpu = dem["cpu"] / run["replay_cpu"]
        print(f"n = {run['every']}, dt_split = {run['dt_split']} s: collision file "
              f"{run['log_seconds']:.2f} s (the logged DEM period), "
              f"{run['file_bytes'] / 1e6:.2f} MB ({log.n_collisions} rows, "
              f"{log.bytes_per_collision():.1f} bytes/collision, written in "
              f"{run['file_seconds']:.2f} s); pairing {run['pairing_seconds']:.3f} s "
              f"{pairing_note(run)}; replay "
              f"set-up {run['replay_setup_seconds']:.3f} s; "
              f"replay {run['replay_seconds']:.4f} s per period ({run['n_rows']} rows, "
              f"max m H/C {run['max_stability_ratio']:.2g}, {run['n_substepped']} sub-stepped); "
              f"speed-up {speed:.0f} per period (CPU: DEM {dem['cpu']:.2f} s, replay "
              f"{run['replay_cpu']:.4f} s, {speed_cpu:.0f}; logged period "
              f"{run['log_cpu']:.2f} s CPU); same t1 as the first run: {run['same_t1']}")
        # the seed's cells held 80,000/200 = 400 particles: the same count per cell here
        cells400 = max(1, n // 400)
        seeds = voronoi_seeds(log.x1, cells400, seed=0)
        e400 = period_errors(log, {"T": run["T"], "x": run["x"]}, dem["T"], dem["x"], seeds,
                             hot[log.ids])
        run["eps_abs_400"], run["eps_rel_400"] = e400["eps_abs"], e400["eps_rel"]
        run["eps_level_400"] = e400["eps_level"]
        for k in range(args.periods):
            print(f"  t{k + 2}: eps_abs {run['eps_abs'][k]:.4f} K (sampling level "
                  f"{run['eps_level'][k]:.4f} K), eps_rel "
                  f"{100 * run['eps_rel'][k]:.2f} %, eq. 10 {100 * run['energy_error'][k]:+.2f} %, "
                  f"drift {run['energy_drift'][k + 1]:.1e}; DEM T_hot - T_cold "
                  f"{abs(dem_gap(dem, hot, log, k + 1)):.3f} K; with {cells400} cells of 400 "
                  f"particles: eps_abs {e400['eps_abs'][k]:.4f} K (level "
                  f"{e400['eps_level'][k]:.4f} K), eps_rel {100 * e400['eps_rel'][k]:.2f} %")
        last = (run, speed, speed_cpu)
    run, speed, speed_cpu = last
    runs = r["runs"]
    res = dict(
        particles=n, froude=g.froude, regime=g.regime,
        dem_s_per_period=dem["seconds"], extrap_s_per_period=run["replay_seconds"],
        speedup_per_period=speed, dem_cpu_s_per_period=dem["cpu"],
        extrap_cpu_s_per_period=run["replay_cpu"], speedup_cpu_per_period=speed_cpu,
        eps_abs_max=max(float(x["eps_abs"].max()) for x in runs),
        eps_rel_max=max(float(np.nanmax(x["eps_rel"])) for x in runs),
        energy_err_max=max(float(np.abs(x["energy_error"]).max()) for x in runs),
        eps_abs_400_max=max(float(x["eps_abs_400"].max()) for x in runs),
        eps_rel_400_max=max(float(np.nanmax(x["eps_rel_400"])) for x in runs),
        eps_over_level_max=finite_max(np.concatenate(
            [x["eps_abs"] / x["eps_level"] for x in runs])),
        eps_over_level_400_max=finite_max(np.concatenate(
            [x["eps_abs_400"] / x["eps_level_400"] for x in runs])),
        energy_drift_max=max(float(x["energy_drift"].max()) for x in runs),
        pairing_s=run["pairing_seconds"], replay_setup_s=run["replay_setup_seconds"],
        collision_file_s=run["log_seconds"],
        collision_file_mb=run["file_bytes"] / 1e6,
        bytes_per_collision=run["log"].bytes_per_collision(), every=run["every"],
        dt_split=run["dt_split"], periods=args.periods, period_turns=args.period_turns)
    if tw is not None:
        res["twin_eps_abs_max"] = float(tw["eps_abs"].max())
    if timing.get("spin_steps"):
        res["spin_s_per_turn"] = spin_s
    print(" ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                   for k, v in res.items()))
    return res


def pairing_note(run):
    """The sparse pairing's rounds, graph size and certified gap, or "(dense)"."""
    i = run.get("pairing_info") or {}
    if not i:
        return "(dense)"
    return (f"(sparse: {i['rounds']} auction rounds, {i['edges']} pairs in the graph, "
            f"summed distance within {i['gap_bound']:.2g} m of the minimum)")


def dem_gap(dem, hot, log, n):
    """DEM mean temperature of the initially hot particles minus the cold ones at t_{n+1}."""
    h = hot[log.ids]
    T = dem["T"][n]
    return float(T[h].mean() - T[~h].mean())


if __name__ == "__main__":
    main()
