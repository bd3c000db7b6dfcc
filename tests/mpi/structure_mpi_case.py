"""A Structure from the shipped meshes/belt.geo, thermo-mechanically coupled, under
``mpirun -n N`` (tests/mpi/test_structure_mpi.py).

Builds the belt with its physical groups mapped (gmsh on rank 0, the mesh distributed),
attaches it to a DEM on rank 0 holding a row of fixed hot particles pressed into its top,
and runs 15 coupling intervals as a runner does (begin, DEM steps in two pieces,
finish). A structure naming a missing group must fail with the same one-line error on
every rank (no rank left waiting). Rank 0 writes the records and key numbers as JSON.
"""
import json
import sys

import numpy as np
from mpi4py import MPI

from gsi import meshes
from gsi.case.structure import Structure
from gsi.config.schema import load
from gsi.dem import Material, Simulation
from gsi.errors import GsiInputError

TABLE = dict(name="belt", file="belt.geo",
             geometry=dict(length=0.2, width=0.06, thickness=0.006, h=0.02, layers=1),
             tags=dict(support="belt_ends", contact="belt_top", bottom="belt_bottom"),
             material="steel", c=44.0, degree=2, scheme="static", supports=["support"],
             thermal=dict(T_ref=300.0, convection=[dict(tag="bottom", h=500.0, T_ambient=300.0)]),
             contact=dict(tags=["contact"], mode="both", n_sub=20))
R, D = 2.0e-3, 4.0e-5


def main(out_path):
    comm = MPI.COMM_WORLD
    errors = []
    try:
        bad = load(Structure, dict(TABLE, tags=dict(support="clamped", contact="belt_top")),
                   "structures[1]")
        bad.build(comm=comm, dt_dem=2e-5, base_dir=meshes.DIR)
    except GsiInputError as exc:
        errors = comm.gather(str(exc), root=0)
    st = load(Structure, TABLE, "structures[0]")
    cs = st.build(comm=comm, dt_dem=2e-5, base_dir=meshes.DIR)
    sim = None
    if comm.rank == 0:
        ore = {"ore": Material(E=5e7, nu=0.25, rho=3000.0, k=2.0, cp=50.0)}
        name, wall = st.dem_wall_material(ore)
        sim = Simulation({**ore, name: wall}, heat="area", gravity=(0, 0, -9.81), dt=2e-5,
                         skin=5e-4, domain=((-0.12, -0.05, -0.02), (0.12, 0.05, 0.05)))
        x = np.array([(a, 0.0, 0.006 + R - D) for a in np.linspace(-0.06, 0.06, 5)])
        sim.fix(sim.add_particles(x, R, material="ore", T=np.linspace(600.0, 900.0, 5)))
    cs.attach(sim)
    for _ in range(15):
        cs.begin()
        if comm.rank == 0:
            sim.step(8)
            sim.step(12)
        cs.finish()
    h_m, h_t = cs.mechanics.history(), cs.thermal.history()
    summary = cs.summary()
    u = cs.interface.displacement()
    if comm.rank == 0:
        res = dict(n_ranks=comm.size, errors=errors, summary=summary,
                   mech={k: v.tolist() for k, v in h_m.items() if not k.startswith("wall_")},
                   heat={k: v.tolist() for k, v in h_t.items()}, u=u.ravel().tolist(),
                   T_particles=sim.T.tolist())
        with open(out_path, "w") as fh:
            json.dump(res, fh)


if __name__ == "__main__":
    main(sys.argv[1])
