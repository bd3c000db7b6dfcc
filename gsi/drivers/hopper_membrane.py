"""Hopper onto membrane: particles discharge from a conical hopper onto a clamped membrane.

The XDEM scenario of Fig. 15 (seed 000): particles fill a closed conical hopper (a rigid
DEM mesh wall, triangulated here) and rest on a slide gate under its outlet; at
``hopper.open_time`` the gate slides away sideways at ``hopper.gate_speed`` and the
stream falls onto a clamped elastic membrane (the FE structure ``[structure]``, dynamic),
which deflects while waves run through it; the particles roll toward the deepest point
and heap. The membrane and the DEM are coupled two-way by
:class:`gsi.coupling.staggered.StaggeredCoupling` (see its docstring for the coupling
step, the choice of n_sub and the balance record).

Writes under ``out``:

* ``particles.pvd`` + ``particles_*.vtu`` (ParaView), ``hopper.vtu`` (the cone);
* ``structure.xdmf`` (+ .h5): membrane displacement and von Mises stress
  (ParaView, Xdmf3ReaderT); ``structure.csv``: the FE key numbers at each output;
* ``coupling.csv``: the balance record of every coupling step (load, wall force,
  relative balance, work, wall-clock split);
* ``history.csv``: every coupling step, time, vertical interface load (N, negative
  = downward on the membrane), max deflection (m), discharged mass (kg: particles
  below the outlet), particles, largest balance error so far, work (J);
* ``history.png`` (load, deflection, discharged mass vs time), ``membrane_*.png``
  snapshots (particles coloured by speed over the deformed membrane coloured by |u|)
  and ``membrane.gif``.

Prints progress and a physics summary whose last line is ``key=value`` pairs.
MPI: the FE runs on all ranks; the DEM, particle output and pictures on rank 0.

Choices (DESIGN.md is silent): the membrane's self-weight is left out unless
``structure.self_weight`` (a belt or membrane is pre-tensioned to carry it; linear
elasticity has no pre-tension); ``structure.damping_ratio`` zeta sets mass-proportional
damping a0 = 2 zeta omega_1 from the estimated lowest period; the gate is a square plate
just under the outlet that slides until it clears the outlet and then stops.
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

__all__ = ["HopperMembraneResult", "check", "run", "cone_wall", "gate_plate"]


@dataclasses.dataclass
class HopperMembraneResult:
    """Key results of a hopper_membrane run (SI units)."""

    n_particles: int         # particles at the end
    n_lost: int              # particles that left the domain
    time: float              # s, simulated
    T_1: float               # s, estimated lowest period of the membrane
    n_sub: int               # DEM steps per FE step
    dt_fe: float             # s
    particle_mass: float     # kg, all particles at the start
    discharged_mass: float   # kg, below the outlet at the end
    load_z: float            # N, vertical interface load at the end (negative: down)
    load_z_min: float        # N, most negative vertical load of one step (impacts)
    weight_on_membrane: float  # N, weight of the particles resting below the outlet
    max_deflection: float    # m, largest |u| at the interface over the run
    final_deflection: float  # m, largest |u| at the end
    balance_max: float       # -, largest relative load/wall-force difference of one step
    work: float              # J, work of the interface loads on the membrane
    wall_dem: float          # s wall-clock in the DEM
    wall_fe: float           # s in FE steps
    wall_transfer: float     # s in transfers
    history: dict            # history.csv (one row per coupling step) as arrays
    files: list


# ----------------------------------------------------------------------------- geometry
def cone_wall(*, outlet_radius: float, top_radius: float, height: float, outlet_z: float,
              centre=(0.0, 0.0), facets: int = 48):
    """Triangulated truncated cone (vertical axis) from ``outlet_z`` up by ``height``.

    Rings of ``facets`` vertices; the number of rings keeps the triangles roughly
    equilateral at the top. Returns vertices (nv, 3) (m) and triangles (nt, 3).
    """
    n_z = max(1, int(math.ceil(height / (2 * math.pi * top_radius / facets))))
    th = 2 * math.pi * np.arange(facets) / facets
    V = []
    for k in range(n_z + 1):
        s = k / n_z
        r = outlet_radius + s * (top_radius - outlet_radius)
        V.append(np.c_[centre[0] + r * np.cos(th), centre[1] + r * np.sin(th),
                       np.full(facets, outlet_z + s * height)])
    V = np.vstack(V)
    T = []
    for k in range(n_z):
        a = k * facets + np.arange(facets)
        b = k * facets + (np.arange(facets) + 1) % facets
        T += [np.c_[a, b, b + facets], np.c_[a, b + facets, a + facets]]
    return V, np.vstack(T).astype(np.int64)


def gate_plate(*, half: float, z: float, centre=(0.0, 0.0)):
    """Square plate (two triangles) of half-width ``half`` (m) at height ``z`` (m)."""
    cx, cy = centre
    V = np.array([[cx - half, cy - half, z], [cx + half, cy - half, z],
                  [cx + half, cy + half, z], [cx - half, cy + half, z]])
    return V, np.array([[0, 1, 2], [0, 2, 3]], np.int64)


# ----------------------------------------------------------------------------- checks
def _sections(case):
    for key in ("structure", "coupling", "hopper"):
        if getattr(case, key) is None:
            raise GsiInputError(f"{key}: missing; a hopper_membrane case needs a [{key}] table")
    return case.structure, case.coupling, case.hopper


def check(case) -> None:
    """Checks beyond the schema: sections present, DEM time step, structure material."""
    from gsi.fem.materials import get_material
    st, co, hp = _sections(case)
    check_dt(case)
    get_material(st.material_spec())
    if st.degree not in (1, 2):
        raise GsiInputError(f"structure.degree = {st.degree}: must be 1 or 2")
    lo, hi = np.asarray(case.dem.domain_lo), np.asarray(case.dem.domain_hi)
    top = hp.outlet_z + hp.height
    if not (lo[2] < hp.outlet_z and top < hi[2]):
        raise GsiInputError(f"hopper.outlet_z = {hp.outlet_z}: the hopper (z {hp.outlet_z} to "
                            f"{top}) must lie inside dem.domain z ({lo[2]}, {hi[2]}) (m)")


def _quick_case(case, quick):
    """With --quick: each particle source's count times hopper.quick_fraction."""
    if not quick or case.hopper.quick_fraction >= 1.0:
        return case
    parts = [dataclasses.replace(p, count=max(1, int(round(p.count * case.hopper.quick_fraction))))
             if p.count is not None else p for p in case.particles]
    new = dataclasses.replace(case, particles=parts)
    new.base_dir = case.base_dir
    return new


# ----------------------------------------------------------------------------- pictures
def _snapshot(path, sim, mem_x, mem_tri, u_mag, cone, gate, *, clim_u, clim_v, title):
    lo = mem_x.min(axis=0)
    hi = np.maximum(mem_x.max(axis=0), cone[0].max(axis=0))
    c = 0.5 * (lo + hi)
    c[2] = lo[2] + 0.4 * (hi[2] - lo[2])
    size = float((hi - lo).max())
    cam = dict(position=(c[0] + 1.1 * size, c[1] - 2.0 * size, c[2] + 0.9 * size),
               focal_point=tuple(c), up=(0.0, 0.0, 1.0))
    speed = np.linalg.norm(sim.v, axis=1)
    return viz.snapshot(
        path, x=sim.x, radius=sim.radius, color_by="speed (m/s)", values=speed, clim=clim_v,
        surfaces=[dict(points=mem_x, triangles=mem_tri, values=1e3 * u_mag, name="|u| (mm)",
                       clim=clim_u, cmap="viridis"),
                  dict(points=cone[0], triangles=cone[1], opacity=0.25, color="lightsteelblue"),
                  dict(points=gate.vertices, triangles=gate.triangles, opacity=0.6,
                       color="grey")],
        camera=cam, title=title)


# ----------------------------------------------------------------------------- run
def run(case, *, out: pathlib.Path, quick: bool = False, verbose: bool = True,
        pictures: bool = True) -> HopperMembraneResult:
    """Run a validated ``hopper_membrane`` case; write its files under ``out``.

    ``pictures=False`` skips the PNG snapshots and the GIF (data files and the plot are
    still written).
    """
    from mpi4py import MPI
    pictures = pictures and MPI.COMM_WORLD.rank == 0

    import meshes
    from gsi.coupling.staggered import StaggeredCoupling, choose_n_sub, lowest_period
    from gsi.fem.elasticity import Elasticity
    from gsi.fem.materials import get_material
    from gsi.fem.output import FemOutput

    comm = MPI.COMM_WORLD
    root = 0
    is_root = comm.rank == root
    out = pathlib.Path(out)
    if is_root:
        out.mkdir(parents=True, exist_ok=True)
    say = print if (verbose and is_root) else (lambda *a, **k: None)
    check(case)
    st, co, hp = _sections(case)
    case = _quick_case(case, quick)
    wall_clock = time.perf_counter()

    # ---- structure: mesh, lowest period, time step, damping
    sm = meshes.build(st.mesh, comm=comm, **st.mesh_params())
    mat = get_material(st.material_spec())
    dt_dem = check_dt(case)
    static = Elasticity(sm, mat, degree=st.degree)
    st.apply_supports(static)
    T_1 = lowest_period(static)
    n_sub = co.n_sub or choose_n_sub(dt_dem, T_1, steps_per_period=co.steps_per_period)
    dt_fe = n_sub * dt_dem
    a0, a1 = st.rayleigh
    if st.damping_ratio is not None:
        a0 = 2.0 * st.damping_ratio * 2.0 * math.pi / T_1
    gravity = case.dem.gravity if st.self_weight else (0.0, 0.0, 0.0)
    if st.scheme == "static":
        el = static
        el.set_gravity(gravity)
    else:
        el = Elasticity(sm, mat, degree=st.degree, scheme=st.scheme, dt=dt_fe,
                        rho_inf=st.rho_inf, rayleigh=(a0, a1), gravity=gravity)
        st.apply_supports(el)

    # ---- DEM on the root rank: particles, the case's walls, hopper cone and gate
    sim = gate = cone_w = None
    cone = cone_wall(outlet_radius=hp.outlet_radius, top_radius=hp.top_radius,
                     height=hp.height, outlet_z=hp.outlet_z, centre=hp.centre[:2],
                     facets=hp.facets)
    gate_half = hp.outlet_radius + 2.0 * max(p.size.largest for p in case.particles)
    if is_root:
        sim = build_simulation(case, dt=dt_dem)
        cone_w = sim.add_mesh_wall(*cone, material=hp.material)
        gate = sim.add_mesh_wall(*gate_plate(half=gate_half, z=hp.outlet_z,
                                             centre=hp.centre[:2]), material=hp.material)
        gate.set_motion(velocity=(0.0, 0.0, 0.0))
    coupling = StaggeredCoupling(sim, el, wall_material=co.wall_material, n_sub=n_sub,
                                 tag=co.tag, root=root, relaxation=co.relaxation,
                                 csv_path=out / "coupling.csv")
    itf = coupling.interface

    duration = (case.run.quick_duration or case.run.duration / 5) if quick else case.run.duration
    open_time = hp.quick_open_time if (quick and hp.quick_open_time is not None) else hp.open_time
    n_steps = max(1, int(round(duration / dt_fe)))
    every = max(1, int(round(case.run.output_interval / dt_fe)))
    gate_travel = 2.0 * gate_half + 2.0 * max(p.size.largest for p in case.particles)
    mass0 = comm.bcast(float(sim.mass.sum()) if is_root else None, root=root)
    n0 = comm.bcast(int(sim.n) if is_root else None, root=root)
    say(f"hopper_membrane: {n0} particles ({mass0:.3f} kg), membrane {st.mesh} P{st.degree} "
        f"{el.n_dofs} dofs on {comm.size} rank(s), T_1 = {T_1 * 1e3:.1f} ms, dt_DEM = "
        f"{dt_dem:.3g} s, n_sub = {n_sub} (dt_FE = {dt_fe * 1e3:.2f} ms), {n_steps} coupling "
        f"steps ({duration:g} s), gate opens at {open_time:g} s -> {out}")

    # ---- output
    from gsi.dem.output import ParticleWriter, write_wall_vtu
    writer = ParticleWriter(out, "particles") if is_root else None
    if is_root:
        write_wall_vtu(out / "hopper.vtu", cone_w)
    fem_out = FemOutput(out, elasticity=el)
    rows, frames = [], []
    clim_v = (0.0, math.sqrt(2 * 9.81 * (hp.outlet_z + hp.height)))
    state = {"gate": "closed", "gate_x0": None, "bal": 0.0}

    def record(rec):
        """One history row per coupling step (root): time, load, deflection, discharge."""
        if is_root:
            below = sim.x[:, 2] < hp.outlet_z - sim.radius
            rows.append((coupling.t, rec.load_z if rec else 0.0,
                         rec.max_deflection if rec else 0.0, float(sim.mass[below].sum()),
                         int(sim.n), state["bal"], coupling.work))

    def output():
        fem_out.write(coupling.t)
        u = itf.displacement()
        umag = np.sqrt((u ** 2).sum(axis=1))
        if not is_root:
            return
        writer.write(sim)
        row = rows[-1]
        say(f"  t = {coupling.t:6.3f} s  particles {sim.n:5d}  load_z {row[1]:8.3f} N  "
            f"max |u| {1e3 * row[2]:7.3f} mm  discharged {row[3]:.3f} kg  "
            f"balance {state['bal']:.1e}", flush=True)
        if pictures:
            frames.append(_snapshot(
                out / f"membrane_{len(frames):04d}.png", sim, itf.x0 + u, itf.triangles, umag,
                cone, gate, clim_u=None, clim_v=clim_v,
                title=f"{case.case.name}  t = {coupling.t:.3f} s"))

    try:
        record(None)
        output()
        for k in range(n_steps):
            if is_root and state["gate"] != "open":
                if state["gate"] == "closed" and coupling.t >= open_time - 1e-12:
                    gate.set_motion(velocity=(hp.gate_speed, 0.0, 0.0))
                    state["gate"], state["gate_x0"] = "moving", float(gate.vertices[0, 0])
                elif state["gate"] == "moving" and \
                        gate.vertices[0, 0] - state["gate_x0"] >= gate_travel:
                    gate.set_motion(velocity=(0.0, 0.0, 0.0))
                    state["gate"] = "open"
            rec = coupling.step()
            state["bal"] = max(state["bal"], rec.balance_rel)
            record(rec)
            if (k + 1) % every == 0 or k + 1 == n_steps:
                output()
    finally:
        fem_out.close()
        if is_root:
            writer.close()
            with (out / "history.csv").open("w", newline="") as fh:
                w = csv.writer(fh)
                w.writerow(["time_s", "load_z_N", "max_deflection_m", "discharged_mass_kg",
                            "particles", "balance_rel_max", "work_J"])
                w.writerows([[f"{v:.10g}" if isinstance(v, float) else v for v in r]
                             for r in rows])

    # ---- results, pictures, summary
    hist = coupling.history()
    info = None
    files = []
    if is_root:
        arr = np.asarray(rows, float)
        history = dict(t=arr[:, 0], load_z=arr[:, 1], max_deflection=arr[:, 2],
                       discharged_mass=arr[:, 3], n_particles=arr[:, 4])
        files = [out / "particles.pvd", out / "structure.xdmf", out / "history.csv",
                 out / "coupling.csv"]
        files.append(viz.plot_series(out / "history.png", arr[:, 0], {
            "load on the membrane (down)": (-arr[:, 1], "N"),
            "max deflection": (1e3 * arr[:, 2], "mm"),
            "discharged mass": (arr[:, 3], "kg")},
            title=f"{case.case.name}: hopper discharge onto a membrane"))
        frames = [f for f in frames if f is not None]
        files += frames
        gif = viz.animation(out / "membrane.gif", frames, fps=6)
        if gif:
            files.append(gif)
        below = sim.x[:, 2] < hp.outlet_z - sim.radius
        g = float(np.linalg.norm(case.dem.gravity))
        info = dict(n=int(sim.n), lost=int(sim.n_lost), t=coupling.t,
                    m_dis=float(sim.mass[below].sum()),
                    w_mem=float(sim.mass[below].sum()) * g, history=history, files=files)
    info = comm.bcast(info, root=root)
    u_end = itf.displacement()
    result = HopperMembraneResult(
        n_particles=info["n"], n_lost=info["lost"], time=info["t"], T_1=T_1, n_sub=n_sub,
        dt_fe=dt_fe, particle_mass=mass0, discharged_mass=info["m_dis"],
        load_z=float(hist["load_z"][-1]), load_z_min=float(hist["load_z"].min()),
        weight_on_membrane=info["w_mem"],
        max_deflection=float(hist["max_deflection"].max()),
        final_deflection=float(np.sqrt((u_end ** 2).sum(axis=1)).max()),
        balance_max=float(hist["balance_rel"].max()), work=coupling.work,
        wall_dem=float(hist["wall_dem"].sum()), wall_fe=float(hist["wall_fe"].sum()),
        wall_transfer=float(hist["wall_transfer"].sum()), history=info["history"],
        files=info["files"])
    r = result
    total = r.wall_dem + r.wall_fe + r.wall_transfer
    say(f"summary: {n0} particles ({mass0:.3f} kg), {r.discharged_mass:.3f} kg discharged "
        f"({r.n_lost} lost over the rim); the membrane carries {-r.load_z:.3f} N at the end vs "
        f"{r.weight_on_membrane:.3f} N weight of the discharged particles "
        f"(peak {-r.load_z_min:.3f} N during impacts); max deflection {1e3 * r.max_deflection:.2f} "
        f"mm (end {1e3 * r.final_deflection:.2f} mm); load balance max rel. error "
        f"{r.balance_max:.1e}; work on the membrane {r.work:.3e} J; wall time "
        f"{time.perf_counter() - wall_clock:.1f} s (DEM {100 * r.wall_dem / total:.0f} %, FE "
        f"{100 * r.wall_fe / total:.0f} %, transfer {100 * r.wall_transfer / total:.0f} %)")
    say(f"particles={n0} discharged_kg={r.discharged_mass:.4f} load_z={r.load_z:.4f} "
        f"max_deflection={r.max_deflection:.5e} balance_max={r.balance_max:.2e} "
        f"work={r.work:.4e} n_sub={n_sub}")
    return result
