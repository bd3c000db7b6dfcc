"""One loaded structure, run under ``mpirun -n N`` by tests/mpi/test_fem_mpi.py.

Writes a JSON file (rank 0) with rank-count-independent results: displacement norms
(static and after dynamic steps), the assembled load sum, the surface's gathered
displacement and the nodal loads as assembled back at the surface vertices.
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


def main(out_path):
    comm = MPI.COMM_WORLD
    sm = meshes.build("membrane", shape="circle", radius=0.5, thickness=0.01, h=0.06)
    # static: gravity, a traction, and surface nodal loads varying in space
    p = Elasticity(sm, "aluminium", degree=1, gravity=(0.0, 0.0, -9.81))
    p.clamp("support")
    p.set_traction("contact", [0.0, 0.0, -2.0e3])
    s = ContactSurface(elasticity=p)
    x = s.x0
    loads = np.c_[np.sin(7 * x[:, 0]), np.cos(5 * x[:, 1]), -1.0 - x[:, 0] ** 2]
    s.add_nodal_loads(loads if comm.rank == 0 else None)   # given on rank 0 only
    p.solve()
    # loads as assembled at the surface vertices (scatter, then gather back)
    Fvec = compat.function(p.V)
    Fvec.x.array[: p.load_vector().array.size] = p.nodal.values
    back = s.gather("elasticity", Fvec)
    owned = comm.allgather(s.n_owned("elasticity"))
    res = dict(owned_surface_vertices=owned, static_norm=p.displacement_norm(), load_sum=list(p.load_sum()),
               surface_u=s.displacement().tolist(), loads_back=back.tolist(),
               loads_in=loads.tolist(), global_ids=s.global_ids.tolist())
    # dynamic, generalized-alpha with damping, 5 steps
    d = Elasticity(sm, "aluminium", scheme="generalized_alpha", dt=2e-4, rho_inf=0.8,
                   rayleigh=(5.0, 1e-6))
    d.clamp("support")
    sd = ContactSurface(elasticity=d)
    sd.add_nodal_loads(loads)
    for _ in range(5):
        d.step()
    res["dynamic_norm"] = d.displacement_norm()
    res["dynamic_n_factorizations"] = d.n_factorizations
    # heat with a nodal heat load and convection
    h = Heat(sm, "aluminium", dt=0.5, T_initial=20.0)
    h.set_convection("outer", 25.0, 20.0)
    sh = ContactSurface(heat=h)
    sh.add_nodal_heat(np.abs(loads[:, 0]))
    for _ in range(3):
        h.step()
    res["heat_norm"] = compat.petsc_vec(h.T).norm()
    res["surface_T"] = sh.temperature().tolist()
    res["n_ranks"] = comm.size
    if comm.rank == 0:
        with open(out_path, "w") as fh:
            json.dump(res, fh)


if __name__ == "__main__":
    main(sys.argv[1])
