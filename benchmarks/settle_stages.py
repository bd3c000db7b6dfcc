"""Profile of the settle force pass by stage, on one thread (CPU time).

    python benchmarks/settle.py --threads 1 --save-state settled.npz   # once: the settled bed
    python benchmarks/settle_stages.py settled.npz PASSES

The pair path is timed in cumulative levels, each a compiled loop over every slab's rows
in batches as the engine runs them: the gather alone (contact test, branch-free
compaction, inputs), + the pair geometry, + the normal sub-model, + the tangential
sub-model, + the torques, + the scatter (``finish_pairs``: Newton's third
law, springs stored); the differences are the stages.  The planes are timed as their
gather alone, then with the model and the finish; the integration as
``integrate_rows`` in mode 2 (kick, drift, clear, scan).  Each figure is the best of 5
batches of PASSES passes, the state restored before each.  Note: the stages are called
from this file's loops, not from the engine's slab task, so LLVM's inlining choices
may differ from the engine's (until 2026-12-05 the planes went through ``gather_walls``,
a call per particle with every bundle passed member by member, so "planes: gather" read
0.5 ms; ``gather_planes`` is inlined here as in the engine: 0.09 ms); the pair rows summed
(1.7 ms on 2026-12-05) are below the engine's pair figure (1.8-2.2 ms, which also counts
the forces-only pass's clearing and its slab tasks): read them as shares, not as the
engine's absolute times.
Last line: each stage's ms per pass.
"""
import os, sys, time
import numpy as np, numba
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from settle_profile import make
from gsi.jit import uint
from gsi.dem.contact.lanes import CH
from gsi.dem.contact import model as cm
from gsi.dem.contact.model import M_NORMAL, M_TANGENTIAL
from gsi.dem import pair_lanes as pln
from gsi.dem import wall_lanes as wln
from gsi.dem.engine import lane_buffer
from gsi.dem.state import MAX_WALL_SLOTS
from gsi.dem.integrate import integrate_rows


@numba.njit
def pairs_pass(level, dt, P, pairs, tab, nt, model):
    """One pass of the pair path over every slab, up to stage ``level`` (see :func:`stage`)."""
    B = lane_buffer()
    lk = np.empty(CH, np.uint64); lj = np.empty(CH, np.uint64)
    lrow = np.empty(CH, np.int64); brow = np.empty(CH, np.int64)
    blane = np.zeros(CH + 1, np.uint64)
    acc = 0.0
    for sl in range(pairs.slab_start.shape[0] - 1):
        n = uint(0); nrow = np.int64(0)
        for m in range(pairs.slab_start[sl], pairs.slab_start[sl + 1]):
            i = pairs.slab_list[m]
            row_i = P.type[i] * nt
            k0 = uint(pairs.start[i]); k_end = uint(pairs.start[i + 1])
            while k0 < k_end:
                if n == uint(CH) or nrow == CH:
                    acc += stage(level, nrow, brow, blane, n, B, lk, lj, lrow, P, pairs, tab, dt, model)
                    n = uint(0); nrow = np.int64(0)
                k1 = min(k_end, k0 + (uint(CH) - n))
                n = pln.gather_pairs(i, k0, k1, row_i, P, pairs, B, lk, lj, lrow, n, False, False)
                brow[nrow] = i; nrow += 1; blane[nrow] = n
                k0 = k1
        acc += stage(level, nrow, brow, blane, n, B, lk, lj, lrow, P, pairs, tab, dt, model)
    return acc

@numba.njit
def stage(level, nrow, brow, blane, n, B, lk, lj, lrow, P, pairs, tab, dt, model):
    """A gathered batch through the stages up to ``level``: 0 none, 1 geometry, 2 + normal,
    3 + tangential, 4 + torques, 6 the whole ``finish_pairs`` (with the scatter)."""
    if level == 0:
        return B[n // 2]
    if level >= 6:
        pln.finish_pairs(nrow, brow, blane, n, B, lk, lj, lrow, P, pairs, tab, dt, model, False)
        return 0.0
    pln.pair_geometry(n, B)
    if level >= 2:
        cm.normal_stage(model[M_NORMAL], uint(0), n, B, tab, lrow[0], dt)
    if level >= 3:
        cm.tangential_stage(model[M_TANGENTIAL], uint(0), n, B, tab, lrow[0], dt)
    if level >= 4:
        pln.pair_torques(n, B)
    return B[n // 2]

@numba.njit
def rep_pairs(k, level, dt, P, pairs, tab, nt, model):
    """``k`` pair passes up to ``level``."""
    a = 0.0
    for _ in range(k):
        a += pairs_pass(level, dt, P, pairs, tab, nt, model)
    return a

@numba.njit
def rep_walls(k, wlev, dt, P, pairs, pl, M, wc, plh, tab, nt, model, pl_acc):
    """``k`` passes of the wall path: the gather alone (``wlev`` 0) or with the finish (1)."""
    W = lane_buffer()
    wi = np.empty(CH, np.int64); wkind = np.empty(CH, np.int64); wk = np.empty(CH, np.int64)
    wp = np.empty(CH, np.int64); wrow = np.empty(CH, np.int64)
    for _ in range(k):
        for sl in range(pairs.slab_start.shape[0] - 1):
            nw = uint(0)
            for m in range(pairs.slab_start[sl], pairs.slab_start[sl + 1]):
                i = pairs.slab_list[m]
                row_i = P.type[i] * nt
                if wc.plane_cand[i] != 0 or wc.count[i] > 0:
                    if nw + uint(wln.plane_count(wc.plane_cand[i]) + MAX_WALL_SLOTS) > uint(CH):
                        if wlev == 1:
                            wln.finish_walls(nw, W, wi, wkind, wk, wp, wrow, sl, P, pairs, pl, M, wc, plh, tab, dt, model, False, pl_acc)
                        nw = uint(0)
                    if wc.plane_cand[i] != 0:
                        nw = wln.gather_planes(i, P, pl, wc, plh, W, wi, wkind, wk, wp, wrow, nw, row_i)
                    if wc.count[i] > 0:
                        nw = wln.gather_triangles(i, P, pairs, M, wc, W, wi, wkind, wk, wp, wrow, nw, row_i)
            if wlev == 1:
                wln.finish_walls(nw, W, wi, wkind, wk, wp, wrow, sl, P, pairs, pl, M, wc, plh, tab, dt, model, False, pl_acc)

@numba.njit
def rep_int(k, mode, dt, P, pairs, lo, hi):
    """``k`` integrations of every particle (``integrate_rows``, ``mode``)."""
    for _ in range(k):
        integrate_rows(0, P.x.shape[0], pairs.slab_list, mode, False, 0.5 * dt, dt, 0.0, 0.0, -9.81, P, lo, hi, 1e30)

def main():
    """Print the table and the key=value line."""
    numba.set_num_threads(1)
    sim = make(sys.argv[1]); K = int(sys.argv[2])
    sim.step(200)
    P, pairs, pl, M, wc = sim.bundles()
    model = sim.engine.model
    nt = sim.table.shape[0]; tab = sim.table.reshape((nt * nt, sim.table.shape[2]))
    npl = pl.point.shape[0]
    plh = wc.plane_hist.reshape((P.x.shape[0] * npl, 3))
    pl_acc = np.zeros((len(pairs.slab_start) - 1, npl, 8))
    dt = sim.dt
    arrs = [sim.x, sim.v, sim.omega, sim.force, sim.torque, pairs.hist, pairs.active, wc.plane_hist]
    saved = [a.copy() for a in arrs]
    def restore():
        for a, b in zip(arrs, saved): a[:] = b
    def tm(f):
        restore(); f(1)
        best = 1e9
        for _ in range(5):
            restore(); t0 = time.process_time(); f(K); best = min(best, (time.process_time() - t0) / K)
        restore(); return best
    T = {}
    for lev in (0, 1, 2, 3, 4, 6):
        T[lev] = tm(lambda k: rep_pairs(k, lev, dt, P, pairs, tab, nt, model))
    T["wg"] = tm(lambda k: rep_walls(k, 0, dt, P, pairs, pl, M, wc, plh, tab, nt, model, pl_acc))
    T["walls"] = tm(lambda k: rep_walls(k, 1, dt, P, pairs, pl, M, wc, plh, tab, nt, model, pl_acc))
    T["int"] = tm(lambda k: rep_int(k, 2, dt, P, pairs, sim.lo, sim.hi))
    ncont = int(pairs.active.sum())
    npc = int(sum(bin(int(m)).count("1") for m in wc.plane_mask)); ncand = int(sum(bin(int(m)).count("1") for m in wc.plane_cand))
    print(f"# plane contacts {npc}, plane candidates {ncand}, particles with candidates {int((wc.plane_cand != 0).sum())}")
    rows = [("gather (contact test, compaction, inputs)", T[0]), ("geometry", T[1] - T[0]),
            ("normal (hertz)", T[2] - T[1]), ("tangential (history)", T[3] - T[2]),
            ("torques", T[4] - T[3]), ("scatter (Newton 3rd law, springs back)", T[6] - T[4]),
            ("planes: gather", T["wg"]), ("planes: model + finish", T["walls"] - T["wg"]), ("integration (mode 2)", T["int"])]
    tot = sum(t for _, t in rows)
    print(f"# n={sim.n} candidates={len(pairs.j)} touching={ncont} total={tot*1e3:.3f} ms")
    for name, t in rows:
        print(f"| {name} | {t*1e3:.3f} ms | {100*t/tot:.1f} % | {t/max(ncont,1)*1e9:.1f} ns/contact |")
    keys = ("gather", "geometry", "normal", "tangential", "torques", "scatter", "plane_gather", "plane_finish",
            "integration")
    print(" ".join(f"{k}_ms={t * 1e3:.4g}" for k, (_, t) in zip(keys, rows)) + f" total_ms={tot * 1e3:.4g}")


if __name__ == "__main__":
    main()
