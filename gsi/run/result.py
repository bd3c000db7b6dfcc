"""What a run hands back: :class:`RunResult`, the closing summary, :class:`RunInterrupted`."""
from __future__ import annotations

import dataclasses
import math
import pathlib

import numpy as np

from gsi.checkpoint import write_atomic


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


def agreed(exc):
    """Mark an error that every rank raises alike (rank 0 alone reports it)."""
    exc.agreed = True
    return exc


def agree(comm, root: int, exc):
    """Broadcast an error raised on the DEM rank ``root`` (or None) so that every rank
    stops with it (one message): returns the error on every rank, or None."""
    from gsi.errors import GsiInputError, GsiRunError
    if comm.size == 1:
        return exc
    payload = (type(exc).__name__, str(exc)) if exc is not None else None
    payload = comm.bcast(payload, root=root)
    if payload is None:
        return None
    kind = GsiInputError if payload[0] == "GsiInputError" else GsiRunError
    err = exc if exc is not None else kind(payload[1])
    err.agreed = True       # every rank raises it: rank 0 alone reports it
    return err


def summary(r: RunResult, extrap: dict | None = None,
            extra_lines: list[str] = ()) -> tuple[str, dict]:
    """The closing physics summary of ``r``: its text and its key=value numbers (with
    those of the extrapolation, ``extrap``, and its own ``extra_lines``)."""
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
        if "drift_rel" in rec:        # an energy monitor: its drift is a key number
            keys[f"{name}.drift_rel"] = float(f"{rec['drift_rel'][-1]:.4e}")
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
        lines += list(extra_lines)
    return "\n".join(lines), keys


def key_line(keys: dict) -> str:
    """The last summary line: ``key=value`` pairs."""
    return " ".join(f"{k}={v:.6g}" if isinstance(v, float) else f"{k}={v}"
                    for k, v in keys.items())


def write_summary(out: pathlib.Path, text: str, keys: dict) -> None:
    """``out/summary.txt``: the summary text and its key line."""
    write_atomic(out / "summary.txt", text + "\n" + key_line(keys) + "\n", fsync=False)


def finish_run(case, sim, handles, structures, outputs, extrapolation, *, out, dt, wall0,
               pictures, structure_summaries, checkpoint_seconds, say) -> RunResult:
    """The end of a run on the DEM rank: the loads on the walls, the monitor series, the
    pictures, the extrapolation's summary; the :class:`RunResult` with its summary
    printed (``say``) and written to ``out/summary.txt``."""
    import time
    from gsi.run.pictures import monitor_plot, render_frames
    g = np.asarray(case.dem.gravity, float)
    load = np.zeros(3)
    for hs in handles.values():
        for h in hs:
            load += h.force
    for st in structures:
        if st.wall is not None:
            load += st.wall.force
    monitors = outputs.monitor_arrays()
    files = list(outputs.files)
    for st in structures:
        files += st.output_files()
    files += monitor_plot(out, case.case.name, monitors)
    if pictures and outputs.frames:
        files += render_frames(out, case.case.name, outputs.frames)
    extrap, extra = {}, []
    if extrapolation is not None:
        extrap = extrapolation.finish(case.case.name)
        if extrap:
            extra = extrapolation.summary_lines(extrap)
            files += extrapolation.files
            if pictures:
                files += extrapolation.pictures(case.case.name, view=case.output.view)
    res = RunResult(name=case.case.name, time=sim.time, steps=sim.step_count, dt=dt,
                    n_particles=int(sim.n), n_lost=int(sim.n_lost),
                    particle_mass=float(sim.mass.sum()), kinetic_energy=sim.kinetic_energy(),
                    wall_load=load, weight=float(sim.mass.sum()) * g, monitors=monitors,
                    structures=structure_summaries, summary={},
                    wall_clock=time.perf_counter() - wall0, files=files)
    text, res.summary = summary(res, extrap, extra)
    say(text)
    say(key_line(res.summary))
    write_summary(out, text, res.summary)
    if checkpoint_seconds:
        spent = sum(checkpoint_seconds)
        say(f"checkpoints: {len(checkpoint_seconds)} written in {spent:.3f} s "
            f"({100 * spent / res.wall_clock:.2f} % of the {res.wall_clock:.1f} s "
            f"wall time; the longest {max(checkpoint_seconds):.3f} s)")
    return res
