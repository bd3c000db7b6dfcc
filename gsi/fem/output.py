"""Structure output: an XDMF time series (ParaView) and a CSV time series of key numbers.

``structure.xdmf`` (+ ``.h5``) holds the mesh and, at every :meth:`FemOutput.write`,
``displacement`` (P1 vector, m), ``von_mises`` (DG0, Pa) and ``temperature`` (P1, K or degC),
as far as the problems exist. Open it in ParaView with the "Xdmf3ReaderT" reader.

``structure.csv`` has one row per write with the columns

``t`` (s), ``max_deflection`` (m, largest nodal |u|), ``max_von_mises`` (Pa, largest cell
value), ``T_min``, ``T_max``, ``reaction_x``, ``reaction_y``, ``reaction_z`` (N, total
force of the supports on the structure, from the residual M a + C v + K u - f at the
constrained dofs) and ``heat_flow_<tag>`` (W, conductive heat flow into the structure
through each tagged surface: the Dirichlet residual on fixed-temperature surfaces,
int q + h (T_ambient - T) ds on the others) and ``nodal_heat`` (W, sum of the nodal heat
loads, e.g. from particles).

Crash safety (every step is durable; dolfinx 0.5.2's ``XDMFFile`` keeps one HDF5 file
open and a kill -9 leaves it unreadable, and re-opening it in mode ``"a"`` cannot
replace a step): each :meth:`FemOutput.write` writes its fields into a closed file
pair of its own, ``<prefix>_steps/<prefix>_<k:06d>.xdmf`` (+ ``.h5``), then rewrites
``<prefix>.xdmf`` atomically (temporary file, fsync, rename): the mesh (in
``<prefix>.h5``) and one temporal collection per field whose k-th entry points into
the k-th step file. After a kill at any moment ``<prefix>.xdmf`` lists only complete
steps. The CSV gets one row per write, appended and closed at once. ``resume=n`` keeps
the first n writes of an earlier run (CSV rows, XDMF steps) and drops the rest.
"""
from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np
from mpi4py import MPI

from . import compat


class FemOutput:
    """Writer of the XDMF and CSV series of an elasticity and/or heat problem.

    Parameters
    ----------
    directory : str or Path
        Output directory (created).
    elasticity, heat : problems (at least one)
    prefix : str
        File name stem (default "structure").
    xdmf : bool
        Write the XDMF fields (default True); the CSV is always written.
    """

    def __init__(self, directory, *, elasticity=None, heat=None, prefix: str = "structure",
                 xdmf: bool = True, resume: int | None = None):
        from gsi.checkpoint import truncate_csv
        prob = elasticity if elasticity is not None else heat
        self.elasticity, self.heat = elasticity, heat
        self.comm = prob.comm
        self.mesh = prob.mesh
        self.dir = Path(directory)
        self.prefix = prefix
        if self.comm.rank == 0:
            self.dir.mkdir(parents=True, exist_ok=True)
        self.comm.barrier()
        self.tags = [n for n in prob.structure.tags if n != "volume"]
        self.csv_path = self.dir / f"{prefix}.csv"
        self.columns = ["t", "max_deflection", "max_von_mises", "T_min", "T_max",
                        "reaction_x", "reaction_y", "reaction_z"] + \
                       [f"heat_flow_{n}" for n in self.tags] + ["nodal_heat"]
        self.n_writes = 0 if resume is None else int(resume)
        if self.comm.rank == 0:
            if resume is None:
                with open(self.csv_path, "w", newline="") as fh:
                    csv.writer(fh).writerow(self.columns)
            else:
                truncate_csv(self.csv_path, self.n_writes)
        self._xdmf = None
        if xdmf:
            self._xdmf = self.dir / f"{prefix}.xdmf"
            self._steps_dir = self.dir / f"{prefix}_steps"
            if self.comm.rank == 0:
                self._steps_dir.mkdir(exist_ok=True)
            if resume is None:
                with compat.xdmf_file(self.comm, self._xdmf, "w") as f:
                    compat.xdmf_write_mesh(f, self.mesh)
            self._steps = []          # per write: {field name: its Grid element (text)}
            if self.comm.rank == 0:
                self._read_series(keep=self.n_writes)
                if resume is not None:
                    for p in self._steps_dir.iterdir():
                        m = re.match(rf"^{re.escape(prefix)}_(\d{{6}})\.", p.name)
                        if m is None or int(m.group(1)) >= self.n_writes:
                            p.unlink(missing_ok=True)
                self._write_series()
            self.comm.barrier()
            if elasticity is not None:
                self._u1 = compat.function(compat.vector_space(self.mesh, 1), "displacement")
            if heat is not None:
                self._T1 = compat.function(compat.scalar_space(self.mesh, 1), "temperature")

    # ---- the XDMF series (rank 0)
    def _read_series(self, *, keep: int) -> None:
        mesh_grid, series = _parse_xdmf(self._xdmf.read_text())
        self._mesh_grid = mesh_grid
        self._fields = list(series)
        for name, grids in series.items():
            for k, g in enumerate(grids[:keep]):
                if k == len(self._steps):
                    self._steps.append({})
                self._steps[k][name] = g
        if len(self._steps) < keep:
            raise OSError(f"{self._xdmf}: holds {len(self._steps)} steps, the checkpoint "
                          f"expects {keep}")

    def _write_series(self) -> None:
        from gsi.checkpoint import write_atomic
        parts = ['<?xml version="1.0"?>\n<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>\n'
                 '<Xdmf Version="3.0" xmlns:xi="http://www.w3.org/2001/XInclude">\n'
                 '  <Domain>\n    ', self._mesh_grid, '\n']
        for name in self._fields:
            parts.append(f'    <Grid Name="{name}" GridType="Collection" '
                         'CollectionType="Temporal">\n')
            parts += [f"      {st[name]}\n" for st in self._steps if name in st]
            parts.append("    </Grid>\n")
        parts.append("  </Domain>\n</Xdmf>\n")
        write_atomic(self._xdmf, "".join(parts))

    def _write_fields(self, t: float) -> None:
        stem = f"{self.prefix}_{self.n_writes:06d}"
        with compat.xdmf_file(self.comm, self._steps_dir / f"{stem}.xdmf", "w") as f:
            compat.xdmf_write_mesh(f, self.mesh)
            if self.elasticity is not None:
                compat.interpolate_function(self._u1, self.elasticity.u)
                compat.xdmf_write_function(f, self._u1, t)
                compat.xdmf_write_function(f, self.elasticity.von_mises(), t)
            if self.heat is not None:
                compat.interpolate_function(self._T1, self.heat.T)
                compat.xdmf_write_function(f, self._T1, t)
        if self.comm.rank == 0:
            _, series = _parse_xdmf((self._steps_dir / f"{stem}.xdmf").read_text())
            step = {}
            for name, grids in series.items():
                step[name] = grids[0].replace(f">{stem}.h5:",
                                              f">{self._steps_dir.name}/{stem}.h5:")
                if name not in self._fields:
                    self._fields.append(name)
            self._steps.append(step)
            self._write_series()

    def row(self, t: float) -> dict:
        """The CSV numbers at time ``t`` (collective)."""
        r = {c: np.nan for c in self.columns}
        r["t"] = float(t)
        if self.elasticity is not None:
            e = self.elasticity
            r["max_deflection"] = e.max_displacement()
            vm = e.von_mises()
            ncell = compat.num_cells_local(self.mesh)
            local = float(vm.x.array[:ncell].max()) if ncell else 0.0
            r["max_von_mises"] = self.comm.allreduce(local, op=MPI.MAX)
            r["reaction_x"], r["reaction_y"], r["reaction_z"] = e.reaction()
        if self.heat is not None:
            r["T_min"], r["T_max"] = self.heat.min_max()
            for n in self.tags:
                r[f"heat_flow_{n}"] = self.heat.heat_flow(n)
            r["nodal_heat"] = self.heat.nodal_heat()
        return r

    def write(self, t: float) -> dict:
        """Append the fields at time ``t`` (s) to the XDMF series and a row to the CSV
        (collective; both durable when it returns)."""
        r = self.row(t)
        if self.comm.rank == 0:
            with open(self.csv_path, "a", newline="") as fh:
                csv.writer(fh).writerow([f"{r[c]:.10g}" for c in self.columns])
        if self._xdmf is not None:
            self._write_fields(t)
        self.n_writes += 1
        return r

    def close(self) -> None:
        """Nothing is left open between writes; kept for the context-manager protocol."""
        self._xdmf = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


_XI = "http://www.w3.org/2001/XInclude"


def _parse_xdmf(text):
    """(mesh Grid as text, {field: [its temporal Grids as text]}) of an XDMF file in the
    layout dolfinx writes."""
    import xml.etree.ElementTree as ET
    ET.register_namespace("xi", _XI)
    domain = ET.fromstring(text).find("Domain")

    def txt(el):
        el.tail = None
        return ET.tostring(el, encoding="unicode")
    mesh, series = None, {}
    for grid in domain.findall("Grid"):
        if grid.get("CollectionType") == "Temporal":
            series[grid.get("Name")] = [txt(g) for g in grid.findall("Grid")]
        elif mesh is None:
            mesh = txt(grid)
    return mesh, series
