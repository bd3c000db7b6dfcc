"""Benchmark: the hopper demo onto a large membrane (2.5e5+ dofs), FE distributed over the ranks.

Runs demos/hopper_membrane.toml (``--quick`` variant by default: 400 particles, 1.5 s)
through the one runner with the membrane refined to ``--h`` and ``--n-thickness`` P2
layers (default h = 8.5 mm, 2 layers: about 2.8e5 dofs) and the linear solver
``--solver``, without pictures. The DEM runs on rank 0; the FE on every rank.

Per rank it takes, for every coupling step, the wall time of the DEM sub-cycle, the FE step
and the transfers as :class:`gsi.coupling.staggered.StaggeredCoupling` measures them. A
rank other than 0 runs no DEM: what it books as "DEM" (from the start of the interval to
the start of the transfers) and as "transfer" (the broadcast of the wall's loads) is, beyond
rank 0's own transfer time, its wait for rank 0's DEM sub-cycle: that rank's idle time
(``idle_s``, the largest over the ranks). The shares are given over the coupling steps
after the first (``*_share``; the first holds the DEM's numba compilation when its cache is
cold and the first FE solve) and over all steps (``*_share_all``).

Usage: ``mpirun -n 2 python benchmarks/coupled_large.py [--full] [--h 0.0085]
[--solver direct]``. Last line: ``dofs=... ranks=... solver=... fe_share=...
transfer_share=... dem_share=... idle_s=... idle_share=... first_step_s=... setup_s=...
peak_mem_gb=... wall_s=...`` (``setup_s``: the factorization or multigrid set-up;
``peak_mem_gb``: peak resident memory summed over the ranks).
"""
import argparse
import dataclasses
import os
import pathlib
import resource
import shutil
import sys
import tempfile
import time

import numpy as np
from mpi4py import MPI

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run from a checkout too


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help="the full case instead of --quick")
    ap.add_argument("--h", type=float, default=0.0085, help="membrane element size (m)")
    ap.add_argument("--n-thickness", type=int, default=2, help="P2 layers through the membrane")
    ap.add_argument("--solver", choices=["auto", "direct", "out_of_core", "iterative"],
                    default="direct")
    args = ap.parse_args()
    from gsi.case import load_case
    from gsi.run import Runner
    case = load_case(ROOT / "demos" / "hopper_membrane.toml")
    st = case.structures[0]
    geometry = dict(st.geometry, h=args.h, n_thickness=args.n_thickness)
    case.structures[0] = dataclasses.replace(st, geometry=geometry, solver=args.solver)
    comm = MPI.COMM_WORLD
    load0 = os.getloadavg()[0]
    tmp = tempfile.mkdtemp(prefix="gsi_coupled_large_") if comm.rank == 0 else None
    tmp = pathlib.Path(comm.bcast(tmp, root=0))      # one output directory for all ranks
    t0 = time.perf_counter()
    runner = Runner(case, out=tmp, quick=not args.full, verbose=False, pictures=False)
    r = runner.run()
    wall = time.perf_counter() - t0
    comm.barrier()
    if comm.rank == 0:
        shutil.rmtree(tmp, ignore_errors=True)
    s = r.structures["membrane"]
    h = runner.structures[0].mechanics.history()
    steps = np.c_[h["wall_dem"], h["wall_fe"], h["wall_transfer"]]     # (coupling steps, 3)
    per_rank = comm.gather((steps[1:].sum(axis=0), steps.sum(axis=0)), root=0)
    solver = runner.structures[0].elasticity.linear_solver
    factor_s = comm.allreduce(solver.factor_seconds, op=MPI.MAX)
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6          # GB (kB on Linux)
    peak_gb, rank_gb = comm.allreduce(rss, op=MPI.SUM), comm.allreduce(rss, op=MPI.MAX)
    if comm.rank != 0:
        return
    (dem0, fe0, tr0), (dem0_all, fe0_all, tr0_all) = per_rank[0]
    loop, loop_all = dem0 + fe0 + tr0, dem0_all + fe0_all + tr0_all
    idle = [dem + tr - tr0 for (dem, _, tr), _ in per_rank[1:]]
    idle_s = max(idle) if idle else 0.0
    print(f"hopper_membrane {'full' if args.full else 'quick'} on {comm.size} rank(s), membrane "
          f"{s['n_dofs']} dofs (h = {args.h} m, {args.n_thickness} layers), solver {args.solver}: "
          f"n_sub = {s['n_sub']}, dt_FE = {1e3 * s['dt']:.2f} ms, {s['intervals']} coupling "
          f"steps; run {wall:.1f} s (incl. set-up, JIT, output), coupling loop {loop:.1f} s; "
          f"solver set-up {factor_s:.1f} s; peak memory {peak_gb:.2f} GB (rank max {rank_gb:.2f})",
          flush=True)
    for k, ((dem, fe, tr), (dem_a, fe_a, tr_a)) in enumerate(per_rank):
        what = "DEM" if k == 0 else "waiting for the DEM"
        print(f"  rank {k}, steps 2..{len(steps)}: {what} {dem:.2f} s, FE {fe:.2f} s, transfer "
              f"(incl. waiting) {tr:.2f} s; all steps: {what} {dem_a:.2f} s, FE {fe_a:.2f} s, "
              f"transfer {tr_a:.2f} s", flush=True)
    n = max(len(steps) - 1, 1)
    print(f"dofs={s['n_dofs']} ranks={comm.size} solver={args.solver} intervals={s['intervals']} "
          f"fe_share={fe0 / loop:.3f} transfer_share={tr0 / loop:.3f} dem_share={dem0 / loop:.3f} "
          f"fe_step_s={fe0 / n:.3f} dem_step_s={dem0 / n:.3f} idle_s={idle_s:.2f} "
          f"idle_share={idle_s / loop:.3f} loop_s={loop:.1f} first_step_s={loop_all - loop:.1f} "
          f"fe_share_all={fe0_all / loop_all:.3f} dem_share_all={dem0_all / loop_all:.3f} "
          f"setup_s={factor_s:.1f} peak_mem_gb={peak_gb:.2f} wall_s={wall:.1f} "
          f"load_start={load0:.2f} load_end={os.getloadavg()[0]:.2f}",
          flush=True)


if __name__ == "__main__":
    main()
