"""Wall-time shares of DEM, FE and transfer in the coupled hopper-onto-membrane demo.

Runs demos/hopper_membrane.toml through the one runner (``--quick`` by default; ``--full``
for the full case) without pictures and sums, over all coupling steps, the wall-clock time of the DEM
sub-cycles, the FE steps, and the transfers (gathering positions and velocities,
broadcasting and applying loads, moving the wall, the balance record), as measured by
:class:`gsi.coupling.staggered.StaggeredCoupling` on rank 0. The target is FE plus
transfer at most 10 % of the coupled wall time with the default sub-cycling.

Usage: ``python benchmarks/coupled_hopper.py [--full] [--steps-per-period N]``
(``mpirun -n 2`` distributes the FE). Last line: ``dem_share=... fe_share=...
transfer_share=...``.
"""
import argparse
import dataclasses
import pathlib
import shutil
import tempfile
import time

from mpi4py import MPI

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help="the full case instead of --quick")
    ap.add_argument("--steps-per-period", type=float, default=None,
                    help="override the membrane's contact.steps_per_period (sets n_sub)")
    args = ap.parse_args()
    from gsi.case import load_case
    from gsi.run import run_case
    case = load_case(ROOT / "demos" / "hopper_membrane.toml")
    if args.steps_per_period:
        c = case.structures[0].contact
        case.structures[0].contact = dataclasses.replace(c, steps_per_period=args.steps_per_period)
    comm = MPI.COMM_WORLD
    tmp = tempfile.mkdtemp(prefix="gsi_coupled_hopper_") if comm.rank == 0 else None
    tmp = pathlib.Path(comm.bcast(tmp, root=0))      # one output directory for all ranks
    t0 = time.perf_counter()
    r = run_case(case, out=tmp, quick=not args.full, verbose=False, pictures=False)
    wall = time.perf_counter() - t0
    comm.barrier()
    if comm.rank == 0:
        shutil.rmtree(tmp, ignore_errors=True)
    s = r.structures["membrane"]
    total = s["wall_dem"] + s["wall_fe"] + s["wall_transfer"]
    if comm.rank == 0:
        print(f"hopper_membrane {'full' if args.full else 'quick'} on {comm.size} "
              f"rank(s): n_sub = {s['n_sub']}, dt_FE = {1e3 * s['dt']:.2f} ms, "
              f"{s['intervals']} coupling steps; run {wall:.1f} s (incl. set-up, JIT, output), "
              f"coupling loop {total:.2f} s: DEM {s['wall_dem']:.2f} s, FE {s['wall_fe']:.2f} s, "
              f"transfer {s['wall_transfer']:.2f} s")
        print(f"dem_share={s['wall_dem'] / total:.3f} fe_share={s['wall_fe'] / total:.3f} "
              f"transfer_share={s['wall_transfer'] / total:.3f}")


if __name__ == "__main__":
    main()
