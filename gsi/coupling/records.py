"""The per-interval records of a coupling: kept in memory, appended to a CSV as they come.

One name per idea: a coupling interval (n_sub DEM steps, one FE step) leaves a
:class:`MechanicalRecord` (forces and motion, :mod:`gsi.coupling.staggered`) and/or a
:class:`ThermalRecord` (heat, :mod:`gsi.coupling.thermal`); a structure's interval
returns both in one :class:`IntervalRecord`.

:class:`RecordLog` is the part :class:`gsi.coupling.staggered.StaggeredCoupling` and
:class:`gsi.coupling.thermal.ThermalCoupling` share: a record is a dataclass row
(``RECORD``), its fields are the CSV columns, each row is appended (and closed) when it is
made, so a killed run leaves a complete CSV, and the rows round-trip through plain arrays
for checkpoints.
"""
from __future__ import annotations

import csv
import dataclasses
import pathlib

import numpy as np

__all__ = ["RecordLog", "MechanicalRecord", "ThermalRecord", "IntervalRecord"]


@dataclasses.dataclass
class MechanicalRecord:
    """One interval of the mechanical coupling (SI units; :mod:`gsi.coupling.staggered`)."""

    step: int
    t: float              # s, time at the end of the step
    load_x: float         # N, sum of the nodal loads held by the FE
    load_y: float
    load_z: float
    wall_force_x: float   # N, -impulse_on_particles / dt_FE
    wall_force_y: float
    wall_force_z: float
    balance_rel: float    # -, |load - wall_force| / |wall_force|
    work_step: float      # J, sum P . du over the step
    work: float           # J, cumulative
    max_deflection: float  # m, largest |u| at the interface nodes
    min_uz: float         # m, lowest vertical displacement at the interface nodes
    n_particles: int
    n_loaded_triangles: int  # wall triangles touched by particles at the last DEM step
    wall_dem: float       # s of wall-clock time in the DEM sub-cycle (rank root)
    wall_fe: float        # s in the FE step/solve
    wall_transfer: float  # s in gathering, broadcasting and applying loads and positions



@dataclasses.dataclass
class ThermalRecord:
    """The energy record and key numbers of one interval of the heat coupling (SI units;
    :mod:`gsi.coupling.thermal`)."""

    step: int
    t: float                 # s, simulated time at the end of the step
    t_thermal: float         # s, time of the physical system (time_scale * t)
    Q_particles: float       # J, heat leaving the particles into the wall over the step
    Q_radiation: float       # J, the part of Q_particles carried by radiation
    Q_friction: float        # J, the wall's share of the frictional heat over the step
    Q_structure: float       # J, heat entering the structure through the nodal loads
    balance_error: float     # J, Q_structure - Q_particles - Q_friction
    heat_flow: float         # W, Q_structure / dt_FE: heat flow into the wall
    Q_boundary_loss: float   # J, heat leaving the structure through its boundary (convection)
    Q_planes: float          # J, heat from DEM planes with a temperature (and the radiation
                             # enclosure) into the particles
    Q_contact: float         # J, heat into the structure from FE-FE contacts (other bodies)
    E_particles: float       # J, sum m c_p (T - T_ref)
    E_structure: float       # J, int rho c (T - T_ref) dx
    drift: float             # J, total energy drift since the start
    T_wall_max: float        # max nodal structure temperature
    T_wall_mean: float       # volume mean structure temperature
    T_contact_max: float     # max temperature at the contact-surface vertices
    T_particles_mean: float  # mass-heat-capacity weighted mean particle temperature
    T_particles_max: float
    max_von_mises: float     # Pa (nan without elasticity)
    max_displacement: float  # m (nan without elasticity)
    wall_force_z: float      # N, time-averaged z force of the particles on the wall
    n_particles: int
    n_contacts: int



def _fmt(v) -> str:
    return f"{v:.12g}" if isinstance(v, float) else str(v)


@dataclasses.dataclass
class IntervalRecord:
    """One interval of a structure, as
    :meth:`gsi.coupling.coupled_structure.CoupledStructure.finish` returns it.

    ``mechanical``: :class:`MechanicalRecord` (None for a thermal-only contact);
    ``thermal``: :class:`ThermalRecord` (None without heat coupling). ``t`` (s): the time at the end of the interval.
    """

    name: str
    t: float
    mechanical: object = None
    thermal: object = None


class RecordLog:
    """Records of one coupling (subclasses set ``RECORD``, a dataclass, and ``is_root``)."""

    RECORD: type = None

    @classmethod
    def columns(cls) -> list[str]:
        return [f.name for f in dataclasses.fields(cls.RECORD)]

    def _init_log(self, csv_path) -> None:
        self.records = []
        self.csv_path = None
        if csv_path is not None:
            self.open_csv(csv_path)

    def open_csv(self, path) -> None:
        """Write the records from now on to the CSV file ``path`` (header now; rank root)."""
        self.csv_path = pathlib.Path(path)
        if self.is_root:
            self.csv_path.parent.mkdir(parents=True, exist_ok=True)
            with self.csv_path.open("w", newline="") as fh:
                csv.writer(fh).writerow(self.columns())

    def _log(self, rec):
        """Keep ``rec`` and append it to the CSV (rank root); returns it."""
        self.records.append(rec)
        if self.csv_path is not None and self.is_root:
            with self.csv_path.open("a", newline="") as fh:
                csv.writer(fh).writerow([_fmt(getattr(rec, c)) for c in self.columns()])
        return rec

    def history(self) -> dict:
        """The records as arrays: {column: ndarray}."""
        return {c: np.array([getattr(r, c) for r in self.records]) for c in self.columns()}

    def _records_state(self) -> dict:
        """The records as plain arrays ``rec.<column>`` (int columns stay int)."""
        types = {f.name: f.type for f in dataclasses.fields(self.RECORD)}
        return {f"rec.{c}": np.array([getattr(r, c) for r in self.records],
                                     np.int64 if types[c] in (int, "int") else np.float64)
                for c in self.columns()}

    def _set_records_state(self, d: dict) -> None:
        n = len(d[f"rec.{self.columns()[0]}"])
        # a column added later (Q_friction) reads as 0 from older checkpoints
        cols = {c: d[f"rec.{c}"].tolist() if f"rec.{c}" in d else [0.0] * n
                for c in self.columns()}
        self.records = [self.RECORD(**{c: cols[c][i] for c in cols}) for i in range(n)]
