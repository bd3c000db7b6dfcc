"""Pour driver: particles fall into walls and settle; the smallest complete gsi case.

Writes under ``out``: ``particles.pvd`` + ``particles_*.vtu`` (ParaView), ``history.csv``
(time, particles, kinetic energy, wall force, bed height), ``pour.png`` (final bed),
``history.png`` (energy and wall load against time), and prints a summary whose last
line is ``key=value`` pairs. The physics check printed is the load balance of a bed at
rest: the vertical force of the walls equals the weight of the particles.
"""
from __future__ import annotations

import csv
import dataclasses
import pathlib
import time

import numpy as np

from gsi import viz  # before dolfinx: pictures render in-process (gsi.viz._preload_vtk)
from gsi.drivers.dem_setup import build_simulation, check_dt


@dataclasses.dataclass
class PourResult:
    n_particles: int
    n_lost: int
    time: float
    kinetic_energy: float
    weight: float
    wall_load: float
    bed_height: float
    files: list


def check(case) -> None:
    check_dt(case)


def _wall_force(sim) -> np.ndarray:
    total = np.zeros(3)
    for wall in [*sim.planes, *sim.mesh_walls]:
        total += wall.force
    return total


def _box_of(case):
    for w in case.walls:
        if w.kind == "box":
            return (w.lo, w.hi)
    return None


def run(case, *, out: pathlib.Path, quick: bool = False, verbose: bool = True) -> PourResult:
    from gsi.dem.output import ParticleWriter

    sim = build_simulation(case)
    duration = (case.run.quick_duration or case.run.duration / 5) if quick else case.run.duration
    n_steps = int(round(duration / sim.dt))
    every = max(1, int(round(case.run.output_interval / sim.dt)))
    writer = ParticleWriter(out, "particles")
    g = np.asarray(case.dem.gravity, dtype=float)
    rows = []
    wall_clock = time.perf_counter()
    if verbose:
        print(f"pour: {sim.n} particles, dt = {sim.dt:.3g} s, {n_steps} steps "
              f"({duration:g} s), output every {every} steps -> {out}")
    try:
        writer.write(sim)
        while sim.step_count < n_steps:
            sim.step(min(every, n_steps - sim.step_count))
            writer.write(sim)
            f_wall = _wall_force(sim)
            top = float(np.max(sim.x[:, 2] + sim.radius)) if sim.n else 0.0
            rows.append((sim.time, sim.n, sim.kinetic_energy(), *f_wall, top))
            if verbose:
                print(f"  t = {sim.time:7.4f} s  particles {sim.n:6d}  "
                      f"KE {rows[-1][2]:.3e} J  wall Fz {f_wall[2]:.4g} N  bed top {top:.4f} m",
                      flush=True)
    finally:
        writer.close()
        with (out / "history.csv").open("w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["time_s", "particles", "kinetic_energy_J", "wall_force_x_N",
                        "wall_force_y_N", "wall_force_z_N", "bed_top_m"])
            w.writerows(rows)

    mass = float(np.sum(sim.mass))
    weight = float(mass * np.linalg.norm(g))
    g_hat = g / np.linalg.norm(g)
    wall_load = float(_wall_force(sim) @ g_hat)  # force of the particles on the walls, along g
    files = [out / "particles.pvd", out / "history.csv"]
    if rows:
        arr = np.asarray(rows)
        files.append(viz.plot_series(out / "history.png", arr[:, 0], {
            "kinetic energy": (arr[:, 2], "J"),
            "wall force z": (arr[:, 5], "N"),
            "bed top": (arr[:, 6], "m")}, title=f"{case.case.name}: settling"))
    speed = np.linalg.norm(sim.v, axis=1)
    png = viz.snapshot(out / "pour.png", x=sim.x, radius=sim.radius, color_by="speed",
                       values=speed, box=_box_of(case), title=f"{case.case.name}  t = {sim.time:.3f} s")
    if png:
        files.append(png)
    result = PourResult(n_particles=sim.n, n_lost=sim.n_lost, time=sim.time,
                        kinetic_energy=sim.kinetic_energy(), weight=weight,
                        wall_load=wall_load,
                        bed_height=float(np.max(sim.x[:, 2] + sim.radius)),
                        files=files)
    if verbose:
        wall_s = time.perf_counter() - wall_clock
        print(f"summary: {result.n_particles} particles ({result.n_lost} lost), "
              f"weight {weight:.4g} N, walls carry {wall_load:.4g} N "
              f"({100 * wall_load / weight:.2f} % of the weight), "
              f"KE {result.kinetic_energy:.3e} J, bed top {result.bed_height:.4f} m, "
              f"wall time {wall_s:.1f} s")
        print(f"particles={result.n_particles} lost={result.n_lost} "
              f"load_ratio={wall_load / weight:.4f} ke={result.kinetic_energy:.3e} "
              f"bed_top={result.bed_height:.4f}")
    return result
