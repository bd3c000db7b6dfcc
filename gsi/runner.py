"""One runner for every case: the time loop, sub-cycling, outputs, monitors, pictures.

:func:`run_case` (and ``gsi run CASE.toml``) runs any composition of parts
(:mod:`gsi.case`). The loop counts DEM steps k = 0, 1, ..., N (N = duration/dt); the
DEM advances in chunks between *events*, each at a whole step:

* a structure's coupling step ends every ``n_sub`` DEM steps (its own n_sub: several
  structures sub-cycle independently); at the end of each, the structure takes its loads
  and heat, steps, and hands its moved, heated wall back (``finish``), then opens the
  next interval (``begin``);
* a wall motion's schedule event (its time rounded to the nearest step);
* the steps of an ``[extrapolation]`` (:class:`gsi.extrapolation.CaseExtrapolation`):
  temperatures set on two halves, the contact log's start t0 and end t1 (then the
  pairing and the replay), the reference DEM's t_n;
* a monitor sample, every ``interval`` (default the output interval);
* an output (particles, walls, structures, progress line, pictures) every
  ``output.interval``;
* the end.

MPI: the FE structures are distributed over all ranks; the DEM, particle output,
monitors' DEM values and pictures live on rank 0. Every rank runs the same loop (the
event steps are known everywhere); an error on the DEM rank is broadcast at the end of
each chunk, so every rank stops with the same message and none hangs.

Files under ``out``: ``particles.pvd`` (+ ``particles/*.vtu``), ``walls/<name>.vtu``
(moving walls: ``walls/<name>.pvd`` series), ``<structure>.xdmf`` (+ ``.h5``, one closed
file pair per step under ``<structure>_steps/``) and its coupling CSVs,
``monitors/<name>.csv`` (one row per sample, flushed as written), ``monitors.png``,
``pictures/frame_*.png``, ``<case>.gif`` and ``<case>.png`` (the last frame), and
``summary.txt`` (the closing summary), ``checkpoints/``.

Checkpoints and restart (:mod:`gsi.checkpoint`): every ``run.checkpoint_interval``
simulated seconds (``checkpoint_every`` overrides it; the checkpoint steps are events),
every ``run.checkpoint_minutes`` of wall-clock time (decided on rank 0), and on
SIGINT/SIGTERM, every rank writes its state (:meth:`Runner.state`: the DEM's
:meth:`gsi.dem.simulation.Simulation.state` on rank 0, each structure's
:meth:`gsi.coupling.structure.CoupledStructure.state`, the loop counters, the monitor
series, the output series and the pending picture jobs) to
``checkpoints/ckpt_<step>.rank<r>.npz``, then rank 0 the manifest. A signal only sets a
flag; at the end of the current chunk every rank agrees (one allreduce), writes the
checkpoint and raises :class:`RunInterrupted`. ``resume=True`` rebuilds the case, loads
the newest valid checkpoint (same number of ranks) and continues bit-identically to an
uninterrupted run; every output series is cut back to the checkpoint (PVD entries and
VTU files, CSV rows, XDMF steps), so it has no duplicate and no stale entries.
"""
from __future__ import annotations

import csv
import dataclasses
import json
import math
import pathlib
import re
import signal
import time

import numpy as np

from gsi import viz  # before dolfinx: pictures render in-process (gsi.viz._preload_vtk)
from gsi.errors import GsiInputError, GsiRunError

__all__ = ["Runner", "RunResult", "RunInterrupted", "run_case", "build_simulation"]


@dataclasses.dataclass
class RunResult:
    """What a run measured (SI units)."""

    name: str
    time: float                 # s, simulated
    steps: int                  # DEM steps
    dt: float                   # s, DEM step
    n_particles: int            # at the end
    n_lost: int                 # left the domain
    particle_mass: float        # kg, at the end
    kinetic_energy: float       # J, at the end
    wall_load: np.ndarray       # (3,) N: force of the particles on all walls and structures
    weight: np.ndarray          # (3,) N: m g of all particles
    monitors: dict              # name -> {"time_s": array, column: array}
    structures: dict            # name -> summary dict of the structure
    summary: dict               # the key=value numbers of the last summary line
    wall_clock: float           # s
    files: list


class RunInterrupted(Exception):
    """A run stopped by SIGINT/SIGTERM after writing a checkpoint (every rank raises it).

    ``signum``: the signal; ``time`` (s): the simulated time of the checkpoint;
    ``out``: the output directory (resume with ``gsi run ... --out out --resume``).
    """

    def __init__(self, signum: int, t: float, out):
        self.signum, self.time, self.out = int(signum), float(t), pathlib.Path(out)
        super().__init__(f"interrupted at t = {t:.6g} s; checkpoint written")

    @property
    def exit_code(self) -> int:
        """128 + the signal number (130 for SIGINT, 143 for SIGTERM)."""
        return 128 + self.signum


def _engine_is_cold(sim) -> bool:
    """True when the DEM engine module of ``sim`` has no numba cache newer than its source
    (its first step will compile it: ~1 min on 2 cores; see gsi.dem.engine_factory)."""
    f = getattr(getattr(sim, "engine", None), "__file__", None)
    if not f:
        return False
    src = pathlib.Path(f)
    index = list((src.parent / "__pycache__").glob(f"{src.stem}.advance-*.nbi"))
    try:
        return not index or max(i.stat().st_mtime for i in index) < src.stat().st_mtime
    except OSError:
        return False


def build_simulation(case, *, dt: float):
    """The DEM of a case: materials, walls (with their motions at t = 0) and particles.

    Returns ``(sim, wall_handles, groups)``: ``wall_handles`` maps each ``[[walls]]`` name
    to the DEM walls it made, ``groups`` each ``[[particles]]`` name to its ids (fills,
    files) or its inserter (streams).
    """
    from gsi.dem.simulation import Simulation

    if case.run.threads:
        import numba
        numba.set_num_threads(min(case.run.threads, numba.config.NUMBA_NUM_THREADS))
    r_min = case.smallest_radius()
    sim = Simulation(
        materials=case.dem_materials(), contact=case.dem.contact, k_n=case.dem.k_n,
        rolling=case.dem.rolling, heat=None if case.dem.heat == "none" else case.dem.heat,
        h_c=case.dem.h_c, pipe_length=case.dem.pipe_length,
        pipe_resistance=case.dem.pipe_resistance, gravity=case.dem.gravity, dt=dt,
        skin=case.dem.skin if case.dem.skin is not None else 0.4 * r_min,
        domain=(case.dem.domain_lo, case.dem.domain_hi), force_dt=case.dem.force_dt,
        pair_overrides=case.pair_overrides(), seed=case.run.seed, dt_checked=True)
    radiation = case.radiation_options()
    if radiation is not None:
        sim.set_radiation(**radiation)
    handles = {}
    for i, w in enumerate(case.walls):
        handles[w.name] = w.add_to(sim, base_dir=case.base_dir, path=f"walls[{i}]")
        w.apply_motion(handles[w.name], 0.0)
    rng = np.random.default_rng(case.run.seed)
    groups = {}
    for i, p in enumerate(case.particles):
        groups[p.name] = p.add_to(sim, rng=rng, base_dir=case.base_dir, path=f"particles[{i}]")
    return sim, handles, groups


class _Series:
    """A ParaView series ``<dir>/<prefix>.pvd`` of files written by ``write(path, t)``."""

    def __init__(self, directory: pathlib.Path, prefix: str, write):
        from gsi.dem.output import ParticleWriter
        self._pvd = ParticleWriter.__new__(ParticleWriter)   # its .pvd bookkeeping only
        self._pvd.dir, self._pvd.prefix, self._pvd.entries = directory, prefix, []
        self._pvd.pvd = directory / f"{prefix}.pvd"
        self._write = write

    def restore(self, times) -> None:
        """Continue an earlier series: keep its first len(times) entries, drop later files."""
        _restore_series(self._pvd, times)

    def write(self, t: float) -> None:
        name = f"{self._pvd.prefix}_{len(self._pvd.entries):06d}.vtu"
        self._write(self._pvd.dir / name)
        self._pvd.entries.append((t, name))
        self._pvd._write_pvd()


class Runner:
    """Runs one case (see the module docstring).

    Parameters
    ----------
    case : gsi.case.Case
        A validated case (``gsi.case.load_case`` or built in Python).
    out : path
        Output directory (created).
    quick : bool
        Run the case's ``[quick]`` form.
    pictures : bool, optional
        Override ``output.pictures``.
    verbose : bool
        Print the set-up, the progress and the summary (rank 0).
    overwrite : bool
        Replace an earlier run's outputs in ``out`` (else refused, see :func:`_output_dir`).
    resume : bool
        Continue from the newest valid checkpoint under ``out/checkpoints`` (same case,
        same number of MPI ranks).
    checkpoint_every : float, optional
        Simulated seconds between checkpoints; overrides ``run.checkpoint_interval``
        (0: none).
    """

    def __init__(self, case, *, out, quick: bool = False, pictures: bool | None = None,
                 verbose: bool = True, overwrite: bool = False, resume: bool = False,
                 checkpoint_every: float | None = None):
        from mpi4py import MPI
        self.comm = MPI.COMM_WORLD
        self.root = 0
        self.is_root = self.comm.rank == self.root
        from gsi.case.case import validated
        case = validated(case)
        self.case = case.quick_variant() if quick else case
        self.quick = quick
        self.out = _output_dir(out, self.comm, overwrite=overwrite, resume=resume)
        self.verbose = verbose and self.is_root
        self.pictures = (case.output.pictures if pictures is None else pictures) and self.is_root
        self.sim = None
        self._handles = {}
        self._groups = {}
        self.structures = []
        self.contact_groups = []
        self._files = []
        self.resume = bool(resume)
        if checkpoint_every is not None and not (checkpoint_every >= 0
                                                 and math.isfinite(checkpoint_every)):
            raise GsiInputError(f"--checkpoint-every = {checkpoint_every}: must be >= 0 "
                                "(simulated seconds; 0 = none)")
        self.checkpoint_every = checkpoint_every
        self.checkpoint_seconds = []       # wall-clock duration of each checkpoint write (s)
        self._signal = 0

    # ------------------------------------------------------------------ queries for parts
    def say(self, *args, **kw):
        if self.verbose:
            print(*args, **kw, flush=True)

    def structure(self, name: str):
        """The built structure ``name`` (a :class:`gsi.case.structure.CoupledStructure`)."""
        for st in self.structures:
            if st.name == name:
                return st
        raise GsiInputError(f"structure {name!r}: not in the case")

    def wall_handles(self, name: str) -> list:
        """The DEM walls of a ``[[walls]]`` name, or the contact wall(s) of a structure."""
        if name in self._handles:
            return list(self._handles[name])
        st = self.structure(name)
        return [st.wall] if st.wall is not None else []

    def group_ids(self, name: str) -> np.ndarray:
        """Ids of the particles of a ``[[particles]]`` source."""
        g = self._groups[name]
        ids = getattr(g, "ids", g)
        return np.asarray(ids, np.int64)

    def heat_capacity(self) -> np.ndarray:
        """m c_p of each particle (J/K), as the DEM integrates it (scaled c_p)."""
        from gsi.coupling.thermal import particle_heat_capacity
        return particle_heat_capacity(self.sim)

    # ------------------------------------------------------------------ set-up
    def setup(self) -> None:
        case = self.case
        try:
            self.dt = case.check()
        except GsiInputError as exc:      # the same case on every rank: the same error
            raise _agreed(exc)
        self.n_total = max(1, int(round(case.run.duration / self.dt)))
        if self.is_root:
            self.sim, self._handles, self._groups = build_simulation(case, dt=self.dt)
        err = self._agree(None)
        if err:
            raise err
        for st in case.structures:
            built = st.build(comm=self.comm, dt_dem=self.dt, gravity=case.dem.gravity,
                             base_dir=case.base_dir, heat_scale=case.run.heat_time_scale,
                             root=self.root)
            built.attach(self.sim)
            if self.is_root:
                st.apply_motion(built.wall, 0.0)
            self.structures.append(built)
        from gsi.case.thermal_contacts import build_contact_groups
        self.contact_groups = build_contact_groups(
            case.thermal_contacts, {st.name: st for st in self.structures})
        if self.structures:
            # whole coupling intervals of every structure (an FE step has a fixed dt)
            L = math.lcm(*(st.n_sub for st in self.structures))
            self.n_total = max(L, int(round(self.n_total / L)) * L)
        n_out = max(1, int(round(case.output.interval / self.dt)))
        self.every = {"output": n_out}
        for m in case.monitors:
            self.every[f"monitor:{m.name}"] = max(1, int(round((m.interval or
                                                                case.output.interval) / self.dt)))
        for st in self.structures:
            self.every[f"structure:{st.name}"] = st.n_sub
        interval = (case.run.checkpoint_interval if self.checkpoint_every is None
                    else self.checkpoint_every)
        if interval > 0:
            self.every["checkpoint"] = max(1, int(round(interval / self.dt)))
        # the long-time heat extrapolation (gsi.case.extrapolation): its steps are events
        self.extrapolation = None
        if case.extrapolation is not None:
            if self.resume:
                raise _agreed(GsiInputError(
                    "resume: a case with [extrapolation] cannot resume (its contact log is "
                    "not in the checkpoints); run it again"))
            from gsi.extrapolation import CaseExtrapolation
            if self.structures and self.comm.size > 1:
                raise _agreed(GsiInputError(
                    "extrapolation with [[structures]]: the kiln replay runs on one MPI rank; "
                    "run without mpirun"))
            self.extrapolation = CaseExtrapolation(
                case.extrapolation, dt=self.dt, out=self.out,
                structure=self.structures[0] if self.structures else None)
        # a schedule event at time t takes effect at the first step boundary at or after t
        # (the wall takes the motion state of the event itself, whatever the round-off)
        self.motion_events = {}
        movers = [(w.motion, lambda t, w=w: w.apply_motion(self._handles[w.name], t))
                  for w in case.walls]
        movers += [(st.contact.motion, lambda t, st=st, b=b: st.apply_motion(b.wall, t))
                   for st, b in zip(case.structures, self.structures)
                   if st.contact.motion is not None]
        for motion, move in movers:
            for t in motion.event_times():
                k = int(math.ceil(t / self.dt - 1e-9))
                if 0 < k <= self.n_total:
                    self.motion_events.setdefault(k, []).append((move, t))

    def _agree(self, exc):
        """Broadcast an error raised on the DEM rank so that every rank stops (one message)."""
        if self.comm.size == 1:
            return exc
        payload = (type(exc).__name__, str(exc)) if exc is not None else None
        payload = self.comm.bcast(payload, root=self.root)
        if payload is None:
            return None
        kind = GsiInputError if payload[0] == "GsiInputError" else GsiRunError
        err = exc if exc is not None else kind(payload[1])
        err.agreed = True       # every rank raises it: rank 0 alone reports it
        return err

    # ------------------------------------------------------------------ output
    def _open_outputs(self, restored: dict | None = None) -> None:
        """Open the output series; ``restored`` (a checkpoint's runner state) continues
        those of an earlier run, cut back to the checkpoint."""
        from gsi.checkpoint import truncate_csv
        from gsi.dem.output import ParticleWriter, write_wall_vtu
        out, fields = self.out, self.case.output.fields
        self._pw = None
        self._wall_series = []
        if self.is_root:
            if restored is not None:      # temporaries of a killed run
                for p in out.iterdir():
                    if re.search(r"\.tmp\d+$", p.name) and p.is_file():
                        p.unlink(missing_ok=True)
            if "particles" in fields:
                if restored is None:
                    self._pw = ParticleWriter(out / "particles", "particles")
                else:
                    self._pw = ParticleWriter.__new__(ParticleWriter)
                    self._pw.dir, self._pw.prefix = out / "particles", "particles"
                    self._pw.pvd = self._pw.dir / "particles.pvd"
                    self._pw.dir.mkdir(parents=True, exist_ok=True)
                    _restore_series(self._pw, restored["pvd.particles"])
                self._files.append(out / "particles" / "particles.pvd")
            if "walls" in fields:
                (out / "walls").mkdir(exist_ok=True)
                for w in self.case.walls:
                    for j, h in enumerate(self._handles[w.name]):
                        if not hasattr(h, "triangles"):
                            continue      # planes have no geometry to write
                        stem = w.name if len(self._handles[w.name]) == 1 else f"{w.name}_{j}"
                        if w.motion.moves:
                            series = _Series(out / "walls", stem,
                                             lambda path, h=h: write_wall_vtu(path, h))
                            if restored is not None:
                                series.restore(restored[f"pvd.walls.{len(self._wall_series)}"])
                            self._wall_series.append(series)
                            self._files.append(out / "walls" / f"{stem}.pvd")
                        elif restored is None:
                            write_wall_vtu(out / "walls" / f"{stem}.vtu", h)
                            self._files.append(out / "walls" / f"{stem}.vtu")
                        else:
                            self._files.append(out / "walls" / f"{stem}.vtu")
            (out / "monitors").mkdir(exist_ok=True)
        if "structures" in self.case.output.fields:
            for st in self.structures:
                st.open_output(out, resume=None if restored is None else
                               int(restored[f"fem.{st.name}.writes"]))
        self._mon = {}
        for m in self.case.monitors:
            self._mon[m.name] = {"time_s": [], **{c: [] for c in m.columns}}
            if restored is not None:
                for c in self._mon[m.name]:
                    self._mon[m.name][c] = restored.get(f"mon.{m.name}.{c}",
                                                        np.zeros(0)).tolist()
            if self.is_root:
                path = out / "monitors" / f"{m.name}.csv"
                if restored is None:
                    with path.open("w", newline="") as fh:
                        csv.writer(fh).writerow(["time_s", *m.columns])
                else:
                    truncate_csv(path, len(self._mon[m.name]["time_s"]))
                self._files.append(path)
        self._frames = []
        if restored is not None and "frames" in restored:
            from gsi.checkpoint import unpack
            self._frames = unpack(json.loads(str(restored["frames"])), restored)

    def _sample(self, m, t: float) -> None:
        row = m.sample(self)
        if not self.is_root:
            return
        rec = self._mon[m.name]
        rec["time_s"].append(t)
        for c, v in zip(m.columns, row):
            rec[c].append(v)
        with (self.out / "monitors" / f"{m.name}.csv").open("a", newline="") as fh:
            csv.writer(fh).writerow([f"{t:.10g}", *(f"{v:.10g}" if isinstance(v, float) else v
                                                    for v in row)])

    def _output(self, t: float, n_out: int, *, last: bool = False) -> None:
        if "structures" in self.case.output.fields:
            for st in self.structures:
                st.write_output(t)
        if not self.is_root:
            return
        if self._pw is not None:
            self._pw.write(self.sim)
        for s in self._wall_series:
            s.write(t)
        if self.pictures and (n_out % self.case.output.picture_every == 0 or last):
            self._frames.append(self._picture_job(t, len(self._frames)))

    def _picture_job(self, t: float, k: int) -> dict:
        sim, case = self.sim, self.case
        color = case.output.color_by
        values = {"speed": lambda: np.linalg.norm(sim.v, axis=1),
                  "temperature": lambda: sim.T.copy(),
                  "radius": lambda: sim.radius.copy()}[color]()
        surfaces = []
        for w in case.walls:
            for h in self._handles[w.name]:
                if hasattr(h, "triangles"):
                    surfaces.append(dict(points=h.vertices, triangles=h.triangles,
                                         opacity=0.3, color="lightsteelblue"))
        for j, st in enumerate(self.structures):    # the DEM wall follows the FE surface
            x = st.wall.vertices
            if color == "temperature" and st.wall.vertex_temperature is not None:
                surfaces.append(dict(points=x, triangles=st.wall.triangles,
                                     values=st.wall.vertex_temperature, opacity=0.7,
                                     name=f"{st.name} T (K)", cmap="inferno",
                                     bar_x=0.88 - 0.14 * j))
                continue
            u = np.linalg.norm(x - st.interface.x0, axis=1)
            surfaces.append(dict(points=x, triangles=st.wall.triangles, values=1e3 * u,
                                 name=f"{st.name} |u| (mm)", cmap="viridis",
                                 bar_x=0.88 - 0.14 * j))
        (self.out / "pictures").mkdir(exist_ok=True)
        camera = None
        if case.output.view != "iso":
            lo, hi = np.asarray(case.dem.domain_lo), np.asarray(case.dem.domain_hi)
            c = 0.5 * (lo + hi)
            d = np.zeros(3)
            d["xyz".index(case.output.view[1])] = 1.0 if case.output.view[0] == "+" else -1.0
            up = (0.0, 0.0, 1.0) if case.output.view[1] != "z" else (0.0, 1.0, 0.0)
            camera = dict(position=tuple(c - 2.5 * float((hi - lo).max()) * d),
                          focal_point=tuple(c), up=up)
        return dict(camera=camera, path=self.out / "pictures" / f"frame_{k:04d}.png", x=sim.x.copy(),
                    radius=sim.radius.copy(), color_by=color, values=values,
                    surfaces=surfaces, title=f"{case.case.name}  t = {t:.3f} s",
                    box=(case.dem.domain_lo, case.dem.domain_hi) if not surfaces else None)

    def _progress(self, k: int, wall0: float) -> None:
        if not (self.verbose and self.case.run.progress):
            return
        frac = k / self.n_total
        el = time.perf_counter() - wall0
        rate = k * self.dt / el if el > 0 else math.nan
        eta = el * (1 - frac) / frac if frac > 0 else math.nan
        bar = "#" * int(20 * frac) + "." * (20 - int(20 * frac))
        n = self.sim.n if self.sim is not None else 0
        print(f"  [{bar}] t = {k * self.dt:8.4f} / {self.case.run.duration:g} s  "
              f"{rate:.3g} s/s  ETA {eta:5.0f} s  particles {n}", flush=True)

    # ------------------------------------------------------------------ the loop
    def run(self) -> RunResult:
        """Run the case (or continue it, ``resume``); see the module docstring."""
        wall0 = time.perf_counter()
        self._previous_handlers = {}
        try:
            return self._run(wall0)
        finally:
            self._release_signals()

    def _release_signals(self) -> None:
        """After the last step a signal acts as usual again (nothing left to checkpoint)."""
        for sig, handler in self._previous_handlers.items():
            signal.signal(sig, handler)
        self._previous_handlers = {}

    def _catch_signals(self) -> None:
        """From the first step on, SIGINT/SIGTERM checkpoint and stop the run (before,
        during the set-up, they stop it at once as usual)."""
        try:
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._previous_handlers[sig] = signal.signal(sig, self._on_signal)
        except ValueError:      # not the main thread: no signal handling
            pass

    def _on_signal(self, signum, frame) -> None:
        """SIGINT/SIGTERM: note it; the loop checkpoints and stops at the end of the chunk
        (a second signal in a serial run stops at once)."""
        if self._signal and self.comm.size == 1:
            raise KeyboardInterrupt
        self._signal = signum

    def _run(self, wall0: float) -> RunResult:
        self.setup()
        case = self.case
        restored = self._restore() if self.resume else None
        self.say(f"{case.case.name}: {self.sim.n if self.sim is not None else '?'} particles, "
                 f"{len(case.walls)} walls, {len(self.structures)} structure(s) "
                 f"{', '.join(f'{s.name} (n_sub {s.n_sub})' for s in self.structures)}; "
                 f"dt = {self.dt:.3g} s, {self.n_total} steps ({self.n_total * self.dt:g} s)"
                 f"{' [quick]' if self.quick else ''} -> {self.out}")
        self._open_outputs(restored)
        try:
            if restored is None:
                n_out = 0
                for st in self.structures:
                    st.begin()
                for m in case.monitors:
                    self._sample(m, 0.0)
                self._output(0.0, n_out)
                k = 0
            else:
                k, n_out = int(restored["runner.k"]), int(restored["runner.n_out"])
                self.say(f"resumed at t = {k * self.dt:.6g} s (step {k}) from "
                         f"{self.out / 'checkpoints'}")
            self._ckpt_step, self._ckpt_wall = k, time.perf_counter()
            self._catch_signals()
            if self.is_root and _engine_is_cold(self.sim):
                self.say("DEM engine: compiling on first use (about a minute on 2 cores; "
                         "cached for the next runs)")
            while k < self.n_total:
                nxt = min([self.n_total] + [(k // e + 1) * e for e in self.every.values()]
                          + [j for j in self.motion_events if j > k]
                          + [j for j in (self.extrapolation.steps if self.extrapolation
                                         else ()) if j > k])
                exc = None
                if self.is_root:
                    try:
                        self.sim.step(nxt - k)
                    except (GsiRunError, GsiInputError) as e:
                        exc = e
                err = self._agree(exc)
                if err:
                    raise err
                k = nxt
                t = k * self.dt
                self._finish_structures(k)
                for move, t_event in self.motion_events.get(k, []):
                    if self.is_root:
                        move(t_event)
                if self.extrapolation is not None and self.is_root:
                    self.extrapolation.at_step(k, self.sim, say=self.say)
                for m in case.monitors:
                    if k % self.every[f"monitor:{m.name}"] == 0 or k == self.n_total:
                        self._sample(m, t)
                if k % self.every["output"] == 0 or k == self.n_total:
                    n_out += 1
                    self._output(t, n_out, last=k == self.n_total)
                    self._progress(k, wall0)
                if k < self.n_total:
                    self._maybe_checkpoint(k, n_out)
            self._release_signals()
            if self._signal:       # it came during the last chunk: the run is complete
                self.say("the run completed before the interruption took effect")
        finally:
            if self.is_root and self._pw is not None:
                self._pw.close()
            for st in self.structures:
                st.close()
        return self._finish(wall0)

    def _finish_structures(self, k: int) -> None:
        """End the coupling interval of every structure due at step ``k`` and open the
        next. Structures in an FE-FE thermal contact group take their loads first, the
        group steps their heat as one system, then they record."""
        due = [st for st in self.structures if k % st.n_sub == 0]
        grouped = [st for st in due if st.contact_group is not None]
        for st in due:
            if st.contact_group is None:
                st.finish()
            else:
                st.load_heat()
        for group in self.contact_groups:
            if any(st.contact_group is group for st in grouped):
                group.step()
        for st in grouped:
            st.record()
        if k < self.n_total:
            for st in due:
                st.begin()

    # ------------------------------------------------------------------ checkpoints
    def _maybe_checkpoint(self, k: int, n_out: int) -> None:
        """At the end of a chunk (collective): checkpoint when due or signalled; after a
        signal raise :class:`RunInterrupted` on every rank."""
        due = "checkpoint" in self.every and k % self.every["checkpoint"] == 0
        minutes = self.case.run.checkpoint_minutes
        wall_due = (self.is_root and minutes > 0
                    and time.perf_counter() - self._ckpt_wall >= 60.0 * minutes)
        flags = np.array([self._signal, wall_due], np.int64)
        if self.comm.size > 1:
            from mpi4py import MPI
            agreed = np.empty_like(flags)
            self.comm.Allreduce(flags, agreed, op=MPI.MAX)
            flags = agreed
        signum = int(flags[0])
        if (due or flags[1] or signum) and self._ckpt_step != k:
            self.write_checkpoint(k, n_out)
        if signum:
            raise RunInterrupted(signum, k * self.dt, self.out)

    def state(self, k: int, n_out: int) -> dict:
        """This rank's checkpoint arrays at loop step ``k``: ``runner.*`` (k, output count),
        ``mon.<monitor>.<column>`` (the series so far), ``pvd.*`` (output series times),
        ``fem.<structure>.writes``, ``frames`` (pending picture jobs, rank 0), ``dem.*``
        (:meth:`gsi.dem.simulation.Simulation.state`, rank 0) and
        ``st.<structure>.*`` (:meth:`gsi.coupling.structure.CoupledStructure.state`)."""
        from gsi.checkpoint import pack
        d = {"runner.k": np.int64(k), "runner.n_out": np.int64(n_out),
             "runner.n_total": np.int64(self.n_total), "runner.dt": np.float64(self.dt)}
        for st in self.structures:
            d[f"fem.{st.name}.writes"] = np.int64(st.n_writes)
            d.update({f"st.{st.name}.{key}": v for key, v in st.state().items()})
        if self.is_root:
            for name, rec in self._mon.items():
                for c, v in rec.items():
                    d[f"mon.{name}.{c}"] = np.asarray(v)
            if self._pw is not None:
                d["pvd.particles"] = np.array([t for t, _ in self._pw.entries], np.float64)
            for i, series in enumerate(self._wall_series):
                d[f"pvd.walls.{i}"] = np.array([t for t, _ in series._pvd.entries], np.float64)
            if self._frames:
                arrays = {}
                d["frames"] = np.array(json.dumps(pack(self._frames, arrays, "frame.")))
                d.update(arrays)
            d.update({f"dem.{key}": v for key, v in self.sim.state().items()})
        return d

    def write_checkpoint(self, k: int, n_out: int) -> None:
        """Write the checkpoint of loop step ``k`` (collective; see :mod:`gsi.checkpoint`)."""
        from gsi import checkpoint as ck
        t0 = time.perf_counter()
        directory = self.out / "checkpoints"
        err, size = None, 0
        try:
            if self.is_root:
                directory.mkdir(exist_ok=True)
            if self.comm.size > 1:
                self.comm.barrier()
            size = ck.write_npz(ck.rank_file(directory, k, self.comm.rank), self.state(k, n_out))
        except OSError as exc:
            err = f"checkpoint at t = {k * self.dt:.6g} s: cannot write {directory} ({exc})"
        gathered = self.comm.allgather((err, size)) if self.comm.size > 1 else [(err, size)]
        errors = [e for e, _ in gathered if e]
        if errors:
            raise _agreed(GsiRunError(errors[0]))
        if self.is_root:
            try:
                ck.write_manifest(directory, k, dict(
                    time=k * self.dt, n_ranks=self.comm.size, dt=self.dt,
                    case=self.case.case.name, quick=self.quick,
                    sizes=[s for _, s in gathered]))
                ck.prune(directory)
            except OSError as exc:
                err = f"checkpoint at t = {k * self.dt:.6g} s: cannot write {directory} ({exc})"
        err = self._agree(GsiRunError(err) if err else None)
        if err:
            raise err
        self._ckpt_step, self._ckpt_wall = k, time.perf_counter()
        self.checkpoint_seconds.append(time.perf_counter() - t0)

    def _restore(self) -> dict:
        """Load the newest valid checkpoint into the built case (collective); returns its
        arrays."""
        from gsi import checkpoint as ck
        directory = self.out / "checkpoints"
        info = ck.newest(directory) if self.is_root else None
        if self.comm.size > 1:
            info = self.comm.bcast(info, root=self.root)
        if info is None:
            raise _agreed(GsiInputError(f"--resume: no complete checkpoint under {directory}; run "
                                "without --resume (or with --checkpoint-every S)"))
        if info["n_ranks"] != self.comm.size:
            raise _agreed(GsiInputError(
                f"--resume: the checkpoint at t = {info['time']:.6g} s was written by "
                f"{info['n_ranks']} MPI rank(s), this run has {self.comm.size}; resume with "
                f"mpirun -n {info['n_ranks']} (or serially for 1)"))
        if info.get("quick", self.quick) != self.quick:
            raise _agreed(GsiInputError(f"--resume: the checkpoint was written by a run "
                                f"{'with' if info['quick'] else 'without'} --quick; "
                                "resume with the same options"))
        err = None
        try:
            d = ck.read_npz(ck.rank_file(directory, info["step"], self.comm.rank))
            if float(d["runner.dt"]) != self.dt or int(d["runner.k"]) > self.n_total:
                raise GsiInputError(
                    f"--resume: the checkpoint (dt = {float(d['runner.dt']):.6g} s, step "
                    f"{int(d['runner.k'])}) does not belong to this case (dt = {self.dt:.6g} s, "
                    f"{self.n_total} steps); resume with the case that wrote it")
            if self.is_root:
                self.sim.set_state({key[4:]: v for key, v in d.items()
                                    if key.startswith("dem.")})
            for st in self.structures:
                p = f"st.{st.name}."
                st.set_state({key[len(p):]: v for key, v in d.items() if key.startswith(p)})
        except GsiInputError as exc:
            err = str(exc)
        except (OSError, KeyError, ValueError) as exc:
            err = (f"--resume: cannot read the checkpoint at t = {info['time']:.6g} s "
                   f"({type(exc).__name__}: {exc}); it does not match this case")
        errors = self.comm.allgather(err) if self.comm.size > 1 else [err]
        errors = [e for e in errors if e]
        if errors:
            raise _agreed(GsiInputError(errors[0]))
        if self.is_root:
            ck.clear_newer(directory, info["step"])
        return d

    # ------------------------------------------------------------------ results
    def _finish(self, wall0: float) -> RunResult:
        case = self.case
        structures = {st.name: st.summary() for st in self.structures}
        res = None
        if self.is_root:
            sim = self.sim
            g = np.asarray(case.dem.gravity, float)
            weight = float(sim.mass.sum()) * g
            load = np.zeros(3)
            for hs in self._handles.values():
                for h in hs:
                    load += h.force
            for st in self.structures:
                if st.wall is not None:
                    load += st.wall.force
            monitors = {name: {c: np.asarray(v) for c, v in rec.items()}
                        for name, rec in self._mon.items()}
            files = list(self._files)
            for st in self.structures:
                files += st.output_files()
            files += self._pictures(monitors)
            extrap = {}
            if self.extrapolation is not None:
                extrap = self.extrapolation.finish(case.case.name)
                if extrap:
                    files += self.extrapolation.files
                    if self.pictures:
                        files += self.extrapolation.pictures(case.case.name,
                                                             view=case.output.view)
            res = RunResult(name=case.case.name, time=sim.time, steps=sim.step_count, dt=self.dt,
                            n_particles=int(sim.n), n_lost=int(sim.n_lost),
                            particle_mass=float(sim.mass.sum()),
                            kinetic_energy=sim.kinetic_energy(), wall_load=load, weight=weight,
                            monitors=monitors, structures=structures, summary={},
                            wall_clock=time.perf_counter() - wall0, files=files)
            res.summary = self._summary(res, extrap)
            if self.checkpoint_seconds:
                spent = sum(self.checkpoint_seconds)
                self.say(f"checkpoints: {len(self.checkpoint_seconds)} written in {spent:.3f} s "
                         f"({100 * spent / res.wall_clock:.2f} % of the {res.wall_clock:.1f} s "
                         f"wall time; the longest {max(self.checkpoint_seconds):.3f} s)")
        res = self.comm.bcast(res, root=self.root)
        return res

    def _pictures(self, monitors) -> list:
        files = []
        if not self.is_root:
            return files
        series = {}
        for name, rec in monitors.items():
            for c, v in rec.items():
                # no panel for a column without a finite value (a structure without heat
                # has no T_mean)
                if c != "time_s" and len(v) > 1 and np.isfinite(np.asarray(v, float)).any():
                    label, _, unit = c.rpartition("_") if "_" in c else (c, "", "")
                    series[f"{name}: {label}"] = (rec["time_s"], v, unit)
        if series:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
            keys = list(series)[:12]
            fig, axes = plt.subplots(len(keys), 1, figsize=(7, 1.9 * len(keys)), sharex=True,
                                     squeeze=False)
            for ax, key in zip(axes[:, 0], keys):
                t, v, unit = series[key]
                ax.plot(t, v, lw=1.4)
                ax.set_ylabel(f"{key}\n({unit})" if unit else key, fontsize=8)
                ax.grid(alpha=0.3)
            axes[-1, 0].set_xlabel("time (s)")
            axes[0, 0].set_title(f"{self.case.case.name}: monitors")
            fig.tight_layout()
            fig.savefig(self.out / "monitors.png", dpi=100)
            plt.close(fig)
            files.append(self.out / "monitors.png")
        if self.pictures and self._frames:
            paths = [p for p in viz.render_snapshots(self._frames) if p is not None]
            files += paths
            if paths:
                last = self.out / f"{self.case.case.name}.png"
                last.write_bytes(pathlib.Path(paths[-1]).read_bytes())
                files.append(last)
                gif = viz.animation(self.out / f"{self.case.case.name}.gif", paths, fps=6)
                if gif:
                    files.append(gif)
        return files

    def _summary(self, r: RunResult, extrap: dict | None = None) -> dict:
        """Print the closing physics summary; return its key=value numbers (with those of
        the extrapolation, ``extrap``)."""
        g = np.linalg.norm(r.weight)
        along = float(r.wall_load @ r.weight / g ** 2) if g > 0 else math.nan
        lines = [f"summary of {r.name} at t = {r.time:.4g} s ({r.steps} steps of "
                 f"{r.dt:.3g} s, {r.wall_clock:.1f} s wall):",
                 f"  particles: {r.n_particles} ({r.particle_mass:.4g} kg), {r.n_lost} lost, "
                 f"kinetic energy {r.kinetic_energy:.3e} J; walls and structures carry "
                 f"{100 * along:.2f} % of the particles' weight ({g:.4g} N)"]
        keys = dict(particles=r.n_particles, lost=r.n_lost, load_ratio=round(along, 5),
                    ke=float(f"{r.kinetic_energy:.4e}"))
        for name, rec in r.monitors.items():
            if len(rec["time_s"]) == 0:
                continue
            last = ", ".join(f"{c} {rec[c][-1]:.5g}" for c in rec if c != "time_s")
            lines.append(f"  monitor {name}: {last}")
        for name, s in r.structures.items():
            lines.append(f"  structure {name}: " + ", ".join(
                f"{k} {v:.5g}" if isinstance(v, float) else f"{k} {v}" for k, v in s.items()))
            for k, v in s.items():
                if isinstance(v, (int, float)):
                    keys[f"{name}.{k}"] = v
        if extrap:
            lines.append("  extrapolation: " + ", ".join(
                f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}" for k, v in extrap.items()))
            keys.update(extrap)
            if "extrap_hours" in extrap:
                e = extrap
                lines.append(
                    f"  kiln: mean bed temperature {e['bed_T_t1']:.2f} K at t1 -> "
                    f"{e['bed_T_end']:.2f} K after {e['extrap_hours']:.3g} h extrapolated "
                    f"(shell mean {e['wall_T_end']:.2f} K); wall -> bed "
                    f"{e['wall_heat_flow_W']:.4g} W "
                    f"and heat in through the shell's boundary {e['boundary_heat_flow_W']:.4g} W "
                    f"on average; energy balance (bed + shell - boundary heat) "
                    f"{e['energy_balance_rel']:.2g} relative")
        text = "\n".join(lines)
        last = " ".join(f"{k}={v:.6g}" if isinstance(v, float) else f"{k}={v}"
                        for k, v in keys.items())
        self.say(text)
        self.say(last)
        from gsi.checkpoint import write_atomic
        write_atomic(self.out / "summary.txt", text + "\n" + last + "\n", fsync=False)
        return keys


def _agreed(exc):
    """Mark an error that every rank raises alike (rank 0 alone reports it)."""
    exc.agreed = True
    return exc


def _restore_series(writer, times) -> None:
    """A ParticleWriter-like series (``dir``, ``prefix``, ``entries``, ``_write_pvd``)
    continued from an earlier run: its first len(times) entries, later files removed."""
    times = [float(t) for t in times]
    writer.entries = [(t, f"{writer.prefix}_{i:06d}.vtu") for i, t in enumerate(times)]
    pattern = re.compile(rf"^{re.escape(writer.prefix)}_(\d{{6}})\.vtu")
    for p in writer.dir.iterdir():
        m = pattern.match(p.name)
        if (m is not None and int(m.group(1)) >= len(times)) or re.search(r"\.tmp\d+$",
                                                                           p.name):
            p.unlink(missing_ok=True)
    writer._write_pvd()



#: what a run writes in its output directory: these directories (any one of them, or
#: summary.txt, marks an earlier run) and these top-level files; ``--overwrite`` removes
#: them and nothing else (a user's own files there stay)
OUTPUT_DIRS = ("particles", "walls", "monitors", "pictures", "checkpoints")
OUTPUT_FILES = ("summary.txt", "*.xdmf", "*.h5", "*_coupling.csv", "*_energy.csv",
                "history.csv", "*.pvd", "*.png", "*.gif")


def previous_outputs(out: pathlib.Path) -> list[pathlib.Path]:
    """The files and directories of an earlier run in ``out`` (none if ``out`` holds no
    OUTPUT_DIRS and no summary.txt: then it is not a run's directory)."""
    dirs = [out / d for d in OUTPUT_DIRS if (out / d).is_dir()]
    if not dirs and not (out / "summary.txt").is_file():
        return []
    files = sorted({f for pattern in OUTPUT_FILES for f in out.glob(pattern) if f.is_file()})
    return dirs + files


def _output_dir(out, comm, *, overwrite: bool = False, resume: bool = False) -> pathlib.Path:
    """Create the output directory (rank 0) or raise a one-line error on every rank.

    A directory holding an earlier run's outputs (:func:`previous_outputs`) is refused
    unless ``overwrite``, which removes those outputs first (other files stay), so that no
    stale file of the earlier run is left in a series, or ``resume``, which continues them
    (the runner truncates each series to the checkpoint)."""
    import shutil
    msg = None
    if out is None or str(out).strip() == "":
        msg = "--out = '': give an output directory"
    else:
        out = pathlib.Path(out)
        if comm.rank == 0:
            try:
                out.mkdir(parents=True, exist_ok=True)
                old = previous_outputs(out)
                if resume and overwrite:
                    msg = "--resume and --overwrite: give one (continue or start again)"
                elif old and not overwrite and not resume:
                    msg = (f"--out = {str(out)!r}: holds the outputs of an earlier run "
                           f"({', '.join(f.name for f in old[:3])}{', ...' if len(old) > 3 else ''}); "
                           "add --overwrite to replace them or give another directory")
                for f in old if overwrite and not resume else ():
                    if f.is_dir():
                        shutil.rmtree(f)
                    else:
                        f.unlink()
                probe = out / f".gsi-write-test-{comm.rank}"
                probe.write_text("")
                probe.unlink()
            except FileExistsError:
                msg = f"--out = {str(out)!r}: a file of that name exists; give a directory"
            except NotADirectoryError:
                msg = f"--out = {str(out)!r}: a parent is a file, not a directory"
            except PermissionError:
                msg = f"--out = {str(out)!r}: not writable; choose another directory"
            except OSError as exc:
                msg = f"--out = {str(out)!r}: cannot write there ({exc.strerror})"
    if comm.size > 1:
        msg = comm.bcast(msg, root=0)
    if msg:
        raise GsiInputError(msg)
    return out


def run_case(case, *, out, quick: bool = False, pictures: bool | None = None,
             verbose: bool = True, overwrite: bool = False, resume: bool = False,
             checkpoint_every: float | None = None) -> RunResult:
    """Run a case (a :class:`gsi.case.Case` or a path to a case file) into ``out``.

    ``overwrite``: replace an earlier run's outputs in ``out`` (else such a directory is
    refused); ``resume``: continue from the newest checkpoint in ``out``;
    ``checkpoint_every``: simulated seconds between checkpoints (overrides the case). Input
    errors found before the run are the same on every MPI rank (marked so: rank 0 alone
    reports them). A failure to write (a full disk, a quota, a vanished directory) or to
    allocate stops the run with a one-line :class:`gsi.errors.GsiRunError`; the files
    written so far stay, half-written temporary files are removed."""
    if not hasattr(case, "run"):
        from gsi.case import load_case
        try:
            case = load_case(case)
        except GsiInputError as exc:
            raise _agreed(exc)
    try:
        runner = Runner(case, out=out, quick=quick, pictures=pictures, verbose=verbose,
                        overwrite=overwrite, resume=resume, checkpoint_every=checkpoint_every)
    except GsiInputError as exc:
        raise _agreed(exc)
    try:
        return runner.run()
    except OSError as exc:
        _remove_temporaries(out)
        where = exc.filename or f"under {out}"
        raise GsiRunError(f"cannot write {where}: {exc.strerror or exc}; free space (or fix "
                          f"the directory) and run again with --overwrite") from None
    except MemoryError:
        raise GsiRunError("out of memory; fewer particles (particles[].count, rate) or a "
                          "coarser structure mesh (structures[].geometry.h)") from None


def _remove_temporaries(out) -> None:
    """Remove the ``<file>.tmp<pid>`` files a failed atomic write left under ``out``."""
    try:
        for f in pathlib.Path(out).rglob("*.tmp[0-9]*"):
            if f.is_file():
                f.unlink()
    except OSError:
        pass


def demo_main(case, *, description: str = "", argv=None) -> RunResult | None:
    """The command line of a demo script: ``python demos/<name>.py [--quick] [--out DIR]
    [--no-pictures] [--overwrite | --resume] [--checkpoint-every S]``, the options of ``gsi
    run``; runs ``case`` and returns its result. Errors print one line: exit status 2 for
    bad input, 3 for a run that stopped, 130/143 after SIGINT/SIGTERM (checkpoint written)."""
    import argparse
    import sys
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--quick", action="store_true", help="the short form (< 2 minutes)")
    parser.add_argument("--out", default=None, help="output directory (default out/<name>)")
    parser.add_argument("--no-pictures", action="store_true", help="skip the PNG pictures")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace the outputs of an earlier run in --out")
    parser.add_argument("--resume", action="store_true",
                        help="continue from the newest checkpoint under OUT/checkpoints")
    parser.add_argument("--checkpoint-every", type=float, default=None, metavar="S",
                        help="checkpoint every S simulated seconds")
    args = parser.parse_args(argv)
    out = args.out if args.out is not None else pathlib.Path("out") / case.case.name
    try:
        return run_case(case, out=out, quick=args.quick,
                        pictures=False if args.no_pictures else None, overwrite=args.overwrite,
                        resume=args.resume, checkpoint_every=args.checkpoint_every)
    except GsiInputError as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        sys.exit(2)
    except GsiRunError as exc:
        print(f"run stopped: {' '.join(str(exc).split())}", file=sys.stderr)
        sys.exit(3)
    except RunInterrupted as exc:
        print(f"interrupted at t = {exc.time:.6g} s; checkpoint written; resume with "
              f"python {' '.join(sys.argv)} --resume", file=sys.stderr)
        sys.exit(exc.exit_code)
