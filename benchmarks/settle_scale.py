"""Benchmark "settle_scale": the settle bed widened to 20k, 200k and 1M particles.

The bed of ``benchmarks/settle.py`` (spheres d = 2 mm in an 84 x 84 mm box, Hertz +
tangential history, E = 5 MPa, dt = 2 us, skin 0.4 mm, five planes) tiled kx x ky
times side by side in a box widened to (84 kx) x (84 ky) mm: 1 x 1 (19,773), 5 x 2
(197,730) and 10 x 5 (988,650 particles).  The tile is the settled bed written by
``python benchmarks/settle.py --save-state settled.npz`` (``--state``); without it,
the unsettled lattice of settle.py (falling, few contacts: not representative).

A first, untimed child fills numba's cache if it is cold.  Each size runs in its own
process (so its memory peak is its own): ``--warm-steps``
steps (first neighbour build, JIT or cache load), then blocks of ``--steps`` timed steps
until ``--min-seconds`` have passed (the rate is over all of them).  Rows
are sorted at each neighbour build (``sort_particles``) unless ``--no-sort``.

Usage::

    python benchmarks/settle_scale.py --state settled.npz [--threads N] [--max-n 300000]

Prints per size: throughput (particle steps per second), bytes per particle
(``Simulation.memory_bytes``), the neighbour-build time (s, best of two), the
process memory peak (MB, max RSS) and the rebuilds during the timed steps; the last
line holds key=value pairs (``rate_<n>``, ``bytes_<n>``, ``build_s_<n>``,
``peak_mb_<n>``, and ``rate_ratio_largest`` = rate per particle of the largest size
over that of the smallest).
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import time

TILES = [(1, 1), (5, 2), (10, 5)]
W = 0.084


def bed(kx, ky, state):
    """Positions, velocities, angular velocities of kx x ky tiles of the settle bed."""
    import numpy as np
    if state:
        d = np.load(state)
        x0, v0, w0 = d["x"], d["v"], d["omega"]
    else:
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        from settle import lattice_positions
        x0 = lattice_positions()
        v0 = np.zeros_like(x0)
        w0 = np.zeros_like(x0)
    xs, vs, ws = [], [], []
    for a in range(kx):
        for b in range(ky):
            xs.append(x0 + [a * W, b * W, 0.0])
            vs.append(v0)
            ws.append(w0)
    return np.concatenate(xs), np.concatenate(vs), np.concatenate(ws)


def run_one(kx, ky, state, warm, steps, min_seconds, sort=True):
    from gsi.dem import Simulation, Material
    glass = Material(E=5e6, nu=0.3, rho=2500.0, e=0.5, mu=0.5)
    X, Y = kx * W, ky * W
    sim = Simulation({"glass": glass}, contact="hertz", gravity=(0, 0, -9.81), dt=2e-6,
                     skin=4e-4, domain=((0, 0, 0), (X, Y, 0.3)), sort_particles=sort)
    x, v, w = bed(kx, ky, state)
    sim.add_particles(x, 0.001, material="glass", v=v, omega=w)
    for point, normal in [((0, 0, 0), (0, 0, 1)), ((0, 0, 0), (1, 0, 0)),
                          ((X, 0, 0), (-1, 0, 0)), ((0, 0, 0), (0, 1, 0)),
                          ((0, Y, 0), (0, -1, 0))]:
        sim.add_plane(point, normal, material="glass")
    sim.step(warm)
    build = []
    for _ in range(2):
        t0 = time.perf_counter()
        sim.rebuild_lists()
        build.append(time.perf_counter() - t0)
    rb = sim.n_rebuilds
    blocks = []                       # seconds of each block of ``steps`` steps
    while not blocks or sum(blocks) < min_seconds:
        t0 = time.perf_counter()
        sim.step(steps)
        blocks.append(time.perf_counter() - t0)
    done = steps * len(blocks)
    return dict(n=sim.n, rate=sim.n * done / sum(blocks), steps=done,
                block_rates=[sim.n * steps / b for b in blocks],
                bytes=sim.memory_bytes() / sim.n,
                build_s=min(build), rebuilds=sim.n_rebuilds - rb, lost=sim.n_lost,
                peak_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0)


def child_cmd(args, kx, ky, warm, steps, min_seconds):
    """The command line of the child run of the kx x ky bed."""
    cmd = [sys.executable, os.path.abspath(__file__), "--one", f"{kx},{ky}",
           "--warm-steps", str(warm), "--steps", str(steps), "--min-seconds", str(min_seconds)]
    if args.state:
        cmd += ["--state", args.state]
    if args.threads:
        cmd += ["--threads", str(args.threads)]
    if args.no_sort:
        cmd += ["--no-sort"]
    return cmd


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--state", default=None, help="settled tile (.npz from settle.py --save-state)")
    ap.add_argument("--threads", type=int, default=None, help="numba threads (default: all)")
    ap.add_argument("--max-n", type=int, default=1_100_000, help="skip sizes above this")
    ap.add_argument("--warm-steps", type=int, default=200)
    ap.add_argument("--steps", type=int, default=1000, help="steps per timed block")
    ap.add_argument("--min-seconds", type=float, default=10.0,
                    help="time blocks until this many seconds (the small bed's 1,000 steps "
                         "last ~2 s, too short for a stable rate)")
    ap.add_argument("--no-sort", action="store_true", help="keep the rows in id order")
    ap.add_argument("--one", default=None, help=argparse.SUPPRESS)   # "kx,ky": child run
    args = ap.parse_args(argv)
    if args.one:
        import numba
        if args.threads:
            numba.set_num_threads(args.threads)
        kx, ky = map(int, args.one.split(","))
        print(json.dumps(run_one(kx, ky, args.state, args.warm_steps, args.steps,
                                 args.min_seconds, not args.no_sort)))
        return 0
    res = {}
    # a first, untimed child fills numba's cache if it is cold, so that every timed
    # child loads the engine compiled: a process that has just compiled it was seen to
    # run it slower (the 19,773 bed at 7.4e6-8.3e6 instead of 1.05e7 particle steps/s)
    subprocess.run(child_cmd(args, 1, 1, warm=2, steps=2, min_seconds=0.0),
                   capture_output=True, text=True, check=True)
    for kx, ky in TILES:
        if 19773 * kx * ky > args.max_n:
            print(f"n = {19773 * kx * ky}: skipped (--max-n {args.max_n})")
            continue
        cmd = child_cmd(args, kx, ky, args.warm_steps, args.steps, args.min_seconds)
        r = subprocess.run(cmd, capture_output=True, text=True, check=True)
        d = json.loads(r.stdout.strip().splitlines()[-1])
        print(f"n = {d['n']}: {d['rate']:.4g} particle steps/s, {d['bytes']:.0f} bytes/particle, "
              f"neighbour build {d['build_s']:.3f} s, peak {d['peak_mb']:.0f} MB, "
              f"{d['rebuilds']} rebuilds in {d['steps']} steps, lost {d['lost']} (blocks of "
              f"{args.steps} steps: {min(d['block_rates']):.4g} to {max(d['block_rates']):.4g})")
        res[d["n"]] = d
    if not res:
        return 1
    out = {"bed": "settled" if args.state else "lattice"}
    for n, d in res.items():
        for k in ("rate", "bytes", "build_s", "peak_mb"):
            out[f"{k}_{n}"] = d[k]
    ns = sorted(res)
    out["rate_ratio_largest"] = res[ns[-1]]["rate"] / res[ns[0]]["rate"]
    print(" ".join(f"{k}={v:.6g}" if isinstance(v, float) else f"{k}={v}"
                   for k, v in out.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
