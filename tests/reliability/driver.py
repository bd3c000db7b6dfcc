"""Run a case file for the reliability tests and dump the final state.

``python driver.py CASE OUT [--resume] [--quick] [--checkpoint-every S] [--dump PATH]
[--dump-restored PATH]
[--parallel-min-n N] [--fail-fe-on-rank R --fail-fe-at-step K]``

``--dump PATH`` writes every rank's final :meth:`gsi.run.Runner.state` to
``PATH.rank<r>.npz`` (``--dump-restored``: the state right after ``--resume`` restored
it, then stop); ``--parallel-min-n 0`` makes the DEM use all numba threads even for
a few particles (the threaded slab code path); ``--fail-fe-*`` raises an error in the FE
step of one rank (the MPI error test). Exit codes are those of ``gsi run``.
"""
import argparse
import sys


def main():
    p = argparse.ArgumentParser()
    p.add_argument("case")
    p.add_argument("out")
    p.add_argument("--resume", action="store_true")
    p.add_argument("--quick", action="store_true")
    p.add_argument("--checkpoint-every", type=float, default=None)
    p.add_argument("--dump", default=None)
    p.add_argument("--dump-restored", default=None,
                   help="with --resume: dump the state right after the restore and stop")
    p.add_argument("--parallel-min-n", type=int, default=None)
    p.add_argument("--fail-fe-on-rank", type=int, default=None)
    p.add_argument("--fail-fe-at-step", type=int, default=3)
    a = p.parse_args()
    if a.parallel_min_n is not None:
        import gsi.dem.simulation as simulation
        init = simulation.Simulation.__init__

        def patched(self, *args, **kw):
            kw["parallel_min_n"] = a.parallel_min_n
            init(self, *args, **kw)
        simulation.Simulation.__init__ = patched
    from mpi4py import MPI

    from gsi.fem.elasticity import Elasticity      # on every rank: PETSc starts collectively
    if a.fail_fe_on_rank is not None and MPI.COMM_WORLD.rank == a.fail_fe_on_rank:
        step = Elasticity.step

        def failing(self):
            if self.n_steps + 1 >= a.fail_fe_at_step:
                raise RuntimeError(f"injected FE failure at step {self.n_steps + 1}")
            return step(self)
        Elasticity.step = failing
    from gsi import cli
    from gsi.run import Runner

    runner = {}
    original = Runner.run

    def dump_and_stop(self, restored):
        import numpy as np
        np.savez(f"{a.dump_restored}.rank{MPI.COMM_WORLD.rank}.npz",
                 **self.state(int(restored["runner.k"]), int(restored["runner.n_out"])))
        raise SystemExit(0)

    def run(self):
        runner["r"] = self
        if a.dump_restored:
            self.on_resume.append(dump_and_stop)
        return original(self)
    Runner.run = run
    argv = ["run", a.case, "--out", a.out, "--no-pictures"]
    if a.resume:
        argv.append("--resume")
    if a.quick:
        argv.append("--quick")
    if a.checkpoint_every is not None:
        argv += ["--checkpoint-every", str(a.checkpoint_every)]
    code = cli.main(argv)
    if code == 0 and a.dump:
        import numpy as np
        r = runner["r"]
        np.savez(f"{a.dump}.rank{MPI.COMM_WORLD.rank}.npz", **r.state(r.n_total, 0))
    return code


if __name__ == "__main__":
    sys.exit(main())
