"""The output series of a run: particles, moving walls, monitors, structures' files and
the picture jobs; each continued from a checkpoint when the run resumes.

:class:`Outputs` takes the data it writes (the case, the DEM walls by case name, the
built structures) and is driven by the loop through its public methods."""
from __future__ import annotations

import csv
import json
import re

import numpy as np

from gsi.checkpoint import pack, truncate_csv, unpack
from gsi.dem.output import ParticleWriter, PvdSeries, write_wall_vtu
from gsi.run.pictures import picture_job


class Outputs:
    """Files under ``out`` (rank 0 the DEM's, every rank its structures' part).

    ``handles``: the case's DEM walls by ``[[walls]]`` name; ``structures``: the built
    :class:`gsi.coupling.coupled_structure.CoupledStructure` objects; ``pictures``: collect picture
    jobs (rank 0)."""

    def __init__(self, out, case, *, is_root: bool, pictures: bool, handles: dict,
                 structures: list):
        self.out, self.case, self.is_root = out, case, is_root
        self.pictures = pictures
        self.handles, self.structures = handles, structures
        self.files = []
        self.particles = None          # ParticleWriter
        self.wall_series = []          # [(PvdSeries, DEM wall)]
        self.monitors = {}             # name -> {column: list}
        self.frames = []               # picture jobs

    def open(self, restored: dict | None = None) -> None:
        """Open the series; ``restored`` (a checkpoint's arrays) continues those of an
        earlier run, cut back to the checkpoint."""
        out, fields = self.out, self.case.output.fields
        if self.is_root:
            if restored is not None:      # temporaries of a killed run
                for p in out.iterdir():
                    if re.search(r"\.tmp\d+$", p.name) and p.is_file():
                        p.unlink(missing_ok=True)
            if "particles" in fields:
                self.particles = ParticleWriter(
                    out / "particles", "particles",
                    times=None if restored is None else restored["pvd.particles"])
                self.files.append(out / "particles" / "particles.pvd")
            if "walls" in fields:
                self._open_walls(restored)
            (out / "monitors").mkdir(exist_ok=True)
        if "structures" in fields:
            for st in self.structures:
                st.open_output(out, resume=None if restored is None else
                               int(restored[f"fem.{st.name}.writes"]))
        self._open_monitors(restored)
        if restored is not None and "frames" in restored:
            self.frames = unpack(json.loads(str(restored["frames"])), restored)

    def _open_walls(self, restored) -> None:
        out = self.out
        (out / "walls").mkdir(exist_ok=True)
        for w in self.case.walls:
            for j, h in enumerate(self.handles[w.name]):
                if not hasattr(h, "triangles"):
                    continue      # planes have no geometry to write
                stem = w.name if len(self.handles[w.name]) == 1 else f"{w.name}_{j}"
                if w.motion.moves:
                    times = (None if restored is None
                             else restored[f"pvd.walls.{len(self.wall_series)}"])
                    self.wall_series.append((PvdSeries(out / "walls", stem, times=times), h))
                    self.files.append(out / "walls" / f"{stem}.pvd")
                    continue
                if restored is None:
                    write_wall_vtu(out / "walls" / f"{stem}.vtu", h)
                self.files.append(out / "walls" / f"{stem}.vtu")

    def _open_monitors(self, restored) -> None:
        for m in self.case.monitors:
            rec = self.monitors[m.name] = {"time_s": [], **{c: [] for c in m.columns}}
            if restored is not None:
                for c in rec:
                    rec[c] = restored.get(f"mon.{m.name}.{c}", np.zeros(0)).tolist()
            if self.is_root:
                path = self.out / "monitors" / f"{m.name}.csv"
                if restored is None:
                    with path.open("w", newline="") as fh:
                        csv.writer(fh).writerow(["time_s", *m.columns])
                else:
                    truncate_csv(path, len(rec["time_s"]))
                self.files.append(path)

    def record_sample(self, m, t: float, row) -> None:
        """Append monitor ``m``'s sample ``row`` at time ``t`` (rank 0: to its CSV)."""
        if not self.is_root:
            return
        rec = self.monitors[m.name]
        rec["time_s"].append(t)
        for c, v in zip(m.columns, row):
            rec[c].append(v)
        with (self.out / "monitors" / f"{m.name}.csv").open("a", newline="") as fh:
            csv.writer(fh).writerow([f"{t:.10g}", *(f"{v:.10g}" if isinstance(v, float) else v
                                                    for v in row)])

    def write(self, sim, t: float, n_out: int, *, last: bool = False) -> None:
        """The output at time ``t`` (the ``n_out``-th; ``last``: the run's end)."""
        if "structures" in self.case.output.fields:
            for st in self.structures:
                st.write_output(t)
        if not self.is_root:
            return
        if self.particles is not None:
            self.particles.write(sim)
        for series, wall in self.wall_series:
            path = series.next_path()
            write_wall_vtu(path, wall)
            series.add(t, path)
        if self.pictures and (n_out % self.case.output.picture_every == 0 or last):
            self.frames.append(picture_job(self.case, sim, self.handles, self.structures,
                                           self.out, t, len(self.frames)))

    def close(self) -> None:
        """Close the series (every rank: its structures' files)."""
        if self.is_root and self.particles is not None:
            self.particles.close()
        for st in self.structures:
            st.close()

    def monitor_arrays(self) -> dict:
        """The monitor series so far: name -> {column: array}."""
        return {name: {c: np.asarray(v) for c, v in rec.items()}
                for name, rec in self.monitors.items()}

    def state(self) -> dict:
        """Checkpoint arrays of the series (rank 0): ``mon.*``, ``pvd.*``, ``frames``."""
        d = {}
        for name, rec in self.monitors.items():
            for c, v in rec.items():
                d[f"mon.{name}.{c}"] = np.asarray(v)
        if self.particles is not None:
            d["pvd.particles"] = self.particles.times()
        for i, (series, _) in enumerate(self.wall_series):
            d[f"pvd.walls.{i}"] = series.times()
        if self.frames:
            arrays = {}
            d["frames"] = np.array(json.dumps(pack(self.frames, arrays, "frame.")))
            d.update(arrays)
        return d
