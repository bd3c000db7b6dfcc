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
"""
from __future__ import annotations

import csv
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
                 xdmf: bool = True):
        prob = elasticity if elasticity is not None else heat
        self.elasticity, self.heat = elasticity, heat
        self.comm = prob.comm
        self.mesh = prob.mesh
        self.dir = Path(directory)
        if self.comm.rank == 0:
            self.dir.mkdir(parents=True, exist_ok=True)
        self.comm.barrier()
        self.tags = [n for n in prob.structure.tags if n != "volume"]
        self.csv_path = self.dir / f"{prefix}.csv"
        self.columns = ["t", "max_deflection", "max_von_mises", "T_min", "T_max",
                        "reaction_x", "reaction_y", "reaction_z"] + \
                       [f"heat_flow_{n}" for n in self.tags] + ["nodal_heat"]
        if self.comm.rank == 0:
            with open(self.csv_path, "w", newline="") as fh:
                csv.writer(fh).writerow(self.columns)
        self._xdmf = None
        if xdmf:
            self._xdmf = compat.xdmf_file(self.comm, self.dir / f"{prefix}.xdmf", "w")
            compat.xdmf_write_mesh(self._xdmf, self.mesh)
            if elasticity is not None:
                self._u1 = compat.function(compat.vector_space(self.mesh, 1), "displacement")
            if heat is not None:
                self._T1 = compat.function(compat.scalar_space(self.mesh, 1), "temperature")

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
        """Append the fields at time ``t`` (s) to the XDMF and a row to the CSV."""
        r = self.row(t)
        if self.comm.rank == 0:
            with open(self.csv_path, "a", newline="") as fh:
                csv.writer(fh).writerow([f"{r[c]:.10g}" for c in self.columns])
        if self._xdmf is not None:
            if self.elasticity is not None:
                compat.interpolate_function(self._u1, self.elasticity.u)
                compat.xdmf_write_function(self._xdmf, self._u1, t)
                compat.xdmf_write_function(self._xdmf, self.elasticity.von_mises(), t)
            if self.heat is not None:
                compat.interpolate_function(self._T1, self.heat.T)
                compat.xdmf_write_function(self._xdmf, self._T1, t)
        return r

    def close(self) -> None:
        if self._xdmf is not None:
            self._xdmf.close()
            self._xdmf = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False
