"""Benchmark: one dynamic FE step on the silo wall at three mesh sizes.

For each element size h: build the silo mesh (flat bottom, steel, P1 unless --degree 2),
set up a Newmark (average acceleration) problem clamped at its base under gravity, time

* ``setup_s``: assembly of K, M and the effective matrix plus the factorization (the
  first-step set-up; FFCx form compilation is excluded by a warm-up on the coarsest mesh),
* ``factor_s``: the one MUMPS LU factorization alone,
* ``step_s``: the mean wall time of one step (nodal loads from the contact surface,
  RHS build with two mat-vecs, forward/back substitution, Newmark update),

and print one line per size, then one machine-readable last line of key=value pairs
(suffixes _1, _2, _3 from coarse to fine).

Run: ``python benchmarks/fe_step.py`` (add ``mpirun -n 2`` for the distributed solve).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from mpi4py import MPI

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout too

from gsi import meshes  # noqa: E402
from gsi.fem.elasticity import Elasticity  # noqa: E402
from gsi.fem.surface import ContactSurface  # noqa: E402


def run(h: float, *, degree: int, n_steps: int, factorization: str = "lu") -> dict:
    comm = MPI.COMM_WORLD
    sm = meshes.build("silo", radius=0.5, height=1.0, thickness=0.01, h=h)
    p = Elasticity(sm, "steel", degree=degree, scheme="newmark", dt=1e-4,
                   gravity=(0.0, 0.0, -9.81), factorization=factorization)
    p.clamp("support")
    s = ContactSurface(elasticity=p)
    loads = np.zeros((s.n_vertices, 3))
    loads[:, 0] = 1.0
    comm.barrier()
    t0 = time.perf_counter()
    p.set_up()                      # assemble K, M, A; factorize A once
    comm.barrier()
    t_setup = time.perf_counter() - t0
    t_factor = p.linear_solver.factor_seconds
    p.step()                        # first step outside the timing (caches)
    comm.barrier()
    t0 = time.perf_counter()
    for _ in range(n_steps):
        p.clear_nodal_loads()
        s.add_nodal_loads(loads)
        p.step()
    comm.barrier()
    t_step = (time.perf_counter() - t0) / n_steps
    t_step = comm.allreduce(t_step, op=MPI.MAX)
    t_factor = comm.allreduce(t_factor, op=MPI.MAX)
    t_setup = comm.allreduce(t_setup, op=MPI.MAX)
    assert p.n_factorizations == 1
    return dict(h=h, dofs=p.n_dofs, setup_s=t_setup, factor_s=t_factor, step_s=t_step,
                surface_vertices=s.n_vertices)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=float, nargs=3, default=[0.08, 0.05, 0.035],
                    help="three element sizes h (m), coarse to fine")
    ap.add_argument("--degree", type=int, default=1)
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--factorization", choices=["lu", "cholesky"], default="lu")
    args = ap.parse_args()
    comm = MPI.COMM_WORLD
    opts = dict(degree=args.degree, factorization=args.factorization)
    run(max(args.sizes), n_steps=1, **opts)   # warm-up: form compilation
    results = [run(h, n_steps=args.steps, **opts) for h in args.sizes]
    if comm.rank == 0:
        for r in results:
            print(f"h={r['h']:.4g} m  dofs={r['dofs']}  surface_vertices={r['surface_vertices']}  "
                  f"setup={r['setup_s']:.3f} s  factor={r['factor_s']:.3f} s  step={1e3 * r['step_s']:.2f} ms", flush=True)
        kv = [f"ranks={comm.size}", f"degree={args.degree}", f"factorization={args.factorization}"]
        for i, r in enumerate(results, start=1):
            kv += [f"dofs_{i}={r['dofs']}", f"setup_s_{i}={r['setup_s']:.4f}",
                   f"factor_s_{i}={r['factor_s']:.4f}",
                   f"step_s_{i}={r['step_s']:.5f}"]
        print(" ".join(kv), flush=True)


if __name__ == "__main__":
    main()
