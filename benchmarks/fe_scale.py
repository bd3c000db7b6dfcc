"""Benchmark: the FE problems at 10^4 to 10^6 dofs, direct against iterative, 1 against N ranks.

The structure is the ``shell`` builder's silo (radius 0.5 m, cylinder 1 m on a 0.4 m
conical hopper, steel wall 10 mm thick, ``--n-thickness`` P2 element layers through it,
held at the outlet rim), sized by its element size h so that each problem has the wanted
number of dofs (:func:`meshes.shell.h_for_dofs`; the heat problem, a scalar, gets its own
finer mesh). At ``--sizes`` sizes from ``--min-dofs`` to ``--max-dofs`` (geometric):

* ``static``: K u = f under self-weight and nodal loads on the contact surface (given on
  rank 0, as the coupling gives them): the first solve from u = 0, then ``--steps``
  solves with changed loads (the quasi-static coupling's pattern: a warm start);
* ``dynamic``: generalized-alpha steps (rho_inf = 0.3, gsi's structure default) of
  dt = 1.25e-4 s (T_1 / 20 of this silo, the coupling's choice) under self-weight and
  nodal loads that change every step;
* ``heat``: backward-Euler (theta = 1) steps of 1 s with a fixed temperature at the
  support, convection outside and nodal heat on the contact surface.

For each: ``setup_s`` (assembly and the factorization or the multigrid hierarchy;
FFCx compilation excluded by a warm-up), ``first_s`` (first solve), ``step_s`` (mean
per-step wall time of the following steps, all ranks), Krylov iterations per solve,
and the peak memory per rank (getrusage ru_maxrss, its high-water mark reset before each
case through /proc/self/clear_refs, glibc told to give freed memory back), summed
(``peak_gb``) and largest (``rank_gb``) over the ranks, with the resident memory at the
case's start (``base_gb``, summed: what earlier cases left, which the peak includes; with
``--largest-first`` it is the larger cases' heap). The last line is machine-readable
key=value: ``max_dofs`` (largest dynamic case), ``ranks``, ``solver`` (the fastest
dynamic step at the largest size run), ``step_s_at_max``
(its dynamic step), ``peak_mem_gb`` (the largest total over every case run), ``exponent``
(least-squares slope of log dynamic step time against log dofs of that solver; the other
solvers' slopes and largest steps as ``exponent_<solver>``, ``step_s_at_max_<solver>``),
the same slopes of the static re-solve and the heat step, the iterations at the
largest size, ``blas`` (the BLAS MUMPS runs on, :func:`gsi.fem.compat.blas_library`: the
direct and BDDC set-ups are 4-8 times slower on netlib's reference BLAS than on OpenBLAS)
and the load average (``uptime``) at the start and the end.

The direct solver is skipped above ``--direct-max-dofs`` (its memory grows faster than the
dofs), the static problem above ``--static-max-dofs`` (from u = 0 the iterative solver
needs ~2000 CG iterations on this thin wall: 27 s on one rank at 1e4 dofs).

With ``--structure plate`` the same is done for the clamped circular plate of the
validation case 6b (radius 0.5 m, 20 mm steel, two P2 layers, dt = 2.5e-4 s = T_1 / 20);
the last line then starts ``structure=plate``. Each record names its preconditioner
(``pc``: lu, cholesky, hypre, gamg); the last line gives, besides the headline solver's
``its_at_max``/``setup_s_at_max``, the other solver's as ``its_at_max_<solver>``,
``setup_s_at_max_<solver>``.

Crossover, issue 33's second step (2026-12-05, 1 rank, the host loaded 7-13 by other
jobs: ratios, not absolute times; iterative = CG + BoomerAMG, gsi's default since then;
direct = MUMPS LU; set-up / step wall seconds, CG iterations per step):

* shell, dynamic: 9.9e3 dofs 1.32 / 0.020 (direct) against 0.34 / 4.31, 204 its;
  2.5e4 6.20 / 0.078 against 1.00 / 17.4, 188; 7.3e4 42.0 / 0.25 against 3.07 / 52.2,
  160; 2.0e5 262 / 0.86 (3.37 GB) against 8.74 / 71.3, 126. The direct step is 80-220
  times faster, its set-up 4-30 times slower: the iterative path is cheaper in total for
  runs shorter than 0.2 / 0.3 / 0.75 / 3.6 steps;
* shell, heat (2.0e5): 49.8 / 0.43 against 5.2 / 3.9, 8 its: break-even at 13 steps;
* plate: see docs/performance.md ("Iterative FE solver: crossover and scaling model")
  and the records in benchmarks/results/fe_scale.json.

Block low-rank Cholesky as CG's preconditioner, issue 33's fifth step (2026-12-05,
2 ranks, load 4-8; gsi's preset ``--petsc '{"pc_type": "cholesky"}'``: MUMPS BLR,
epsilon 1e-5, CG to 1e-10): every MUMPS record also carries MUMPS's own load-independent
figures (``gflop``/``blr_gflop``: RINFOG(3)/(14), ``factor_entries``/``blr_entries``:
INFOG(29)/(35), ``mumps_mb``: INFOG(22)). At 998,280 dofs with the compressed factor on
disk (``"mat_mumps_icntl_22": 1``): 4 iterations per step (4 at 1e5), set-up 138 s, step
10.5 s, 9.0 GB; with epsilon 1e-4 7 iterations (5 at 1e5), 123 s, 15.6 s, 8.2 GB, and in
core 146 s, 19.2 s, 10.6 GB; the exact factor on disk (``out_of_core``, OpenBLAS) 253.5 s,
5.50 s, 6.82 GB. The compressed factor needs 7-8 times fewer flops than the exact one
(510 / 468 against 3,735 Gflop) and 2.4-2.6 times fewer entries (docs/performance.md,
"Block low-rank Cholesky as the preconditioner").

So ``auto`` stays direct wherever the factor fits. Earlier figures (2026-12-02, CG +
GAMG, 2 ranks, load 4-6): the direct dynamic step 60-670 times faster at 1e4-1e5 dofs
(1e5: 1.4 s against 81 s, 505 GAMG iterations); out of core, 2 ranks: 0.88 s per step at
4e5 dofs (2.9 GB) and 3.74 s at 998,280 dofs in 6.82 GB (set-up 1,882 s). GAMG's count
fell with the dofs (884 / 505 / 159 at 1e4 / 1e5 / 1e6) because the wall keeps one layer
while h falls (the elements get less flat), not because the method scales: refined
uniformly, every count grows (benchmarks/shell_precond.py).

Run::

    mpirun -n 2 python benchmarks/fe_scale.py --solver both --max-dofs 1e6 --sizes 5 \
        --steps 1 --direct-max-dofs 1.1e5 --static-max-dofs 1.1e4 --largest-first
    mpirun -n 1 python benchmarks/fe_scale.py --solver both --max-dofs 1e5 --sizes 3 \
        --steps 1 --static-max-dofs 1.1e4
    mpirun -n 2 python benchmarks/fe_scale.py --solver out_of_core --problems dynamic \
        --min-dofs 1e6 --max-dofs 1e6 --sizes 1 --steps 3
    mpirun -n 2 python benchmarks/fe_scale.py --solver iterative --problems dynamic \
        --min-dofs 1e6 --max-dofs 1e6 --sizes 1 --steps 2 \
        --petsc '{"pc_type": "cholesky", "mat_mumps_icntl_22": 1}'
    (the same at 1e5 / 2e5 / 4e5 with "mat_mumps_cntl_7": 1e-3, or "mat_mumps_icntl_35": 0
    for the exact factor)
    python benchmarks/fe_scale.py --structure shell --solver both --min-dofs 1e4 \
        --max-dofs 2e5 --sizes 4 --steps 1 --problems dynamic,heat --direct-max-dofs 2.1e5
    (the same with --structure plate)
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import sys
import time
from pathlib import Path

import numpy as np
from mpi4py import MPI

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout too

from gsi import meshes  # noqa: E402
from gsi.fem import compat  # noqa: E402
from gsi.fem.elasticity import Elasticity  # noqa: E402
from gsi.fem.heat import Heat  # noqa: E402
from gsi.fem.surface import ContactSurface  # noqa: E402
from gsi.meshes import shell  # noqa: E402

DT_DYNAMIC = 1.25e-4     # s, T_1 / 20 of the default shell (T_1 = 2.5 ms)
DT_PLATE = 2.5e-4        # s, T_1 / 20 of the clamped plate (T_1 about 5 ms)
DT_HEAT = 1.0            # s


def load_average() -> float:
    """1-minute load average of the machine (as ``uptime`` prints it)."""
    return os.getloadavg()[0]


def release_freed_memory() -> None:
    """Make glibc return large freed blocks to the system at once (a fixed mmap threshold
    of 64 kB: glibc otherwise raises it after the first large frees and keeps the memory),
    so that each case's peak is its own and not the heap left by the cases before it."""
    try:
        import ctypes
        libc = ctypes.CDLL("libc.so.6")
        libc.mallopt(-3, 65536)          # M_MMAP_THRESHOLD
        libc.mallopt(-1, 65536)          # M_TRIM_THRESHOLD
    except (OSError, AttributeError):
        pass


def reset_peak_memory() -> None:
    """Reset this process's resident-set high-water mark (Linux >= 4.0), so that the next
    ru_maxrss is the peak of what follows."""
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
    except OSError:
        pass


def resident_memory(comm) -> float:
    """Resident memory now (GB), summed over the ranks (VmRSS of /proc/self/status)."""
    gb = 0.0
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmRSS:"):
                    gb = float(line.split()[1]) / 1e6           # kB
    except OSError:
        pass
    return comm.allreduce(gb, op=MPI.SUM)


def peak_memory(comm) -> tuple[float, float]:
    """(sum over ranks, largest rank) of ru_maxrss (GB)."""
    gb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6   # kB on Linux
    return comm.allreduce(gb, op=MPI.SUM), comm.allreduce(gb, op=MPI.MAX)


def _surface_loads(s, k: int) -> np.ndarray:
    """Nodal loads on the contact surface (N), changing a little with the step k as the
    particles' loads do between two coupling steps (rank 0 only)."""
    x = s.x0
    return np.c_[0.2 * np.sin(6.0 * x[:, 2] + 0.1 * k), 0.2 * np.cos(5.0 * x[:, 0] - 0.1 * k),
                 -1.0 - 0.02 * k - x[:, 1] ** 2]


def run_elasticity(sm, scheme: str, solver: str, n_steps: int, petsc: dict,
                   dt: float = DT_DYNAMIC) -> dict:
    comm = MPI.COMM_WORLD
    kw = dict(dt=dt, rho_inf=0.3) if scheme != "static" else {}
    reset_peak_memory()
    base = resident_memory(comm)
    comm.barrier()
    p = Elasticity(sm, "steel", degree=2, scheme=scheme, gravity=(0.0, 0.0, -9.81),
                   solver=solver, petsc_options=petsc, **kw)
    p.clamp("support")
    s = ContactSurface(elasticity=p)
    advance = p.solve if scheme == "static" else p.step
    def load(k):
        p.clear_nodal_loads()
        s.add_nodal_loads(_surface_loads(s, k) if comm.rank == 0 else None)

    t_setup, times = _timed(comm, p.set_up, load, advance, n_steps)
    peak, rank_peak = peak_memory(comm)
    its = p.iterations
    out = dict(problem="static" if scheme == "static" else "dynamic", solver=p.solver_kind,
               pc=p.linear_solver.ksp.getPC().getType(), dofs=p.n_dofs, setup_s=t_setup, first_s=times[0],
               step_s=float(np.mean(times[1:])), its_first=its[0],
               its_step=float(np.mean(its[1:])), peak_gb=peak, rank_gb=rank_peak, base_gb=base,
               surface_vertices=s.n_vertices, umax=p.max_displacement(),
               **mumps_statistics(p.linear_solver.ksp.getPC()))
    p.linear_solver.destroy()
    return out


def _mumps_count(v: float) -> float:
    """A MUMPS entry count: a negative INFOG value is minus millions."""
    return -v * 1e6 if v < 0 else float(v)


def mumps_statistics(pc) -> dict:
    """MUMPS's own load-independent figures when ``pc`` is a MUMPS factorization (MUMPS
    5.5 users' guide): full-rank flops RINFOG(3) and those spent with block low-rank
    compression RINFOG(14) (Gflop), the factor's entries full rank INFOG(29) and after
    compression INFOG(35), the memory MUMPS used in the factorization summed over the
    ranks INFOG(22) (MB), its error code INFOG(1); {} for any other preconditioner."""
    try:
        if pc.getType() not in ("lu", "cholesky") or pc.getFactorSolverType() != "mumps":
            return {}
        F = pc.getFactorMatrix()
        return dict(gflop=F.getMumpsRinfog(3) / 1e9, blr_gflop=F.getMumpsRinfog(14) / 1e9,
                    factor_entries=_mumps_count(F.getMumpsInfog(29)),
                    blr_entries=_mumps_count(F.getMumpsInfog(35)),
                    mumps_mb=F.getMumpsInfog(22), mumps_infog1=F.getMumpsInfog(1))
    except Exception:          # noqa: BLE001 -- statistics only: a PETSc without them
        return {}


def _timed(comm, setup, load, advance, n_steps):
    """(set-up seconds, seconds of each of the n_steps + 1 steps): ``setup()`` once, then
    ``load(k)`` and a timed ``advance()`` per step, every rank in step (barriers)."""
    comm.barrier()
    t0 = time.perf_counter()
    setup()
    comm.barrier()
    t_setup = time.perf_counter() - t0
    times = []
    for k in range(n_steps + 1):
        load(k)
        comm.barrier()
        t0 = time.perf_counter()
        advance()
        comm.barrier()
        times.append(time.perf_counter() - t0)
    return t_setup, times


def run_heat(sm, solver: str, n_steps: int, petsc: dict) -> dict:
    comm = MPI.COMM_WORLD
    reset_peak_memory()
    base = resident_memory(comm)
    comm.barrier()
    h = Heat(sm, "steel", dt=DT_HEAT, theta=1.0, T_initial=20.0, degree=2, solver=solver,
             petsc_options=petsc)
    h.fix_temperature("support", 20.0)
    h.set_convection("outer", 10.0, 20.0)
    s = ContactSurface(heat=h)
    def load(k):
        h.clear_nodal_heat()
        s.add_nodal_heat(np.full(s.n_vertices, 1.0 + 0.1 * k) if comm.rank == 0 else None)

    t_setup, times = _timed(comm, h.set_up, load, h.step, n_steps)
    peak, rank_peak = peak_memory(comm)
    its = h.iterations
    out = dict(problem="heat", solver=h.solver_kind, pc=h.linear_solver.ksp.getPC().getType(),
               dofs=h.n_dofs, setup_s=t_setup,
               first_s=times[0], step_s=float(np.mean(times[1:])), its_first=its[0],
               its_step=float(np.mean(its[1:])), peak_gb=peak, rank_gb=rank_peak, base_gb=base,
               surface_vertices=s.n_vertices, Tmax=h.min_max()[1])
    h.linear_solver.destroy()
    return out


def build(target: float, *, n_thickness: int, components: int,
          structure: str = "shell") -> tuple[object, float, float]:
    """(mesh, h, build seconds) of the shell (or the clamped plate) with about ``target``
    dofs. The plate (radius 0.5 m, 20 mm steel, two P2 layers whatever ``n_thickness``):
    23.7e3 vector dofs at h = 0.05 m, dofs ~ 1/h^2."""
    comm = MPI.COMM_WORLD
    if structure == "plate":
        h = 0.05 * (23.7e3 * components / (3.0 * target)) ** 0.5
        args = dict(shape="circle", radius=0.5, thickness=0.02, h=h, n_thickness=2)
    else:
        h = shell.h_for_dofs(target, n_thickness=n_thickness, components=components)
        args = dict(h=h, n_thickness=n_thickness)
    comm.barrier()
    t0 = time.perf_counter()
    sm = meshes.build("membrane" if structure == "plate" else "shell", **args)
    comm.barrier()
    return sm, h, time.perf_counter() - t0


def slope(dofs, times) -> float:
    """Least-squares slope of log(times) against log(dofs) (nan below two points)."""
    if len(dofs) < 2:
        return float("nan")
    return float(np.polyfit(np.log(dofs), np.log(times), 1)[0])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max-dofs", type=float, default=1e6, help="largest size (dofs)")
    ap.add_argument("--min-dofs", type=float, default=1e4, help="smallest size (dofs)")
    ap.add_argument("--sizes", type=int, default=6, help="number of sizes (geometric)")
    ap.add_argument("--solver", choices=["direct", "out_of_core", "iterative", "both", "all"],
                    default="both", help="both: direct and iterative; all: the three")
    ap.add_argument("--problems", default="static,dynamic,heat",
                    help="comma-separated subset of static,dynamic,heat")
    ap.add_argument("--steps", type=int, default=2, help="timed steps after the first solve")
    ap.add_argument("--n-thickness", type=int, default=1, help="P2 element layers in the wall")
    ap.add_argument("--structure", choices=["shell", "plate"], default="shell",
                    help="the silo shell, or the clamped plate of validation case 6b "
                         "(dt = 2.5e-4 s, T_1 / 20)")
    ap.add_argument("--direct-max-dofs", type=float, default=4e5,
                    help="skip the direct solver above this size (memory)")
    ap.add_argument("--static-max-dofs", type=float, default=2e5,
                    help="skip the static problem above this size (iterative: 10^3 iterations)")
    ap.add_argument("--petsc", default="{}", help="JSON dict of PETSc options (iterative)")
    ap.add_argument("--petsc-direct", default="{}",
                    help='JSON dict of PETSc options (direct), e.g. \'{"pc_type": "cholesky", '
                         '"pc_factor_mat_solver_type": "mumps"}\'')
    ap.add_argument("--largest-first", action="store_true",
                    help="run the sizes from the largest down (its figures come first)")
    ap.add_argument("--json", default=None, help="write every record to this JSON file")
    args = ap.parse_args()
    release_freed_memory()
    comm = MPI.COMM_WORLD
    problems = [p for p in args.problems.split(",") if p]
    solvers = {"both": ["direct", "iterative"],
               "all": ["direct", "out_of_core", "iterative"]}.get(args.solver, [args.solver])
    petsc = json.loads(args.petsc)
    petsc_direct = json.loads(args.petsc_direct)
    dt = DT_PLATE if args.structure == "plate" else DT_DYNAMIC
    load0 = load_average()
    targets = np.geomspace(args.min_dofs, args.max_dofs, args.sizes)
    if args.largest_first:
        targets = targets[::-1]
    # warm-up: FFCx compilation of every form, outside the timings
    sm, _, _ = build(3e3, n_thickness=args.n_thickness, components=3)
    for solver in solvers:
        run_elasticity(sm, "static", solver, 1, {})
        run_elasticity(sm, "generalized_alpha", solver, 1, {})
        run_heat(sm, solver, 1, {})
    del sm
    records = []

    def report(r):
        records.append(r)
        if comm.rank == 0:
            print(f"{r['problem']:8s} {r['solver']:9s} {r['pc']:6s} dofs={r['dofs']:8d} h={r['h']:.4g} "
                  f"mesh={r['mesh_s']:.1f}s setup={r['setup_s']:.2f}s first={r['first_s']:.2f}s "
                  f"step={r['step_s']:.3f}s its={r['its_first']}/{r['its_step']:.0f} "
                  f"peak={r['peak_gb']:.2f}GB (rank max {r['rank_gb']:.2f}, at start "
                  f"{r['base_gb']:.2f}) "
                  f"surface_vertices={r['surface_vertices']} "
                  + (f"gflop={r['gflop']:.1f} blr_gflop={r['blr_gflop']:.1f} "
                     f"factor_entries={r['factor_entries']:.4g} "
                     f"blr_entries={r['blr_entries']:.4g} mumps_mb={r['mumps_mb']} "
                     f"infog1={r['mumps_infog1']} " if "gflop" in r else "")
                  + f"load={load_average():.1f}", flush=True)

    for target in targets:
        if {"static", "dynamic"} & set(problems):
            sm, h, t_mesh = build(target, n_thickness=args.n_thickness, components=3,
                                  structure=args.structure)
            for solver in solvers:
                if solver == "direct" and target > args.direct_max_dofs:
                    continue
                opts = petsc if solver == "iterative" else petsc_direct
                for prob, scheme in (("static", "static"), ("dynamic", "generalized_alpha")):
                    if prob == "static" and target > args.static_max_dofs:
                        continue
                    if prob in problems:
                        r = run_elasticity(sm, scheme, solver, args.steps, opts, dt=dt)
                        report(dict(r, h=h, mesh_s=t_mesh, ranks=comm.size))
            del sm
        if "heat" in problems:
            sm, h, t_mesh = build(target, n_thickness=args.n_thickness, components=1,
                                  structure=args.structure)
            for solver in solvers:
                if solver == "direct" and target > args.direct_max_dofs:
                    continue
                r = run_heat(sm, solver, args.steps, petsc if solver == "iterative" else petsc_direct)
                report(dict(r, h=h, mesh_s=t_mesh, ranks=comm.size))
            del sm
    if comm.rank != 0:
        return
    if args.json:
        Path(args.json).write_text(json.dumps(records, indent=1))
    # the headline solver: the fastest dynamic step at the largest size any solver ran
    dyn = [r for r in records if r["problem"] == "dynamic"]
    top = max((r["dofs"] for r in dyn), default=0)
    main_solver = min((r for r in dyn if r["dofs"] == top), key=lambda r: r["step_s"],
                      default={"solver": solvers[-1]})["solver"]

    def pick(prob, solver):
        rs = sorted((r for r in records if r["problem"] == prob and r["solver"] == solver),
                    key=lambda r: r["dofs"])
        return [r["dofs"] for r in rs], [r["step_s"] for r in rs], rs

    kv = [f"structure={args.structure}", f"ranks={comm.size}", f"solver={main_solver}"]
    dofs, steps, rs = pick("dynamic", main_solver)
    if rs:
        kv += [f"pc={rs[-1]['pc']}", f"max_dofs={dofs[-1]}", f"step_s_at_max={steps[-1]:.4g}",
               f"its_at_max={rs[-1]['its_step']:.0f}", f"setup_s_at_max={rs[-1]['setup_s']:.4g}"]
    kv += [f"peak_mem_gb={max(r['peak_gb'] for r in records):.3g}",
           f"exponent={slope(dofs, steps):.3f}"]
    for other in solvers:
        d, t, rs = pick("dynamic", other)
        if rs and other != main_solver:
            kv += [f"step_s_at_max_{other}={t[-1]:.4g}", f"dofs_at_max_{other}={d[-1]}",
                   f"its_at_max_{other}={rs[-1]['its_step']:.0f}",
                   f"setup_s_at_max_{other}={rs[-1]['setup_s']:.4g}",
                   f"exponent_{other}={slope(d, t):.3f}"]
    for prob in ("static", "heat"):
        d, t, rs = pick(prob, main_solver)
        if rs:
            kv += [f"exponent_{prob}={slope(d, t):.3f}", f"{prob}_dofs_at_max={d[-1]}",
                   f"{prob}_step_s_at_max={t[-1]:.4g}"]
    # the BLAS MUMPS ran on (the direct set-ups are 8 times slower on the reference one)
    kv += [f"blas={compat.blas_library()}", f"load_start={load0:.2f}",
           f"load_end={load_average():.2f}"]
    print(" ".join(kv), flush=True)


if __name__ == "__main__":
    main()
