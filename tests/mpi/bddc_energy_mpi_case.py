"""Average-acceleration energy conservation with BDDC, run under ``mpirun -n 2`` by
tests/mpi/test_fem_solvers_mpi.py.

Arguments: out_path. The suddenly loaded bar of tests/validation/test_fem_newmark_bar.py
(average acceleration, no damping: 1/2 v.Mv + 1/2 u.Ku - f.u is conserved exactly by
the discrete scheme) for 3 periods of 100 steps, once with ``solver="direct"`` and once
with CG + BDDC (``pc_type = "bddc"``, its own ``ksp_rtol`` 1e-10); writes (rank 0) the
energy's spread over the run relative to its largest magnitude, and BDDC's iterations.
"""
import json
import sys

import numpy as np
from mpi4py import MPI

from gsi import meshes
from gsi.fem.elasticity import Elasticity
from gsi.fem.materials import StructuralMaterial

L, E, RHO, S = 1.0, 200e9, 7800.0, 1e6

#: gsi's BDDC as it comes (gsi.fem.options.ITERATIVE_DEFAULTS["elasticity_bddc"]): with
#: MUMPS for the coarse solve it failed on this bar (its coarse LU: PC reason FACTOR_OTHER;
#: the second solve: PETSc reason -11), hence PETSc's own LU there
BDDC = {"pc_type": "bddc"}


def _energy_spread(solver, petsc=None, n_periods=3, n_per=100):
    dt = 4 * L / np.sqrt(E / RHO) / n_per
    sm = meshes.build("box", length_x=L, length_y=0.05, length_z=0.05, n=(40, 1, 1))
    p = Elasticity(sm, StructuralMaterial(E=E, nu=0.0, rho=RHO), scheme="newmark", dt=dt,
                   solver=solver, petsc_options=petsc)
    p.clamp("x0")
    p.set_traction("x1", [S, 0.0, 0.0])
    energy = []
    for _ in range(n_periods * n_per):
        p.step()
        e = p.energies()
        energy.append(e["kinetic"] + e["strain"] + e["load_potential"])
    energy = np.array(energy)
    return dict(spread=float(np.ptp(energy) / np.abs(energy).max()),
                its=[int(i) for i in p.iterations], pc=p.linear_solver.describe())


def main(out_path):
    comm = MPI.COMM_WORLD
    res = dict(n_ranks=comm.size, direct=_energy_spread("direct"),
               bddc=_energy_spread("iterative", BDDC))
    if comm.rank == 0:
        with open(out_path, "w") as fh:
            json.dump(res, fh)


if __name__ == "__main__":
    main(*sys.argv[1:])
