"""Benchmark "pairing": the cost of the pairing f_ext (seed 003 eq. 6) against N.

A bed like the drum's at two instants: N sites of a simple-cubic lattice (spacing 2.02 r,
r = 5 mm) in the lower half of a horizontal cylinder, each position jittered by up to
0.3 r independently at t0 and at t1, the particles shuffled between the two (every
particle has moved; the bed has not).  Times the exact dense assignment
(scipy.optimize.linear_sum_assignment, up to --dense-max particles) and the certified
sparse auction (:func:`gsi.extrapolation.pair_particles`, method "sparse"), checks that
they agree, and prints one line per N; the last line holds ``n=`` and the seconds of
each method at the largest N.

``--positions FILE`` pairs the ``x0`` and ``x1`` of an .npz instead (a contact log
written by ``benchmarks/drum_extrapolation.py --out DIR`` has them: a real turn of the
drum, where the bed changes shape), sparse only unless N <= --dense-max.

Usage::

    python benchmarks/pairing.py [--n 1000,2000,5000,10000,20000,80000] [--dense-max 10000]
        [--positions FILE]
"""
import argparse
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def bed(n, seed):
    import numpy as np
    r = 0.005
    a = 2.02 * r
    R = 0.3 * (n / 80_000) ** (1 / 3)
    L = 2 * R
    side = np.arange(-R, R, a)
    g = np.stack(np.meshgrid(side, np.arange(0, L, a), side, indexing="ij"), -1).reshape(-1, 3)
    g = g[(g[:, 0] ** 2 + g[:, 2] ** 2 < (R - r) ** 2)]
    g = g[np.argsort(g[:, 2], kind="stable")][:n]          # the lowest n sites
    rng = np.random.default_rng(seed)
    x0 = g + rng.uniform(-0.3 * r, 0.3 * r, g.shape)
    x1 = g[rng.permutation(len(g))] + rng.uniform(-0.3 * r, 0.3 * r, g.shape)
    return x0, x1


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", default="1000,2000,5000,10000,20000,80000")
    ap.add_argument("--dense-max", type=int, default=10_000)
    ap.add_argument("--positions", default=None, help="an .npz with x0 and x1 (N, 3)")
    args = ap.parse_args(argv)
    import numpy as np
    from gsi.extrapolation import pair_particles, pairing_cost
    if args.positions:
        with np.load(args.positions) as f:
            beds = [(f["x0"], f["x1"])]
    else:
        beds = (bed(int(v), seed=int(v)) for v in args.n.split(","))
    last = {}
    for x0, x1 in beds:
        n = len(x0)
        line = {"n": n}
        if n <= args.dense_max:
            t = time.perf_counter()
            d = pair_particles(x0, x1, method="dense")
            line["dense_s"] = time.perf_counter() - t
            line["dense_cost_m"] = pairing_cost(x0, x1, d)
        t = time.perf_counter()
        info = {}
        s = pair_particles(x0, x1, method="sparse", info=info)
        line["sparse_s"] = time.perf_counter() - t
        line.update(rounds=info["rounds"], edges=info["edges"], gap_bound_m=info["gap_bound"])
        line["sparse_cost_m"] = pairing_cost(x0, x1, s)
        if "dense_cost_m" in line:
            line["agree"] = abs(line["sparse_cost_m"] - line["dense_cost_m"]) <= \
                1e-9 * line["dense_cost_m"]
        print(" ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                       for k, v in line.items()), flush=True)
        last = line
    print(" ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                   for k, v in last.items()))


if __name__ == "__main__":
    main()
