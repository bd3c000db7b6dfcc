"""The force pass with each particle's partners touching-first (as the neighbour build
stores them) against the same lists in a random order, on the settled ``settle`` bed.

    python benchmarks/settle.py --save-state settled.npz     # once: the settled bed
    python benchmarks/pair_order.py settled.npz

A cell scan finds a particle's partners in an order that has nothing to do with whether
they touch; in a dense bed about half of them do, so the force pass's branch on
"touching" is a coin flip for the branch predictor.  ``gsi.dem.neighbour.fill_pairs``
stores the partners touching at the build first; this benchmark shuffles each particle's
partners (springs and flags with them, seeded) to time the other order in the same
process: the calls are interleaved, each a batch of 20 force passes from the same
restored state (``THREADS``, default 1: CPU time; ``ROUNDS``, default 15).  It also
checks that both orders give the same forces to round-off.
Last line: ``touching_first_ms=... shuffled_ms=... speedup=...`` (best batches).
"""
import os
import sys
import time

import numba
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
os.environ.setdefault("SORT", "1")     # rows in force-pass order, as benchmarks/settle.py

from engine_ab import repeater  # noqa: E402
from settle_profile import make  # noqa: E402


def shuffled(pairs, seed=0):
    """``pairs`` with each particle's partners (and their springs and flags) shuffled."""
    rng = np.random.default_rng(seed)
    j, hist, act = pairs.j.copy(), pairs.hist.copy(), pairs.active.copy()
    st = pairs.start
    for i in range(len(st) - 1):
        s, e = st[i], st[i + 1]
        o = s + rng.permutation(e - s)
        j[s:e], hist[s:e], act[s:e] = pairs.j[o], pairs.hist[o], pairs.active[o]
    return pairs._replace(j=j, hist=hist, active=act)


def main(argv):
    threads = int(os.environ.get("THREADS", "1"))
    rounds = int(os.environ.get("ROUNDS", "15"))
    numba.set_num_threads(threads)
    sim = make(argv[0])
    sim.step(200)
    P, pairs, pl, M, wc = sim._bundles()
    rep = repeater(sim.engine)
    nslab = len(pairs.slab_start) - 1
    acc = np.zeros((nslab, len(pl.point), 7))
    so = np.zeros((nslab, 3))
    variants = {"touching_first": pairs, "shuffled": shuffled(pairs)}
    state = [sim.x, sim.v, sim.omega, sim.force, sim.torque, wc.plane_hist]
    saved = [a.copy() for a in state]
    springs = {k: p.hist.copy() for k, p in variants.items()}
    flags = {k: p.active.copy() for k, p in variants.items()}
    clock = time.perf_counter if threads > 1 else time.process_time

    def run(name, n):
        for a, b in zip(state, saved):
            a[:] = b
        p = variants[name]
        p.hist[:] = springs[name]
        p.active[:] = flags[name]
        t0 = clock()
        rep(n, 0, sim.dt, P, p, pl, M, wc, sim.table, acc, sim.g, sim.lo, sim.hi, so)
        return (clock() - t0) / n * 1e3

    forces = {}
    for name in variants:
        run(name, 1)
        forces[name] = sim.force.copy()
    scale = np.abs(forces["touching_first"]).max()
    dF = np.abs(forces["touching_first"] - forces["shuffled"]).max() / scale
    touching = int(pairs.active.sum())
    print(f"{sim.n} particles, {len(pairs.j)} pairs of which {touching} touch; "
          f"max |F_touching_first - F_shuffled| / max |F| = {dF:.1e}")
    times = {k: [] for k in variants}
    for _ in range(rounds):
        for name in variants:
            times[name].append(run(name, 20))
    for a, b in zip(state, saved):
        a[:] = b
    best = {k: min(v) for k, v in times.items()}
    for k, v in times.items():
        print(f"{k}: best {best[k]:.3f} ms, median {np.median(v):.3f} ms per force pass "
              f"({threads} thread(s))")
    print(f"touching_first_ms={best['touching_first']:.4g} shuffled_ms={best['shuffled']:.4g} "
          f"speedup={best['shuffled'] / best['touching_first']:.3f} force_rel_diff={dF:.2g}")


if __name__ == "__main__":
    main(sys.argv[1:])
