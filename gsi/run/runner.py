"""One runner for every case: the time loop, sub-cycling, outputs, monitors, pictures.

:func:`run_case` (and ``gsi run CASE.toml``) runs any composition of parts
(:mod:`gsi.case`). The loop counts DEM steps k = 0, 1, ..., N (N = duration/dt); the
DEM advances in chunks between *events*, each at a whole step:

* a structure's coupling step ends every ``n_sub`` DEM steps (its own n_sub: several
  structures sub-cycle independently); at the end of each, the structure takes its loads
  and heat, steps, and hands its moved, heated wall back (``finish``), then opens the
  next interval (``begin``);
* a wall motion's schedule event (its time rounded to the nearest step);
* the steps of an ``[extrapolation]`` (:class:`gsi.extrapolation.driver.CaseExtrapolation`):
  temperatures set on two halves, the contact log's start t0 and end t1 (then the
  pairing and the replay), the reference DEM's t_n;
* a monitor sample, every ``interval`` (default the output interval);
* an output (particles, walls, structures, progress line, pictures) every
  ``output.interval``;
* the end.

MPI: the FE structures are distributed over all ranks; the DEM, particle output,
monitors' DEM values and pictures live on rank 0. Every rank runs the same loop (the
event steps are known everywhere); an error on the DEM rank is broadcast at the end of
each block of steps, so every rank stops with the same message and none hangs. The
output directory is locked for the run's lifetime (:mod:`gsi.run.lock`, rank 0).

Files under ``out``: ``particles.pvd`` (+ ``particles/*.vtu``), ``walls/<name>.vtu``
(moving walls: ``walls/<name>.pvd`` series), ``<structure>.xdmf`` (+ ``.h5``, one closed
file pair per step under ``<structure>_steps/``) and its coupling CSVs,
``monitors/<name>.csv`` (one row per sample, flushed as written), ``monitors.png``,
``pictures/frame_*.png``, ``<case>.gif`` and ``<case>.png`` (the last frame), and
``summary.txt`` (the closing summary), ``checkpoints/``.

Checkpoints and restart (:class:`gsi.run.checkpoints.Checkpointer`, files :mod:`gsi.checkpoint`): every ``run.checkpoint_interval``
simulated seconds (``checkpoint_every`` overrides it; the checkpoint steps are events),
every ``run.checkpoint_minutes`` of wall-clock time (decided on rank 0), and on
SIGINT/SIGTERM, every rank writes its state (:meth:`Runner.state`: the DEM's
:meth:`gsi.dem.simulation.Simulation.state` on rank 0, each structure's
:meth:`gsi.coupling.coupled_structure.CoupledStructure.state`, the loop counters, the monitor
series, the output series and the pending picture jobs) to
``checkpoints/ckpt_<step>.rank<r>.npz``, then rank 0 the manifest. The DEM runs a chunk
in blocks of about a quarter second of wall time (:mod:`gsi.run.stepping`; bit-identical
to one call). A signal only sets a flag; after the current block every rank agrees (one
allreduce), writes the checkpoint of that step and raises :class:`RunInterrupted`: a
run stops within about a second of SIGINT/SIGTERM, whatever its output interval. ``resume=True`` rebuilds the case, loads
the newest valid checkpoint (same number of ranks) and continues bit-identically to an
uninterrupted run; every output series is cut back to the checkpoint (PVD entries and
VTU files, CSV rows, XDMF steps), so it has no duplicate and no stale entries.
"""
from __future__ import annotations

import math
import time

import numpy as np

from gsi.errors import GsiInputError, GsiRunError
from gsi.case.biot_check import check_biot
from gsi.case.build_dem import build_simulation
from gsi.dem.engine import is_cached as engine_is_cached
from gsi.case.fingerprint import fingerprint
from gsi.run.checkpoints import Checkpointer
from gsi.run.outdir import claim
from gsi.run.outputs import Outputs
from gsi.run.result import RunResult, agree, agreed, finish_run
from gsi.run.stepping import StepBlocks

__all__ = ["Runner"]


class Runner:
    """Runs one case (see the module docstring).

    Parameters
    ----------
    case : gsi.case.Case
        A validated case (``gsi.case.load_case`` or built in Python).
    out : path
        Output directory (created), locked by this run until :meth:`run` ends (or
        :meth:`close`): another run into it is refused (:mod:`gsi.run.lock`).
    quick : bool
        Run the case's ``[quick]`` form.
    pictures : bool, optional
        Override ``output.pictures``.
    verbose : bool
        Print the set-up, the progress and the summary (rank 0).
    overwrite : bool
        Replace an earlier run's outputs in ``out`` (else refused, see
        :func:`gsi.run.outdir.output_dir`).
    resume : bool
        Continue from the newest valid checkpoint under ``out/checkpoints`` (same case,
        same number of MPI ranks).
    checkpoint_every : float, optional
        Simulated seconds between checkpoints; overrides ``run.checkpoint_interval``
        (0: none).

    Hooks: ``on_resume`` (a list of callables ``f(runner, arrays)``) are called on every
    rank after a resumed run has loaded its checkpoint and opened its outputs.
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
        if checkpoint_every is not None and not (checkpoint_every >= 0
                                                 and math.isfinite(checkpoint_every)):
            raise GsiInputError(f"--checkpoint-every = {checkpoint_every}: must be >= 0 "
                                "(simulated seconds; 0 = none)")
        # the directory's lock (rank 0) until run() ends: see gsi.run.lock
        self.out, self.lock = claim(out, self.comm, overwrite=overwrite, resume=resume)
        self.verbose = verbose and self.is_root
        self.pictures = (case.output.pictures if pictures is None else pictures) and self.is_root
        self.sim = None
        self.handles = {}
        self.groups = {}
        self.structures = []
        self.contact_groups = []
        self.resume = bool(resume)
        self.checkpoint_every = checkpoint_every
        self.checkpoints = None       # Checkpointer, after setup()
        self.outputs = None           # Outputs, when the run starts
        self.blocks = StepBlocks()    # the DEM's step calls (gsi.run.stepping)
        self.on_resume = []

    # ------------------------------------------------------------------ queries for parts
    def say(self, *args, **kw):
        if self.verbose:
            print(*args, **kw, flush=True)

    def structure(self, name: str):
        """The built structure ``name`` (a :class:`gsi.coupling.coupled_structure.CoupledStructure`)."""
        for st in self.structures:
            if st.name == name:
                return st
        raise GsiInputError(f"structure {name!r}: not in the case")

    def wall_handles(self, name: str) -> list:
        """The DEM walls of a ``[[walls]]`` name, or the contact wall(s) of a structure."""
        if name in self.handles:
            return list(self.handles[name])
        st = self.structure(name)
        return [st.wall] if st.wall is not None else []

    def group_ids(self, name: str) -> np.ndarray:
        """Ids of the particles of a ``[[particles]]`` source."""
        g = self.groups[name]
        ids = getattr(g, "ids", g)
        return np.asarray(ids, np.int64)

    def heat_capacity(self) -> np.ndarray:
        """m c_p of each particle (J/K), as the DEM integrates it (scaled c_p)."""
        from gsi.coupling.thermal import particle_heat_capacity
        return particle_heat_capacity(self.sim)

    @property
    def checkpoint_seconds(self) -> list:
        """Wall-clock duration of each checkpoint write (s)."""
        return self.checkpoints.seconds if self.checkpoints is not None else []

    # ------------------------------------------------------------------ set-up
    def setup(self) -> None:
        """Build the DEM (rank 0), the structures (every rank), the contact groups, the
        event schedule and the extrapolation."""
        case = self.case
        try:
            self.dt = case.check()
        except GsiInputError as exc:      # the same case on every rank: the same error
            raise agreed(exc)
        self.n_total = max(1, int(round(case.run.duration / self.dt)))
        if self.is_root:
            self.sim, self.handles, self.groups = build_simulation(case, dt=self.dt)
            if not self.resume:
                check_biot(case, self.sim)      # a warning when Bi is not << 1 at the start
        err = agree(self.comm, self.root, None)
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
        self.every = _periods(case, self.dt, self.structures)
        interval = (case.run.checkpoint_interval if self.checkpoint_every is None
                    else self.checkpoint_every)
        self.checkpoints = Checkpointer(
            self.comm, self.root, self.out, dt=self.dt, case_name=case.case.name,
            quick=self.quick, minutes=case.run.checkpoint_minutes, fingerprint=fingerprint(case),
            every=max(1, int(round(interval / self.dt))) if interval > 0 else None)
        self.extrapolation = _case_extrapolation(case, self.dt, self.out, self.structures,
                                                 resume=self.resume, ranks=self.comm.size)
        self.motion_events = _motion_events(case, self.dt, self.n_total, self.handles,
                                            self.structures)

    # ------------------------------------------------------------------ the loop
    def run(self) -> RunResult:
        """Run the case (or continue it, ``resume``); see the module docstring."""
        wall0 = time.perf_counter()
        try:
            return self._run(wall0)
        finally:
            if self.checkpoints is not None:
                self.checkpoints.release_signals()
            self.close()

    def close(self) -> None:
        """Release the output directory's lock (:meth:`run` does it when it ends; call
        it for a runner that is not run)."""
        if self.lock is not None:
            self.lock.release()
            self.lock = None

    def _run(self, wall0: float) -> RunResult:
        self.setup()
        case = self.case
        restored = (self.checkpoints.restore(self.n_total, self.load_state) if self.resume
                    else None)
        self.say(f"{case.case.name}: {self.sim.n if self.sim is not None else '?'} particles, "
                 f"{len(case.walls)} walls, {len(self.structures)} structure(s) "
                 f"{', '.join(f'{s.name} (n_sub {s.n_sub})' for s in self.structures)}; "
                 f"dt = {self.dt:.3g} s, {self.n_total} steps ({self.n_total * self.dt:g} s)"
                 f"{' [quick]' if self.quick else ''} -> {self.out}")
        self.outputs = Outputs(self.out, case, is_root=self.is_root, pictures=self.pictures,
                               handles=self.handles, structures=self.structures)
        self.outputs.open(restored)
        try:
            if restored is None:
                k, n_out = 0, 0
                for st in self.structures:
                    st.begin()
                for m in case.monitors:
                    self._sample(m, 0.0)
                self.outputs.write(self.sim, 0.0, n_out)
            else:
                for hook in self.on_resume:
                    hook(self, restored)
                k, n_out = int(restored["runner.k"]), int(restored["runner.n_out"])
                self.say(f"resumed at t = {k * self.dt:.6g} s (step {k}) from "
                         f"{self.out / 'checkpoints'}")
            self._loop(k, n_out, wall0)
        finally:
            self.outputs.close()
        return self._finish(wall0)

    def _loop(self, k: int, n_out: int, wall0: float) -> None:
        """Steps ``k``..N in chunks between events."""
        case, ckpt = self.case, self.checkpoints
        ckpt.start(k)
        ckpt.catch_signals()
        if self.is_root and not engine_is_cached():
            self.say("DEM engine: compiling on first use (about a minute on 2 cores; "
                     "cached for the next runs)")
        while k < self.n_total:
            nxt = min([self.n_total] + [(k // e + 1) * e for e in self.every.values()]
                      + [j for j in self.motion_events if j > k]
                      + [j for j in (self.extrapolation.steps if self.extrapolation
                                     else ()) if j > k])
            if ckpt.every is not None:
                nxt = min(nxt, (k // ckpt.every + 1) * ckpt.every)
            while k < nxt:       # in blocks: a signal is honoured within one block
                exc = None
                if self.is_root:
                    try:
                        k += self.blocks.step(self.sim, nxt - k)
                    except (GsiRunError, GsiInputError) as e:
                        exc = e
                k = ckpt.between_blocks(k, nxt, exc, lambda j: self.state(j, n_out))
            t = k * self.dt
            self.finish_structures(k)
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
                self.outputs.write(self.sim, t, n_out, last=k == self.n_total)
                if self.verbose and case.run.progress:
                    _progress(k, self.n_total, self.dt, case.run.duration, wall0,
                              self.sim.n if self.sim is not None else 0)
            if k < self.n_total:
                ckpt.at_chunk_end(k, lambda: self.state(k, n_out))
        ckpt.release_signals()
        if ckpt.signum:       # it came during the last chunk: the run is complete
            self.say("the run completed before the interruption took effect")

    def _sample(self, m, t: float) -> None:
        self.outputs.record_sample(m, t, m.sample(self))

    def finish_structures(self, k: int) -> None:
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
    def state(self, k: int, n_out: int) -> dict:
        """This rank's checkpoint arrays at loop step ``k``: ``runner.*`` (k, output count),
        ``mon.<monitor>.<column>`` (the series so far), ``pvd.*`` (output series times),
        ``fem.<structure>.writes``, ``frames`` (pending picture jobs, rank 0), ``dem.*``
        (:meth:`gsi.dem.simulation.Simulation.state`, rank 0) and
        ``st.<structure>.*`` (:meth:`gsi.coupling.coupled_structure.CoupledStructure.state`)."""
        d = {"runner.k": np.int64(k), "runner.n_out": np.int64(n_out),
             "runner.n_total": np.int64(self.n_total), "runner.dt": np.float64(self.dt)}
        for st in self.structures:
            d[f"fem.{st.name}.writes"] = np.int64(st.n_writes)
            d.update({f"st.{st.name}.{key}": v for key, v in st.state().items()})
        if self.is_root:
            d.update(self.outputs.state())
            d.update({f"dem.{key}": v for key, v in self.sim.state().items()})
        return d

    def load_state(self, d: dict) -> None:
        """Set the DEM (rank 0) and the structures from checkpoint arrays ``d``."""
        if self.is_root:
            self.sim.set_state({key[4:]: v for key, v in d.items() if key.startswith("dem.")})
        for st in self.structures:
            p = f"st.{st.name}."
            st.set_state({key[len(p):]: v for key, v in d.items() if key.startswith(p)})

    def write_checkpoint(self, k: int, n_out: int) -> None:
        """Write the checkpoint of loop step ``k`` (collective; see :mod:`gsi.checkpoint`)."""
        self.checkpoints.write(k, self.state(k, n_out))

    # ------------------------------------------------------------------ results
    def _finish(self, wall0: float) -> RunResult:
        """The result (rank 0 builds it, prints and writes the summary; every rank gets it)."""
        structures = {st.name: st.summary() for st in self.structures}
        res = None
        if self.is_root:
            res = finish_run(self.case, self.sim, self.handles, self.structures, self.outputs,
                             self.extrapolation, out=self.out, dt=self.dt, wall0=wall0,
                             pictures=self.pictures, structure_summaries=structures,
                             checkpoint_seconds=self.checkpoint_seconds, say=self.say)
        return self.comm.bcast(res, root=self.root)


def _progress(k: int, n_total: int, dt: float, duration: float, wall0: float,
              n: int) -> None:
    """The progress line after step ``k`` (``n`` particles)."""
    frac = k / n_total
    el = time.perf_counter() - wall0
    rate = k * dt / el if el > 0 else math.nan
    eta = el * (1 - frac) / frac if frac > 0 else math.nan
    bar = "#" * int(20 * frac) + "." * (20 - int(20 * frac))
    print(f"  [{bar}] t = {k * dt:8.4f} / {duration:g} s  "
          f"{rate:.3g} s/s  ETA {eta:5.0f} s  particles {n}", flush=True)


def _case_extrapolation(case, dt, out, structures, *, resume: bool, ranks: int):
    """The long-time heat extrapolation (gsi.case.extrapolation): its steps are events."""
    if case.extrapolation is None:
        return None
    if resume:
        raise agreed(GsiInputError(
            "resume: a case with [extrapolation] cannot resume (its contact log is "
            "not in the checkpoints); run it again"))
    from gsi.extrapolation import CaseExtrapolation
    if structures and ranks > 1:
        raise agreed(GsiInputError(
            "extrapolation with [[structures]]: the replay of an FE wall runs on one MPI "
            "rank; run without mpirun"))
    return CaseExtrapolation(case.extrapolation, dt=dt, out=out,
                             structure=structures[0] if structures else None)


def _periods(case, dt: float, structures) -> dict:
    """Steps between the periodic events: outputs, each monitor's samples, each
    structure's coupling interval."""
    every = {"output": max(1, int(round(case.output.interval / dt)))}
    for m in case.monitors:
        every[f"monitor:{m.name}"] = max(1, int(round((m.interval or case.output.interval)
                                                      / dt)))
    for st in structures:
        every[f"structure:{st.name}"] = st.n_sub
    return every


def _motion_events(case, dt: float, n_total: int, handles: dict, structures) -> dict:
    """Step -> [(move(t), t)] of the walls' and structures' schedule events. An event at
    time t takes effect at the first step boundary at or after t (the wall takes the motion
    state of the event itself, whatever the round-off)."""
    events = {}
    movers = [(w.motion, lambda t, w=w: w.apply_motion(handles[w.name], t))
              for w in case.walls]
    movers += [(st.contact.motion, lambda t, st=st, b=b: st.apply_motion(b.wall, t))
               for st, b in zip(case.structures, structures)
               if st.contact.motion is not None]
    for motion, move in movers:
        for t in motion.event_times():
            k = int(math.ceil(t / dt - 1e-9))
            if 0 < k <= n_total:
                events.setdefault(k, []).append((move, t))
    return events
