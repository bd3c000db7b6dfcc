"""A hot-particles-on-a-plate thermo-mechanical coupled run, under ``mpirun -n N``
(tests/mpi/test_thermal_mpi.py).

Sixteen hot particles, held fixed in contact with a clamped steel plate cooled on its
underside, heat it through the DEM <-> FE coupling (DEM on rank 0, FE on all ranks).
Rank 0 writes a JSON file with rank-count-independent results: the energy records, the
gathered surface temperature and displacement, and the particle temperatures.
"""
import json
import sys

import numpy as np
from mpi4py import MPI

from gsi import meshes
from gsi.coupling.staggered import StaggeredCoupling
from gsi.coupling.thermal import ThermalCoupling
from gsi.dem import Material, Simulation
from gsi.fem.elasticity import Elasticity
from gsi.fem.heat import Heat

L, LZ, R, D = 0.04, 0.004, 2.0e-3, 4.0e-5
STEEL = dict(E=210e9, nu=0.3, rho=7850.0, c=44.0, k=53.3, alpha=12e-6)


def main(out_path):
    comm = MPI.COMM_WORLD
    plate = meshes.build("box", length_x=L, length_y=L, length_z=LZ, n=(8, 8, 2))
    dt, n_sub = 2e-5, 20
    heat = Heat(plate, STEEL, dt=n_sub * dt, T_initial=300.0)
    heat.set_convection("z0", 500.0, 300.0)
    el = Elasticity(plate, STEEL, T_ref=300.0)
    el.clamp("x0")
    sim = None
    if comm.rank == 0:
        sim = Simulation({"ore": Material(E=5e7, nu=0.25, rho=3000.0, k=2.0, cp=50.0),
                          "steel": Material(E=210e9, nu=0.3, rho=7850.0, k=53.3)},
                         heat="area", gravity=(0, 0, -9.81), dt=dt, skin=5e-4,
                         domain=((-0.01, -0.01, -0.01), (L + 0.01, L + 0.01, 0.03)))
    mech = StaggeredCoupling(sim, el, wall_material="steel", n_sub=n_sub, tag="z1")
    tc = ThermalCoupling(sim, heat, mechanics=mech, tag="z1", T_ref=300.0)
    if comm.rank == 0:
        g = (np.arange(4) + 0.6) * L / 4.3
        x = np.array([(a, b, LZ + R - D) for a in g for b in g])
        ids = sim.add_particles(x, R, material="ore", T=np.linspace(600.0, 900.0, len(x)))
        sim.fix(ids)
    tc.run(60)
    h = tc.history()
    T_surf = tc.surface.temperature()
    u_surf = tc.mechanics.interface.displacement()
    if comm.rank == 0:
        res = {k: v.tolist() for k, v in h.items()}
        res.update(n_ranks=comm.size, T_surf=T_surf.tolist(), u_surf=u_surf.ravel().tolist(),
                   T_particles=sim.T.tolist(), wall_x=tc.wall.vertices.ravel().tolist())
        with open(out_path, "w") as fh:
            json.dump(res, fh)


if __name__ == "__main__":
    main(sys.argv[1])
