"""One structure solved with a chosen linear solver, run under ``mpirun -n N`` by
tests/mpi/test_fem_solvers_mpi.py.

Arguments: out_path, solver ("direct", "out_of_core" or "iterative"), mesh ("slab": a small thick disc;
"shell": the silo shell of ``meshes.shell`` at the element size given next), [h].
Writes (rank 0) rank-count-independent results of a static solve, five generalized-alpha
steps and three heat steps: norms, the gathered contact-surface displacement and
temperature, the iteration counts and the number of preconditioner set-ups.
"""
import json
import sys

import numpy as np
from mpi4py import MPI

from gsi import meshes
from gsi.fem import compat
from gsi.fem.elasticity import Elasticity
from gsi.fem.heat import Heat
from gsi.fem.surface import ContactSurface


def main(out_path, solver, mesh, h=None):
    comm = MPI.COMM_WORLD
    if mesh == "slab":
        sm = meshes.build("membrane", shape="circle", radius=0.3, thickness=0.03, h=0.06)
    else:
        sm = meshes.build("shell", h=float(h), n_thickness=1)
    res = dict(n_ranks=comm.size, solver=solver)
    p = Elasticity(sm, "steel", degree=2, gravity=(0.0, 0.0, -9.81), solver=solver)
    p.clamp("support")
    s = ContactSurface(elasticity=p)
    x = s.x0
    loads = np.c_[np.sin(7 * x[:, 0]), np.cos(5 * x[:, 1]), -1.0 - x[:, 0] ** 2]
    s.add_nodal_loads(loads if comm.rank == 0 else None)
    p.solve()
    res.update(n_dofs=p.n_dofs, static_norm=p.displacement_norm(),
               static_surface_u=s.displacement().tolist(), static_its=p.iterations,
               static_reaction=p.reaction("support").tolist())
    d = Elasticity(sm, "steel", degree=2, scheme="generalized_alpha", dt=1.25e-4, rho_inf=0.3,
                   rayleigh=(5.0, 0.0), solver=solver)
    d.clamp("support")
    sd = ContactSurface(elasticity=d)
    for k in range(5):
        d.clear_nodal_loads()
        sd.add_nodal_loads(loads * (1.0 + 0.1 * k) if comm.rank == 0 else None)
        d.step()
    res.update(dynamic_norm=d.displacement_norm(), dynamic_surface_u=sd.displacement().tolist(),
               dynamic_its=d.iterations, dynamic_setups=d.n_factorizations)
    h = Heat(sm, "steel", dt=1.0, T_initial=20.0, degree=2, solver=solver)
    h.fix_temperature("support", 20.0)
    h.set_convection("outer", 25.0, 20.0)
    sh = ContactSurface(heat=h)
    sh.add_nodal_heat(np.abs(loads[:, 0]) if comm.rank == 0 else None)
    for _ in range(3):
        h.step()
    res.update(heat_norm=compat.petsc_vec(h.T).norm(), surface_T=sh.temperature().tolist(),
               heat_its=h.iterations, heat_setups=h.n_factorizations,
               solver_kinds=[p.solver_kind, d.solver_kind, h.solver_kind])
    if comm.rank == 0:
        with open(out_path, "w") as fh:
            json.dump(res, fh)


if __name__ == "__main__":
    main(*sys.argv[1:])
