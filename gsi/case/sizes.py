"""Size estimates of a case before it runs (``gsi check``): particles, DEM steps, outputs,
checkpoints, monitor rows, mixing cells, wall triangles and FE dofs; a one-line error
above a limit (with the estimate and the key to change), a one-line warning with the
estimated memory and wall time below it.

The rates behind the estimates are gsi's measured benchmarks (``benchmarks/results``):
the DEM moves about :data:`PARTICLE_STEPS_PER_S` particle-steps per second on one thread
and holds about :data:`BYTES_PER_PARTICLE` (settle_scale: 6.5e6-9.9e6 particle-steps/s,
493 bytes per particle); a P2 structure of 1e6 dofs took 6.8 GB and 31 min of set-up
out of core on 2 ranks (fe_scale), 1e5 dofs 1.3 GB in memory (:data:`FE_BYTES_PER_DOF`,
:data:`FE_SETUP_S_PER_DOF`). They are orders of magnitude, said as such ("about")."""
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


def _memory_bytes() -> float:
    """Physical memory of the machine (inf when unknown)."""
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return math.inf


def structure_dofs(st, base_dir) -> dict | None:
    """The estimated size of a structure before it is built, or None when unknown:
    ``dofs``, ``how`` (words), and for a gmsh file its bounding box ``box`` ((lo, hi), m,
    after ``translate``) and largest ``extent`` (m). A gmsh file: the mesh size h measured
    on its curves (a 1D mesh, cheap) and its bounding box: a surface mesh of size h has
    about A/(0.87 h^2) vertices on the box's area A; P2 adds about 3 edge nodes per vertex;
    3 dofs per node. This counts the surface only (a lower bound for a bulky body). The
    shell builder: its own estimate."""
    if st.mesh == "shell":
        from gsi.meshes.shell import estimate_dofs
        return dict(dofs=float(estimate_dofs(**st.geometry)),
                    how="the shell builder's estimate", box=None, extent=None)
    if st.file is None or not st.file_path(base_dir).is_file():
        return None
    found = _probe(st.file_path(base_dir), st.geometry)
    if found is None:
        return None
    lo, hi, h = found
    dx, dy, dz = (b - a for a, b in zip(lo, hi))
    area = 2.0 * (dx * dy + dy * dz + dz * dx)
    vertices = area / (0.866 * h * h)
    per = 4.0 if st.degree == 2 else 1.0
    shift = [float(t) for t in st.translate]
    return dict(dofs=3.0 * per * vertices,
                how=f"mesh size h = {h:.3g} m over a {dx:.3g} x {dy:.3g} x {dz:.3g} m body",
                box=([a + t for a, t in zip(lo, shift)], [b + t for b, t in zip(hi, shift)]),
                extent=max(dx, dy, dz))


def _probe(path, params) -> tuple[list, list, float] | None:
    """(bounding-box lo, hi, mean curve mesh size) of a gmsh file, from a 1D mesh whose
    size is floored at 1/5000 of the box diagonal (so the probe itself stays cheap)."""
    import gmsh
    from gsi.meshes.file import check_readable
    try:
        check_readable(path, "structure")   # a binary file would harm gmsh's parser
    except GsiInputError:
        return None                         # the build reports it
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.onelab.clear()
        if path.suffix.lower() == ".geo" and params:
            gmsh.open(str(path))
            names = [n for n in gmsh.onelab.getNames() if not n.startswith(("Gmsh/", "ONELAB/"))]
            for k, v in params.items():
                full = [n for n in names if n == k or n.rsplit("/", 1)[-1] == k]
                if len(full) == 1 and isinstance(v, (int, float)) and not isinstance(v, bool):
                    gmsh.onelab.setNumber(full[0], [float(v)])
            gmsh.clear()
        gmsh.open(str(path))
        x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(-1, -1)
        ext = (x1 - x0, y1 - y0, z1 - z0)
        box = [x0, y0, z0], [x1, y1, z1]
        diag = math.sqrt(sum(e * e for e in ext))
        if not (diag > 0 and math.isfinite(diag)):
            return None
        if path.suffix.lower() == ".msh":
            n = len(gmsh.model.mesh.getNodes()[0])
            return (*box, diag / max(1.0, math.sqrt(n)))
        gmsh.option.setNumber("Mesh.MeshSizeMin", diag / 5000.0)
        gmsh.model.mesh.generate(1)
        length, segments = 0.0, 0
        for dim, tag in gmsh.model.getEntities(1):
            types, elems, nodes = gmsh.model.mesh.getElements(dim, tag)
            k = sum(len(e) for e in elems)
            if k:
                a, b = gmsh.model.getParametrizationBounds(dim, tag)
                x = gmsh.model.getValue(dim, tag, [a[0] + (b[0] - a[0]) * t / 64.0
                                                   for t in range(65)])
                pts = [x[3 * i:3 * i + 3] for i in range(65)]
                length += sum(math.dist(pts[i], pts[i + 1]) for i in range(64))
                segments += k
        if segments == 0:
            return None
        return (*box, length / segments)
    except Exception:     # a file gmsh cannot probe: the build reports it
        return None
    finally:
        gmsh.finalize()


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
               memory=n * BYTES_PER_PARTICLE, dofs={})
    if any(w.motion.driven for w in case.walls):
        est["wall_s"] = est["wall_s"] * DRIVEN_FACTOR + steps * DRIVEN_STEP_S
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
    size = case.dem.domain_size
    for i, got in est["dofs"].items():
        dofs, how, extent, box = got["dofs"], got["how"], got["extent"], got["box"]
        if extent is not None and extent > 100 * size:
            raise GsiInputError(
                f"{q}structures[{i}].geometry: the structure is {extent:.3g} m across, over 100 x "
                f"the domain ({size:.3g} m); did you give mm? lengths are in m")
        need = dofs * FE_BYTES_PER_DOF
        if need > MEMORY_FACTOR * mem:
            raise GsiInputError(
                f"{q}structures[{i}]: about {dofs:.3g} FE dofs ({how}) need about "
                f"{need / 1e9:.3g} GB, over {MEMORY_FACTOR:g} x this machine's "
                f"{mem / 1e9:.3g} GB; raise the mesh size (structures[{i}].geometry: h) or "
                f"check its units (m)")
        if box is not None and (any(h < lo for h, lo in zip(box[1], case.dem.domain_lo)) or
                                any(lo > h for lo, h in zip(box[0], case.dem.domain_hi))):
            raise GsiInputError(
                f"{q}structures[{i}].translate = {list(case.structures[i].translate)}: the "
                f"structure ({[round(v, 6) for v in box[0]]} to {[round(v, 6) for v in box[1]]})"
                f" lies wholly outside dem.domain; particles never touch it: move it (m)")
        if dofs > WARN_DOFS and not quick:
            said.append(f"structures[{i}]: about {dofs:.3g} FE dofs ({how}): expect about "
                        f"{need / 1e9:.3g} GB and {_hours(dofs * FE_SETUP_S_PER_DOF)} of set-up")
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


def summary(est: dict) -> str:
    """One line of the estimate for ``gsi check``."""
    dofs = sum(v["dofs"] for v in est["dofs"].values())
    fe = f", about {dofs:.3g} FE dofs" if est["dofs"] else ""
    return (f"estimate: {est['particles']:.3g} particles, {est['steps']:.3g} DEM steps, "
            f"{est['outputs']:.3g} outputs, {est['checkpoints']:.3g} checkpoints{fe}; about "
            f"{_hours(est['wall_s'])} on one thread, {est['memory'] / 1e9:.2g} GB")
