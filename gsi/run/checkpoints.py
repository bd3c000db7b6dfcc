"""Checkpoint and restart of a run (files: :mod:`gsi.checkpoint`).

:class:`Checkpointer` decides when a checkpoint is due (every ``every`` steps, every
``minutes`` of wall-clock time decided on rank 0, or after SIGINT/SIGTERM, within a
block of DEM steps, :meth:`Checkpointer.between_blocks`), writes the
arrays each rank hands it, and loads the newest valid one back. Every method is
collective."""
from __future__ import annotations

import signal
import time

import numpy as np

from gsi import checkpoint as ck
from gsi.errors import GsiInputError, GsiRunError
from gsi.run.result import RunInterrupted, agree, agreed


class Checkpointer:
    """Checkpoints of one run under ``out/checkpoints``.

    ``comm``/``root``: the MPI communicator and the DEM rank; ``every``: steps between
    checkpoints (None: none); ``minutes``: wall-clock minutes between checkpoints (0:
    none); ``dt``: the DEM step (s); ``manifest``: what the manifest records of the run
    (case name, quick, the case's ``fingerprint``, :mod:`gsi.case.fingerprint`)."""

    def __init__(self, comm, root: int, out, *, every: int | None, minutes: float, dt: float,
                 case_name: str, quick: bool, fingerprint: dict | None = None):
        self.comm, self.root, self.is_root = comm, root, comm.rank == root
        self.directory = out / "checkpoints"
        self.out = out
        self.every, self.minutes, self.dt = every, minutes, dt
        self.case_name, self.quick = case_name, quick
        self.fingerprint = fingerprint    # gsi.case.fingerprint: checked by gsi run --resume
        self.seconds = []          # wall-clock duration of each write (s)
        self.signum = 0
        self.last_step, self.last_wall = 0, time.perf_counter()
        self._previous = {}

    # ------------------------------------------------------------------ signals
    def catch_signals(self) -> None:
        """From now on SIGINT/SIGTERM only set :attr:`signum` (the loop checkpoints and
        stops after the current block of DEM steps, :meth:`between_blocks`, or at the end
        of the chunk; a second signal in a serial run stops at once)."""
        try:
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._previous[sig] = signal.signal(sig, self._on_signal)
        except ValueError:      # not the main thread: no signal handling
            pass

    def release_signals(self) -> None:
        """The signals act as before :meth:`catch_signals` again."""
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)
        self._previous = {}

    def _on_signal(self, signum, frame) -> None:
        if self.signum and self.comm.size == 1:
            raise KeyboardInterrupt
        self.signum = signum

    # ------------------------------------------------------------------ write
    def start(self, k: int) -> None:
        """The loop starts (or resumes) at step ``k``: the clocks count from here."""
        self.last_step, self.last_wall = k, time.perf_counter()

    def _wall_due(self) -> bool:
        return (self.is_root and self.minutes > 0
                and time.perf_counter() - self.last_wall >= 60.0 * self.minutes)

    def between_blocks(self, k: int, nxt: int, exc, state) -> int:
        """After a block of DEM steps of a chunk ending at step ``nxt`` (collective: one
        allreduce of four numbers, see :mod:`gsi.run.stepping`): returns the step the DEM
        (rank ``root``: ``k``) reached, on every rank. An error of the DEM rank (``exc``)
        is raised on every rank. Before ``nxt``, a signal writes the checkpoint of that
        step (``state(k)``: this rank's arrays) and raises :class:`RunInterrupted`, and a
        due wall-clock checkpoint is written; at ``nxt`` both are left to
        :meth:`at_chunk_end`, after the chunk's events."""
        flags = np.array([self.signum, self._wall_due(), k if self.is_root else 0,
                          exc is not None], np.int64)
        if self.comm.size > 1:
            from mpi4py import MPI
            both = np.empty_like(flags)
            self.comm.Allreduce(flags, both, op=MPI.MAX)
            flags = both
        signum, wall_due, k, failed = (int(f) for f in flags)
        if failed:
            raise agree(self.comm, self.root, exc)
        if k < nxt and (signum or wall_due):
            if self.last_step != k:
                self.write(k, state(k))
            if signum:
                raise RunInterrupted(signum, k * self.dt, self.out)
        return k

    def at_chunk_end(self, k: int, state) -> None:
        """At the end of a chunk: write ``state()`` (this rank's arrays) when due or
        signalled; after a signal raise :class:`RunInterrupted` on every rank."""
        due = self.every is not None and k % self.every == 0
        wall_due = self._wall_due()
        flags = np.array([self.signum, wall_due], np.int64)
        if self.comm.size > 1:
            from mpi4py import MPI
            both = np.empty_like(flags)
            self.comm.Allreduce(flags, both, op=MPI.MAX)
            flags = both
        signum = int(flags[0])
        if (due or flags[1] or signum) and self.last_step != k:
            self.write(k, state())
        if signum:
            raise RunInterrupted(signum, k * self.dt, self.out)

    def write(self, k: int, arrays: dict) -> None:
        """Write this rank's ``arrays`` as the checkpoint of step ``k``, then (rank 0) the
        manifest."""
        t0 = time.perf_counter()
        directory = self.directory
        err, size = None, 0
        try:
            if self.is_root:
                directory.mkdir(exist_ok=True)
            if self.comm.size > 1:
                self.comm.barrier()
            size = ck.write_npz(ck.rank_file(directory, k, self.comm.rank), arrays)
        except OSError as exc:
            err = f"checkpoint at t = {k * self.dt:.6g} s: cannot write {directory} ({exc})"
        gathered = self.comm.allgather((err, size)) if self.comm.size > 1 else [(err, size)]
        errors = [e for e, _ in gathered if e]
        if errors:
            raise agreed(GsiRunError(errors[0]))
        if self.is_root:
            try:
                ck.write_manifest(directory, k, dict(
                    time=k * self.dt, n_ranks=self.comm.size, dt=self.dt,
                    case=self.case_name, quick=self.quick, sizes=[s for _, s in gathered],
                    fingerprint=self.fingerprint))
                ck.prune(directory)
            except OSError as exc:
                err = f"checkpoint at t = {k * self.dt:.6g} s: cannot write {directory} ({exc})"
        err = agree(self.comm, self.root, GsiRunError(err) if err else None)
        if err:
            raise err
        self.last_step, self.last_wall = k, time.perf_counter()
        self.seconds.append(time.perf_counter() - t0)

    # ------------------------------------------------------------------ restore
    def newest(self) -> dict:
        """The manifest of the newest valid checkpoint written by this many ranks and this
        ``quick``; a one-line error otherwise."""
        info = ck.newest(self.directory) if self.is_root else None
        if self.comm.size > 1:
            info = self.comm.bcast(info, root=self.root)
        if info is None:
            raise agreed(GsiInputError(
                f"--resume: no complete checkpoint under {self.directory}; run "
                "without --resume (or with --checkpoint-every S)"))
        if info["n_ranks"] != self.comm.size:
            raise agreed(GsiInputError(
                f"--resume: the checkpoint at t = {info['time']:.6g} s was written by "
                f"{info['n_ranks']} MPI rank(s), this run has {self.comm.size}; resume with "
                f"mpirun -n {info['n_ranks']} (or serially for 1)"))
        if info.get("quick", self.quick) != self.quick:
            raise agreed(GsiInputError(f"--resume: the checkpoint was written by a run "
                                       f"{'with' if info['quick'] else 'without'} --quick; "
                                       "resume with the same options"))
        return info

    def restore(self, n_total: int, load) -> dict:
        """Read this rank's arrays of the newest checkpoint, check they belong to a run
        of ``n_total`` steps of this ``dt``, hand them to ``load(arrays)`` and drop the
        newer checkpoints; returns the arrays."""
        info = self.newest()
        err = None
        try:
            d = ck.read_npz(ck.rank_file(self.directory, info["step"], self.comm.rank))
            if float(d["runner.dt"]) != self.dt or int(d["runner.k"]) > n_total:
                raise GsiInputError(
                    f"--resume: the checkpoint (dt = {float(d['runner.dt']):.6g} s, step "
                    f"{int(d['runner.k'])}) does not belong to this case (dt = {self.dt:.6g} s, "
                    f"{n_total} steps); resume with the case that wrote it")
            load(d)
        except GsiInputError as exc:
            err = str(exc)
        except (OSError, KeyError, ValueError) as exc:
            err = (f"--resume: cannot read the checkpoint at t = {info['time']:.6g} s "
                   f"({type(exc).__name__}: {exc}); it does not match this case")
        errors = self.comm.allgather(err) if self.comm.size > 1 else [err]
        errors = [e for e in errors if e]
        if errors:
            raise agreed(GsiInputError(errors[0]))
        if self.is_root:
            ck.clear_newer(self.directory, info["step"])
        return d
