"""Size estimates of a case before it runs (``gsi check``): particles, DEM steps, outputs,
checkpoints, monitor rows, mixing cells, wall triangles and FE dofs; a one-line error
above a limit (with the estimate and the key to change), a one-line warning with the
estimated memory and wall time below it.

The rates behind the estimates are gsi's measured benchmarks (``benchmarks/results``):
the DEM moves about :data:`PARTICLE_STEPS_PER_S` particle-steps per second on one thread
and holds about :data:`BYTES_PER_PARTICLE` (settle_scale: 6.5e6-9.9e6 particle-steps/s,
493 bytes per particle); a P2 structure of 1e6 dofs took 6.8 GB and 31 min of set-up
out of core on 2 ranks (fe_scale), 1e5 dofs 1.3 GB in memory (:data:`FE_BYTES_PER_DOF`,
:data:`FE_SETUP_S_PER_DOF`). They are orders of magnitude, said as such ("about").
The dofs of every structure (each builder, a ``.geo`` or ``.msh`` file) come from its
:class:`gsi.meshes.footprint.Footprint`, the body known before it is meshed; the
extrapolation's replay from :data:`REPLAY_S_PER_PARTICLE_SAMPLE`."""
from __future__ import annotations

import math
import os

from gsi.errors import GsiInputError

__all__ = ["estimate", "check_sizes", "summary", "structure_dofs", "MAX_STEPS",
           "MAX_QUICK_STEPS", "MAX_CHECKPOINTS", "MAX_CELLS", "MAX_MONITOR_ROWS"]

PARTICLE_STEPS_PER_S = 7e6
BYTES_PER_PARTICLE = 500.0
FE_BYTES_PER_DOF = 7e3
FE_SETUP_S_PER_DOF = 2e-3
#: more DEM steps than this are refused (a run of 1e9 steps takes days even with few
#: particles: the step's fixed cost is microseconds)
MAX_STEPS = 1e9
#: a case with a driven wall (oscillation, servo, free; gsi.dem.wall_drivers) steps in
#: one-step chunks: a fixed cost per step (s) and a slower step (the next step's kick and
#: drift are no longer fused into the force pass); benchmarks/driven_walls.py measured
#: 5e-5 s per step and x1.4 at 200 and 2,000 beads on a shared 2-core host
DRIVEN_STEP_S = 1e-4
DRIVEN_FACTOR = 1.5
#: ``--quick`` is a smoke test: more steps than this are refused in its form
MAX_QUICK_STEPS = 1e7
MAX_CHECKPOINTS = 1000
MAX_CELLS = 10_000_000
MAX_MONITOR_ROWS = 10_000_000
#: refused when the estimated memory exceeds this many times the machine's (a case may be
#: prepared on a smaller machine than the one it runs on; beyond this it is a unit slip)
MEMORY_FACTOR = 4.0
#: a warning when the estimated wall time exceeds this (s)
WARN_WALL_S = 6 * 3600.0
#: a warning when the FE set-up needs more dofs than this
WARN_DOFS = 200_000
#: the extrapolation's replay, seconds per particle and logged sample (every x dt):
#: benchmarks/results drum_extrapolation, 5,000 particles, a turn of 3150 samples
#: replayed in 0.0213 s (1.35e-9; 80,000 particles: 7.9e-10)
REPLAY_S_PER_PARTICLE_SAMPLE = 1.35e-9
#: a replay estimated above this (s) is refused (a slip in the period count)
MAX_REPLAY_S = 30 * 86400.0


def _memory_bytes() -> float:
    """Physical memory of the machine (inf when unknown)."""
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return math.inf


def structure_footprint(st, base_dir):
    """The :class:`gsi.meshes.footprint.Footprint` of a structure (the body its mesh will
    occupy, after ``translate``, and its estimated mesh size), or None when unknown (a
    file gmsh cannot probe: the build reports it)."""
    from gsi.meshes import footprint
    if st.mesh is not None:
        return footprint.of_builder(st.mesh, st.geometry, st.translate)
    if st.file is None or not st.file_path(base_dir).is_file():
        return None
    return footprint.of_file(st.file_path(base_dir), st.geometry, st.translate)


def structure_dofs(st, base_dir) -> dict | None:
    """The estimated size of a structure before it is built, or None when unknown:
    ``dofs`` (3 per node for the elasticity, 1 for the heat, in the structure's Lagrange
    degree), ``how`` (words), its bounding box ``box`` ((lo, hi), m, after ``translate``)
    and largest ``extent`` (m); from :func:`structure_footprint`."""
    fp = structure_footprint(st, base_dir)
    if fp is None:
        return None
    comps = (3 if st.has_elasticity else 0) + (1 if st.has_heat else 0)
    return dict(dofs=fp.dofs(st.degree, comps), how=fp.how,
                box=(fp.lo.tolist(), fp.hi.tolist()), extent=fp.extent)


def estimate(case, dt: float) -> dict:
    """Sizes of the case (see the module docstring)."""
    d = case.run.duration
    n = 0
    for i, p in enumerate(case.particles):
        k = p.planned_count(duration=d)
        if k < 0:        # a file: its rows
            from gsi.case.sources import read_particle_file
            k = len(read_particle_file(case.base_dir / p.file, key=f"particles[{i}].file")["radius"])
        n += k
    steps = d / dt
    ck = case.run.checkpoint_interval
    est = dict(particles=n, steps=steps, outputs=d / case.output.interval,
               checkpoints=d / max(ck, dt) if ck > 0 else 0.0,
               wall_s=max(n, 1) * steps / PARTICLE_STEPS_PER_S,
               memory=n * BYTES_PER_PARTICLE, dofs={}, replay_s=0.0)
    if any(w.motion.driven for w in case.walls):
        est["wall_s"] = est["wall_s"] * DRIVEN_FACTOR + steps * DRIVEN_STEP_S
    ex = case.extrapolation
    if ex is not None:
        samples = ex.periods * ex.period / (ex.every * dt)
        est["replay_s"] = max(n, 1) * samples * REPLAY_S_PER_PARTICLE_SAMPLE
        est["wall_s"] += est["replay_s"]
    for i, st in enumerate(case.structures):
        got = structure_dofs(st, case.base_dir) if st.has_elasticity or st.has_heat else None
        if got is not None:
            est["dofs"][i] = got
            est["memory"] += got["dofs"] * FE_BYTES_PER_DOF
            est["wall_s"] += got["dofs"] * FE_SETUP_S_PER_DOF
    return est


def _hours(s: float) -> str:
    return f"{s / 3600:.3g} h" if s >= 3600 else f"{s / 60:.3g} min" if s >= 60 else f"{s:.2g} s"


def check_sizes(case, dt: float, *, quick: bool = False) -> list[str]:
    """Refuse a case whose sizes are beyond the limits (one line with the estimate and the
    key); below them, return the warnings (estimated wall time and memory) for the caller
    to give once every check has passed (so a refusal stays one line)."""
    est = estimate(case, dt)
    said = []
    d = case.run.duration
    q = "quick." if quick else ""
    limit = MAX_QUICK_STEPS if quick else MAX_STEPS
    if est["steps"] > limit:
        key = f"{q}run.dt" if case.run.dt is not None else f"{q}run.duration"
        raise GsiInputError(
            f"{key}: {est['steps']:.3g} DEM steps of {dt:.3g} s over {d:g} s (limit "
            f"{limit:.0e}{' for --quick' if quick else ''}; about {_hours(est['wall_s'])}); "
            f"{'raise run.dt (default 0.2 t_R)' if case.run.dt is not None else 'shorten it'}")
    ck = case.run.checkpoint_interval
    if ck > 0 and ck < dt:
        raise GsiInputError(f"{q}run.checkpoint_interval = {ck:g}: shorter than the DEM step "
                            f"{dt:.3g} s (a checkpoint every step); use >= {d / 100:.3g} s")
    if est["checkpoints"] > MAX_CHECKPOINTS:
        raise GsiInputError(f"{q}run.checkpoint_interval = {ck:g}: {est['checkpoints']:.3g} "
                            f"checkpoints (limit {MAX_CHECKPOINTS}); use >= "
                            f"{d / MAX_CHECKPOINTS:.3g} s")
    for i, st in enumerate(case.structures):
        n_sub = st.contact.n_sub
        if n_sub is not None and n_sub * dt > d:
            raise GsiInputError(
                f"{q}structures[{i}].contact.n_sub = {n_sub}: the FE step n_sub x dt = "
                f"{n_sub * dt:.3g} s is longer than the run ({d:g} s), the structure would "
                f"never step; use n_sub <= {max(1, int(d / dt / 100))} (or remove it)")
    for i, m in enumerate(case.monitors):
        if m.cells is not None and math.prod(m.cells) > MAX_CELLS:
            raise GsiInputError(f"{q}monitors[{i}].cells = {list(m.cells)}: "
                                f"{math.prod(m.cells):.3g} sample cells (limit {MAX_CELLS:.0e}); "
                                f"use a few particles per cell")
        rows = d / max(m.interval or case.output.interval, dt)
        if rows > MAX_MONITOR_ROWS:
            raise GsiInputError(f"{q}monitors[{i}].interval = {m.interval:g}: {rows:.3g} rows "
                                f"(limit {MAX_MONITOR_ROWS:.0e}); raise it")
    mem = _memory_bytes()
    for i, got in est["dofs"].items():
        dofs, how = got["dofs"], got["how"]
        need = dofs * FE_BYTES_PER_DOF
        key = _mesh_size_key(case.structures[i], f"{q}structures[{i}]")
        if need > MEMORY_FACTOR * mem:
            raise GsiInputError(
                f"{key}: about {dofs:.3g} FE dofs ({how}) need about {need / 1e9:.3g} GB, over "
                f"{MEMORY_FACTOR:g} x this machine's {mem / 1e9:.3g} GB (and about "
                f"{_hours(dofs * FE_SETUP_S_PER_DOF)} of set-up); raise the mesh size or check "
                f"its units (m)")
        if dofs > WARN_DOFS and not quick:
            said.append(f"{key}: about {dofs:.3g} FE dofs ({how}): expect about "
                        f"{need / 1e9:.3g} GB and {_hours(dofs * FE_SETUP_S_PER_DOF)} of set-up")
    ex = case.extrapolation
    if ex is not None:
        if ex.cells > max(est["particles"], 1):
            raise GsiInputError(f"{q}extrapolation.cells = {ex.cells}: more Voronoi cells than "
                                f"the {est['particles']:.3g} particles; each cell of the eq. 9 "
                                f"error needs particles: use at most a tenth of them")
        if est["replay_s"] > MAX_REPLAY_S:
            raise GsiInputError(
                f"{q}extrapolation.periods = {ex.periods}: the replay of {ex.periods:.3g} "
                f"periods of {est['particles']:.3g} particles takes about "
                f"{_hours(est['replay_s'])} (limit {_hours(MAX_REPLAY_S)}); check the "
                f"period count (periods x period = {ex.periods * ex.period:.3g} s)")
    dem_bytes = est["particles"] * BYTES_PER_PARTICLE
    if dem_bytes > MEMORY_FACTOR * mem:
        raise GsiInputError(f"{q}particles: about {est['particles']:.3g} particles need about "
                            f"{dem_bytes / 1e9:.3g} GB, over {MEMORY_FACTOR:g} x this machine's "
                            f"{mem / 1e9:.3g} GB; lower the counts")
    if est["wall_s"] > WARN_WALL_S and not quick:
        said.append(f"run.duration = {d:g}: about {est['steps']:.3g} DEM steps of "
                    f"{est['particles']:.3g} particles, about {_hours(est['wall_s'])} on one "
                    f"thread and {est['memory'] / 1e9:.2g} GB")
    return said


def _mesh_size_key(st, prefix: str) -> str:
    """The key that sets a structure's mesh size: ``geometry.h`` (a builder, or a file
    given h), the box builder's ``geometry.n`` without h, else the file."""
    if st.mesh == "box" and "h" not in st.geometry:
        return f"{prefix}.geometry.n"
    if st.mesh is not None or "h" in st.geometry:
        return f"{prefix}.geometry.h"
    return f"{prefix}.file"


def summary(est: dict) -> str:
    """One line of the estimate for ``gsi check``."""
    dofs = sum(v["dofs"] for v in est["dofs"].values())
    fe = f", about {dofs:.3g} FE dofs" if est["dofs"] else ""
    return (f"estimate: {est['particles']:.3g} particles, {est['steps']:.3g} DEM steps, "
            f"{est['outputs']:.3g} outputs, {est['checkpoints']:.3g} checkpoints{fe}; about "
            f"{_hours(est['wall_s'])} on one thread, {est['memory'] / 1e9:.2g} GB")
