"""Thermal silo driver: hot particles charged into a steel bin whose outer wall is cooled.

The DEM (particles, particle-particle and particle-wall conduction) is coupled to the
bin's FE heat and thermo-elastic problems through the bin's inner "contact" surface
(:class:`gsi.coupling.staggered.StaggeredCoupling` for forces and motion,
:class:`gsi.coupling.thermal.ThermalCoupling` for heat; see their docstrings for the
coupling step and the energy record). The outer surfaces lose heat by convection
h (T - T_ambient).

Writes under ``out``:

* ``structure.xdmf`` (+ .h5): wall temperature, displacement and von Mises stress
  (ParaView, Xdmf3ReaderT); ``structure.csv``: the FE key numbers at each output;
* ``particles.pvd`` + ``particles_*.vtu``: particles with their temperature;
* ``energy.csv``: the energy record of every coupling step (heat leaving the particles,
  heat entering the wall, convective loss, stored heats, drift, max wall T and stress);
  ``coupling.csv``: the mechanical balance record of every step;
* ``stress.csv``: at each output, max von Mises of the total, thermal-only (particle loads
  removed) and mechanical-only (T = T_ref) stress states (linear elasticity: the two
  add up to the total stress tensor);
* ``history.png`` (heat flow into the wall, max wall T, max stresses, energy drift vs
  time), ``silo_*.png`` snapshots (cut-away: particles coloured by temperature over the
  back half of the wall coloured by temperature) and ``silo.gif``.

Prints progress and a physics summary whose last line is ``key=value`` pairs.
MPI: the FE part runs on all ranks, the DEM and all particle output on rank 0.
"""
from __future__ import annotations

import csv
import dataclasses
import math
import pathlib
import time

import numpy as np

from gsi import viz  # before dolfinx: pictures render in-process (gsi.viz._preload_vtk)
from gsi.drivers.dem_setup import build_simulation, check_dt
from gsi.errors import GsiInputError


@dataclasses.dataclass
class ThermalSiloResult:
    """Key results of a thermal silo run (SI units; ``history``: the energy record arrays)."""

    n_particles: int
    n_lost: int
    time: float                  # s, simulated
    t_thermal: float             # s, physical time of the thermal evolution (time_scale x time)
    T_wall_initial: float        # K
    T_wall_max: float            # K, at the end
    T_particles_mean: float      # K, at the end
    heat_flow: float             # W into the wall, mean over the last 10 % of the steps
    Q_particles: float           # J, total heat the particles gave the wall
    Q_structure: float           # J, total heat the wall received through the nodal loads
    Q_convection: float          # J, total heat lost by the wall to the ambient
    balance_max: float           # J, largest |Q_structure - Q_particles| of one step
    drift_rel: float             # -, largest |energy drift| / energy transferred
    max_von_mises: float         # Pa, at the end
    max_von_mises_thermal: float  # Pa, thermal-only stress state at the end
    max_von_mises_mechanical: float  # Pa, particle-load-only stress state at the end
    weight: float                # N, weight of the particles
    wall_load_z: float           # N, time-averaged vertical force of the particles on the wall
    history: dict
    files: list


def check(case) -> None:
    """Checks beyond the schema: the DEM time step and the thermal set-up."""
    check_dt(case)
    _spec(case)


# ----------------------------------------------------------------------------- set-up
def _spec(case) -> dict:
    """What the driver reads from the case, in one place (validated)."""
    th = case.thermal
    st, co = case.structure, case.coupling
    if case.dem.heat == "none":
        raise GsiInputError("dem.heat = 'none': a thermal_silo case needs a particle "
                            "conduction model ('area', 'radius' or 'constant')")
    if th is None:
        raise GsiInputError("thermal: missing; a thermal_silo case needs a [thermal] table")
    if st is None or co is None:
        raise GsiInputError(f"{'structure' if st is None else 'coupling'}: missing; a "
                            "thermal_silo case needs [structure] and [coupling] tables")
    if co.n_sub is None:
        raise GsiInputError("coupling.n_sub: missing; a thermal_silo case needs the DEM steps "
                            "per FE step (the heat step is n_sub x run.dt)")
    from gsi.fem.materials import get_material
    mat = get_material(st.material_spec())
    wall = case.materials.get(co.wall_material)
    if wall is None:
        raise GsiInputError(f"coupling.wall_material = '{co.wall_material}': not a "
                            f"[materials.X] table; defined: {', '.join(sorted(case.materials))}")
    if not math.isclose(wall.k, mat.k, rel_tol=1e-9):
        raise GsiInputError(f"materials.{co.wall_material}.k = {wall.k}: must equal the "
                            f"structure's conductivity {mat.k} (W/(m K)); the particle-wall "
                            "conductance uses it")
    return dict(material=mat, wall_material=co.wall_material)


def _scaled_case(case, s):
    """The case with every particle material's cp divided by s (heat-capacity scaling)."""
    if s == 1.0:
        return case
    mats = {name: dataclasses.replace(m, cp=m.cp / s) for name, m in case.materials.items()}
    new = dataclasses.replace(case, materials=mats)
    new.base_dir = case.base_dir
    return new


def _stress_split(el, heat, T_ref):
    """Max von Mises (Pa) of the thermal-only and mechanical-only states (collective).

    Linear elasticity: sigma(loads, T) = sigma(loads, T_ref) + sigma(0, T). Two extra
    solves with the factorized matrix; the problem's state is restored afterwards.
    """
    from gsi.fem import compat
    from mpi4py import MPI
    u_saved = el.u.x.array.copy()
    loads = el.nodal.values.copy()

    def vm_max():
        el.solve()
        vm = el.von_mises()
        n = compat.num_cells_local(el.mesh)
        return el.comm.allreduce(float(vm.x.array[:n].max()) if n else 0.0, op=MPI.MAX)

    el.nodal.values[:] = 0.0
    el.set_temperature(heat.T)
    vm_thermal = vm_max()
    el.nodal.values[:] = loads
    el.set_temperature(T_ref)
    vm_mech = vm_max()
    el.set_temperature(heat.T)
    el.u.x.array[:] = u_saved
    return vm_thermal, vm_mech


def _snapshot_job(path, sim, wall, T_wall, *, clim, title):
    """Arguments of one cut-away picture, seen from -y: the back half (y > 0) of the wall
    and of the particles, both coloured by temperature (the cut shows the bed's inside)."""
    x = wall.vertices
    tri = wall.triangles
    back = x[tri].mean(axis=1)[:, 1] > 0.0
    lo, hi = x.min(axis=0), x.max(axis=0)
    c = 0.5 * (lo + hi)
    size = float((hi - lo).max())
    cam = dict(position=(c[0] + 0.3 * size, c[1] - 2.0 * size, c[2] + 1.4 * size),
               focal_point=tuple(c), up=(0.0, 0.0, 1.0))
    keep = sim.x[:, 1] > 0.0
    return dict(path=str(path), x=sim.x[keep], radius=sim.radius[keep],
                color_by="particle T (K)", values=sim.T[keep], clim=clim,
                surfaces=[dict(points=x, triangles=tri[back], values=np.asarray(T_wall),
                               name="wall T (K)", cmap="coolwarm", clim=clim)],
                camera=cam, title=title)


# ----------------------------------------------------------------------------- run
def run(case, *, out: pathlib.Path, quick: bool = False, verbose: bool = True) -> ThermalSiloResult:
    """Run a validated ``thermal_silo`` case; write its files under ``out``."""
    from mpi4py import MPI

    import meshes
    from gsi.coupling.staggered import StaggeredCoupling
    from gsi.coupling.thermal import ThermalCoupling
    from gsi.fem.elasticity import Elasticity
    from gsi.fem.heat import Heat
    from gsi.fem.output import FemOutput

    comm = MPI.COMM_WORLD
    root = 0
    is_root = comm.rank == root
    out = pathlib.Path(out)
    say = print if (verbose and is_root) else (lambda *a, **k: None)
    spec = _spec(case)
    th, st, co = case.thermal, case.structure, case.coupling
    s = th.time_scale
    T_ref = th.T_ref
    T_wall0 = th.T_wall_initial if th.T_wall_initial is not None else T_ref
    wall_clock = time.perf_counter()

    # structure: mesh, heat (capacity scaled by s), thermo-elasticity
    sm = meshes.build(st.mesh, comm=comm, **st.mesh_params())
    mat = spec["material"]
    mat_scaled = dataclasses.replace(mat, c=mat.c / s)
    dt_dem = check_dt(case)
    n_sub = co.n_sub
    for tag in th.cooled:
        if tag not in sm.tags or tag == "volume":
            raise GsiInputError(f"thermal.cooled = {list(th.cooled)}: '{tag}' is not a surface "
                                f"of the {st.mesh}; surfaces: "
                                f"{', '.join(sorted(k for k in sm.tags if k != 'volume'))}")
    heat = Heat(sm, mat_scaled, dt=n_sub * dt_dem, theta=th.theta, T_initial=T_wall0)
    for tag in th.cooled:
        heat.set_convection(tag, th.h, th.T_ambient)
    static = st.scheme == "static"
    rayleigh = list(st.rayleigh)
    el = Elasticity(sm, mat, degree=st.degree, scheme=st.scheme,
                    dt=None if static else n_sub * dt_dem, rho_inf=st.rho_inf,
                    rayleigh=rayleigh, T_ref=T_ref,
                    gravity=case.dem.gravity if st.self_weight else (0.0, 0.0, 0.0))
    st.apply_supports(el)
    el.set_temperature(T_wall0)

    # DEM on the root rank (particle cp scaled by s)
    sim = build_simulation(_scaled_case(case, s), dt=dt_dem) if is_root else None
    mech = StaggeredCoupling(sim, el, wall_material=spec["wall_material"], n_sub=n_sub,
                             tag=co.tag, root=root, csv_path=out / "coupling.csv")
    tc = ThermalCoupling(sim, heat, mechanics=mech, tag=co.tag, T_ref=T_ref, time_scale=s,
                         root=root, csv_path=out / "energy.csv")

    duration = (case.run.quick_duration or case.run.duration / 5) if quick else case.run.duration
    n_steps = max(1, int(round(duration / tc.dt)))
    every = max(1, int(round(case.run.output_interval / tc.dt)))
    n_png = 6
    png_every = max(every, (n_steps // n_png // every) * every or every)
    n_particles = comm.bcast(sim.n if is_root else None, root=root)
    say(f"thermal_silo: {n_particles} particles at {case.particles[0].temperature:g} K, "
        f"bin {sm.params}, {heat.n_dofs} T dofs, dt_DEM = {dt_dem:.3g} s, n_sub = {n_sub}, "
        f"dt_FE = {tc.dt:.3g} s, {n_steps} coupling steps ({duration:g} s simulated = "
        f"{s * duration:g} s of heating with time_scale {s:g}) -> {out}")

    fem_out = FemOutput(out, elasticity=el, heat=heat)
    writer = None
    if is_root:
        from gsi.dem.output import ParticleWriter
        writer = ParticleWriter(out, "particles")
    stress_rows = []
    frames = []
    clim = (min(T_wall0, th.T_ambient), max(p.temperature for p in case.particles))

    def output(k):
        fem_out.write(tc.t)
        vm_th, vm_me = _stress_split(el, heat, T_ref) if static else (math.nan, math.nan)
        rec = tc.records[-1] if tc.records else None
        vm = rec.max_von_mises if rec else 0.0
        stress_rows.append((tc.t, s * tc.t, vm, vm_th, vm_me))
        T_wall = tc._wall_T(tc._T_surf)
        if is_root:
            writer.write(sim)
            if k % png_every == 0 or k == n_steps:
                frames.append(_snapshot_job(
                    out / f"silo_{len(frames):03d}.png", sim, tc.wall, T_wall, clim=clim,
                    title=f"{case.case.name}  t = {tc.t:.3f} s (thermal {s * tc.t:.0f} s)"))
        if rec is not None:
            say(f"  t = {tc.t:7.4f} s ({s * tc.t:7.1f} s)  contacts {rec.n_contacts:5d}  "
                f"heat into wall {rec.heat_flow:9.4g} W  T_wall max {rec.T_wall_max:8.2f} K  "
                f"T_particles {rec.T_particles_mean:7.2f} K  von Mises {vm / 1e6:7.2f} MPa "
                f"(thermal {vm_th / 1e6:.2f}, loads {vm_me / 1e6:.2f})  "
                f"drift {rec.drift:.2e} J", flush=True)

    try:
        output(0)
        for k in range(1, n_steps + 1):
            tc.step()
            if k % every == 0 or k == n_steps:
                output(k)
    finally:
        fem_out.close()
        if writer is not None:
            writer.close()
        if is_root:
            with (out / "stress.csv").open("w", newline="") as fh:
                w = csv.writer(fh)
                w.writerow(["t", "t_thermal", "max_von_mises", "max_von_mises_thermal",
                            "max_von_mises_mechanical"])
                w.writerows(stress_rows)

    h = tc.history()
    files = [out / "structure.xdmf", out / "structure.csv", out / "energy.csv",
             out / "coupling.csv", out / "stress.csv"]
    weight = wall_load = 0.0
    n_lost = 0
    if is_root:
        files.append(out / "particles.pvd")
        sr = np.asarray(stress_rows)
        files.append(viz.plot_series(out / "history.png", h["t_thermal"], {
            "heat flow into wall": (h["heat_flow"], "W"),
            "max wall T": (h["T_wall_max"], "K"),
            "max von Mises": (h["max_von_mises"] / 1e6, "MPa"),
            "energy drift": (h["drift"], "J")},
            xlabel=f"thermal time (s) = {s:g} x simulated time",
            title=f"{case.case.name}: wall heating"))
        files.append(viz.plot_series(out / "stress.png", sr[:, 1], {
            "total": (sr[:, 2] / 1e6, "MPa"), "thermal only": (sr[:, 3] / 1e6, "MPa"),
            "particle loads only": (sr[:, 4] / 1e6, "MPa")},
            xlabel="thermal time (s)", title="max von Mises stress"))
        wall_clim = (T_wall0, max(float(h["T_wall_max"].max()), T_wall0 + 1.0))
        for job in frames:                          # the wall's own scale: its rise shows
            job["surfaces"][0]["clim"] = wall_clim
        pngs = [p for p in viz.render_snapshots(frames) if p is not None]
        files += pngs
        gif = viz.animation(out / "silo.gif", pngs, fps=3)
        if gif is not None:
            files.append(gif)
        g = np.asarray(case.dem.gravity, float)
        weight = float(np.sum(sim.mass) * np.linalg.norm(g))
        n_lost = sim.n_lost
    weight, n_lost = comm.bcast((weight, n_lost), root=root)
    tail = max(1, n_steps // 10)
    Q_p, Q_s = float(h["Q_particles"].sum()), float(h["Q_structure"].sum())
    last = stress_rows[-1]
    result = ThermalSiloResult(
        n_particles=int(h["n_particles"][-1]), n_lost=int(n_lost), time=tc.t,
        t_thermal=s * tc.t, T_wall_initial=T_wall0, T_wall_max=float(h["T_wall_max"][-1]),
        T_particles_mean=float(h["T_particles_mean"][-1]),
        heat_flow=float(h["heat_flow"][-tail:].mean()), Q_particles=Q_p, Q_structure=Q_s,
        Q_convection=float(h["Q_boundary_loss"].sum()),
        balance_max=float(np.abs(h["balance_error"]).max()),
        drift_rel=float(np.abs(h["drift"]).max() / max(abs(Q_p), 1e-300)),
        max_von_mises=float(last[2]), max_von_mises_thermal=float(last[3]),
        max_von_mises_mechanical=float(last[4]), weight=weight,
        wall_load_z=float(-h["wall_force_z"][-tail:].mean()), history=h, files=files)
    r = result
    say(f"summary: {r.n_particles} particles ({r.n_lost} lost) at {r.T_particles_mean:.1f} K "
        f"heated the wall from {r.T_wall_initial:.1f} K to max {r.T_wall_max:.1f} K in "
        f"{r.t_thermal:.1f} s of thermal time; heat into the wall {r.heat_flow:.4g} W "
        f"(particles gave {r.Q_particles:.4g} J, wall received {r.Q_structure:.4g} J, "
        f"largest per-step mismatch {r.balance_max:.2e} J, energy drift "
        f"{r.drift_rel:.2e} of the heat moved); convection took {r.Q_convection:.4g} J; "
        f"max von Mises {r.max_von_mises / 1e6:.2f} MPa (thermal {r.max_von_mises_thermal / 1e6:.2f}, "
        f"particle loads {r.max_von_mises_mechanical / 1e6:.3f}); wall carries "
        f"{r.wall_load_z:.4g} N of {r.weight:.4g} N weight; "
        f"wall time {time.perf_counter() - wall_clock:.1f} s")
    say(f"particles={r.n_particles} lost={r.n_lost} T_wall_max={r.T_wall_max:.3f} "
        f"T_particles={r.T_particles_mean:.3f} heat_flow={r.heat_flow:.4g} "
        f"balance_max={r.balance_max:.3e} drift_rel={r.drift_rel:.3e} "
        f"vm_max={r.max_von_mises:.4g} vm_thermal={r.max_von_mises_thermal:.4g} "
        f"vm_loads={r.max_von_mises_mechanical:.4g} load_ratio={r.wall_load_z / r.weight:.4f} "
        f"t_thermal={r.t_thermal:.4g}")
    return result
