"""Benchmark: the hopper demo onto a large membrane (2.5e5+ dofs), FE distributed over the ranks.

Runs demos/hopper_membrane.toml (``--quick`` variant by default: 400 particles, 1.5 s)
through the one runner with the membrane refined to ``--h`` and ``--n-thickness`` P2
layers (default h = 8.5 mm, 2 layers: about 2.8e5 dofs) and the linear solver
``--solver``, without pictures. The DEM runs on rank 0; the FE on every rank.

Per rank it sums, over the coupling steps, the wall time of the DEM sub-cycles, the FE steps
and the transfers as :class:`gsi.coupling.staggered.StaggeredCoupling` measures them. On a
rank other than 0 the "transfer" includes the wait for rank 0's DEM sub-cycle (the
broadcast of the wall's loads): its excess over rank 0's transfer time is that rank's idle
time while the DEM runs.

Usage: ``mpirun -n 2 python benchmarks/coupled_large.py [--full] [--h 0.0085]
[--solver direct]``. Last line: ``dofs=... ranks=... solver=... fe_share=...
transfer_share=... dem_share=... idle_s=... idle_share=... wall_s=...``.
"""
import argparse
import dataclasses
import os
import pathlib
import shutil
import sys
import tempfile
import time

from mpi4py import MPI

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run from a checkout too


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help="the full case instead of --quick")
    ap.add_argument("--h", type=float, default=0.0085, help="membrane element size (m)")
    ap.add_argument("--n-thickness", type=int, default=2, help="P2 layers through the membrane")
    ap.add_argument("--solver", choices=["auto", "direct", "iterative"], default="direct")
    args = ap.parse_args()
    from gsi.case import load_case
    from gsi.runner import run_case
    case = load_case(ROOT / "demos" / "hopper_membrane.toml")
    st = case.structures[0]
    geometry = dict(st.geometry, h=args.h, n_thickness=args.n_thickness)
    case.structures[0] = dataclasses.replace(st, geometry=geometry, solver=args.solver)
    comm = MPI.COMM_WORLD
    load0 = os.getloadavg()[0]
    tmp = tempfile.mkdtemp(prefix="gsi_coupled_large_") if comm.rank == 0 else None
    tmp = pathlib.Path(comm.bcast(tmp, root=0))      # one output directory for all ranks
    t0 = time.perf_counter()
    r = run_case(case, out=tmp, quick=not args.full, verbose=False, pictures=False)
    wall = time.perf_counter() - t0
    comm.barrier()
    if comm.rank == 0:
        shutil.rmtree(tmp, ignore_errors=True)
    s = r.structures["membrane"]
    mine = (s["wall_dem"], s["wall_fe"], s["wall_transfer"])
    per_rank = comm.gather(mine, root=0)
    if comm.rank != 0:
        return
    dem0, fe0, tr0 = per_rank[0]
    loop = dem0 + fe0 + tr0
    idle = [tr - tr0 for _, _, tr in per_rank[1:]]
    idle_s = max(idle) if idle else 0.0
    print(f"hopper_membrane {'full' if args.full else 'quick'} on {comm.size} rank(s), membrane "
          f"{s['n_dofs']} dofs (h = {args.h} m, {args.n_thickness} layers), solver {args.solver}: "
          f"n_sub = {s['n_sub']}, dt_FE = {1e3 * s['dt']:.2f} ms, {s['intervals']} coupling "
          f"steps; run {wall:.1f} s (incl. set-up, JIT, output), coupling loop {loop:.1f} s",
          flush=True)
    for k, (dem, fe, tr) in enumerate(per_rank):
        print(f"  rank {k}: DEM {dem:.2f} s, FE {fe:.2f} s, transfer (incl. waiting) {tr:.2f} s",
              flush=True)
    print(f"dofs={s['n_dofs']} ranks={comm.size} solver={args.solver} intervals={s['intervals']} "
          f"fe_share={fe0 / loop:.3f} transfer_share={tr0 / loop:.3f} dem_share={dem0 / loop:.3f} "
          f"fe_step_s={fe0 / max(s['intervals'], 1):.3f} idle_s={idle_s:.2f} "
          f"idle_share={idle_s / loop:.3f} loop_s={loop:.1f} wall_s={wall:.1f} "
          f"load_start={load0:.2f} load_end={os.getloadavg()[0]:.2f}", flush=True)


if __name__ == "__main__":
    main()
