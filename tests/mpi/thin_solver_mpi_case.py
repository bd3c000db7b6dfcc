"""The iterative solver against the direct one on thin walls, run under ``mpirun -n N`` by
tests/mpi/test_fem_solvers_mpi.py.

Arguments: out_path [variant] ("all", or "blr": the block low-rank Cholesky preset
alone, elasticity and heat, see :func:`main`). For the coarse P2 silo shell and clamped plate of
tests/unit/fem/test_fem_iterative_thin.py (the same cases), runs each with
``solver="direct"`` and ``solver="iterative"`` on this partition and writes (rank 0)
the largest difference of each field over all ranks, relative to the direct field's
largest value, with the iteration counts and the preconditioners used.
"""
import json
import sys

import numpy as np
from mpi4py import MPI

from gsi import meshes
from gsi.fem import compat
from gsi.fem.elasticity import Elasticity
from gsi.fem.heat import Heat
from gsi.meshes import shell


def _fields(sm, dt, solver, petsc=None, heat_petsc=None):
    """Static and dynamic elasticity and heat with ``solver``; with ``petsc`` (elasticity's
    options) the heat problem is solved directly unless ``heat_petsc`` is given too (BDDC
    is elasticity's)."""
    s = Elasticity(sm, "steel", degree=2, gravity=(0.0, 0.0, -9.81), solver=solver,
                   petsc_options=petsc)
    s.clamp("support")
    s.set_traction("contact", [1.0e3, 0.0, -2.0e4])
    s.solve()
    d = Elasticity(sm, "steel", degree=2, scheme="generalized_alpha", dt=dt, rho_inf=0.3,
                   gravity=(0.0, 0.0, -9.81), solver=solver, petsc_options=petsc)
    d.clamp("support")
    for k in range(2):
        d.set_traction("contact", [0.0, 1.0e3 * k, -2.0e4])
        d.step()
    h = Heat(sm, "steel", dt=1.0, T_initial=20.0, degree=2,
             solver=solver if petsc is None or heat_petsc else "direct",
             petsc_options=heat_petsc)
    h.fix_temperature("support", 80.0)
    h.set_convection("outer", 25.0, 20.0)
    h.set_flux("contact", 2.0e3)
    for _ in range(2):
        h.step()
    out = {}
    for name, f, shift in (("static u", s.u, 0.0), ("dynamic u", d.u, 0.0), ("dynamic v", d.v, 0.0),
                           ("dynamic a", d.a, 0.0), ("heat T - 20", h.T, 20.0)):
        imap, bs = compat.dof_index_map(f.function_space)
        out[name] = f.x.array[:imap.size_local * bs] - shift       # owned values
    info = dict(its=[p.iterations for p in (s, d, h)],
                pcs=[p.linear_solver.describe() for p in (s, d, h)],
                kinds=[p.solver_kind for p in (s, d, h)], n_dofs=s.n_dofs,
                reaction=np.asarray(s.reaction("support")).tolist())
    return out, info


def _errors(fields, ref, comm):
    """Largest difference of each field over all ranks, relative to the reference's
    largest value."""
    errs = {}
    for key in ref:
        diff = comm.allreduce(float(np.abs(fields[key] - ref[key]).max(initial=0.0)), op=MPI.MAX)
        top = comm.allreduce(float(np.abs(ref[key]).max(initial=0.0)), op=MPI.MAX)
        errs[key] = diff / top
    return errs


def _reaction_error(info, ref_info):
    r_ref, r = np.array(ref_info["reaction"]), np.array(info["reaction"])
    return float(np.abs(r - r_ref).max() / np.abs(r_ref).max())


def main(out_path, variant="all"):
    """``variant`` "all": BoomerAMG (and BDDC on several ranks) against direct; "blr":
    the block low-rank Cholesky preset (``petsc = { pc_type = "cholesky" }``) against
    direct, elasticity and heat."""
    comm = MPI.COMM_WORLD
    cases = {"shell": (meshes.build("shell", h=shell.h_for_dofs(2e3, n_thickness=1, components=3),
                                    n_thickness=1), 1.25e-4),
             "plate": (meshes.build("membrane", shape="circle", radius=0.5, thickness=0.02,
                                    h=0.16, n_thickness=2), 2.5e-4)}
    res = dict(n_ranks=comm.size)
    for name, (sm, dt) in cases.items():
        ref, dinfo = _fields(sm, dt, "direct")
        if variant == "blr":
            blr = {"pc_type": "cholesky"}
            fields, info = _fields(sm, dt, "iterative", blr, heat_petsc=blr)
            errs = dict(_errors(fields, ref, comm), reaction=_reaction_error(info, dinfo))
            res[name] = dict(errors=errs, direct=dinfo, blr=info)
            continue
        it, iinfo = _fields(sm, dt, "iterative")
        errs = _errors(it, ref, comm)
        errs["reaction"] = _reaction_error(iinfo, dinfo)
        res[name] = dict(errors=errs, direct=dinfo, iterative=iinfo)
        if comm.size > 1:               # BDDC: a subdomain per rank
            bd, binfo = _fields(sm, dt, "iterative", {"pc_type": "bddc"})
            res[name]["bddc"] = binfo
            res[name]["bddc_errors"] = {}
            for key in ("static u", "dynamic u", "dynamic v", "dynamic a"):
                diff = comm.allreduce(float(np.abs(bd[key] - ref[key]).max(initial=0.0)),
                                      op=MPI.MAX)
                top = comm.allreduce(float(np.abs(ref[key]).max(initial=0.0)), op=MPI.MAX)
                res[name]["bddc_errors"][key] = diff / top
    if comm.rank == 0:
        with open(out_path, "w") as fh:
            json.dump(res, fh)


if __name__ == "__main__":
    main(*sys.argv[1:])
