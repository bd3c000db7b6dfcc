"""Monitors: time series of a few numbers, written to ``<out>/monitors/<name>.csv``.

Each ``[[monitors]]`` table is one :class:`Monitor`; its ``kind`` says what it measures:

``wall``
    Force (N) of the particles on a wall (``target`` = a ``[[walls]]`` name or a
    ``[[structures]]`` name: its contact wall) and the torque (N m) about ``point``
    (default: the origin). A wall made of several planes (a box) sums them.
``discharge``
    Mass (kg) and number of the particles beyond a plane (``point``, ``normal`` pointing
    to the discharge side), e.g. under a hopper outlet; plus the particles lost from the
    domain so far.
``temperature``
    Heat-capacity weighted mean, minimum and maximum particle temperature (K) of a group
    (``group`` = a ``[[particles]]`` name) or of the particles inside a ``region``.
``wall_motion``
    A driven wall's (``target``, motion kind oscillation, servo or free) position along
    its direction (m) or angle about its axis (rad) since the start, its velocity (m/s
    or rad/s), the particles' load along the direction (N) or about the axis (N m), and
    the servo's target force (N; NaN for the other kinds).
``structure``
    Largest displacement (m) and von Mises stress (Pa), mean temperature (K) and the
    interface load (N) of a structure (``target``).
``particles``
    Count, particles lost, kinetic energy (J), contacts, and the top of the bed (m, along
    -gravity).
``mixing``
    Lacey's mixing index of species A (``group``) against all other particles, on a grid
    of ``cells`` sample cells over the box ``region``; cells with fewer than ``min_count``
    particles are left out (:func:`gsi.post.mixing.lacey_index`). 0: segregated, 1:
    randomly mixed. Also the number of cells kept and their mean count.
``energy``
    The energy book of the particles (:mod:`gsi.dem.energy`): kinetic, elastic (contact
    springs), gravitational and thermal energy, the energy particles lost from the domain
    carried out and the energy particles added (inserted) brought in, the work of moving walls on them, the heat from walls into them, the
    walls' share of the frictional heat, the heat that friction generated, and the
    book's drift since the first sample of the run (J, and relative to the heat generated
    + kinetic + elastic energy; a run resumed with ``--resume`` continues the book of the
    run it resumes). Without ``dem.frictional_heating`` the drift is the dissipated
    energy.

A monitor samples every ``interval`` seconds of simulated time (default: the output
interval); the runner makes sure a sample falls on each multiple of it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from gsi.case.regions import Region
from gsi.config.schema import one_of, param, positive
from gsi.errors import GsiInputError

__all__ = ["Monitor", "MONITOR_KINDS"]

MONITOR_KINDS = ("wall", "wall_motion", "discharge", "temperature", "structure", "particles",
                 "mixing", "energy")

_COLUMNS = {
    "wall": ["Fx_N", "Fy_N", "Fz_N", "Tx_Nm", "Ty_Nm", "Tz_Nm"],
    "wall_motion": ["position", "velocity", "load", "target_N"],
    "discharge": ["mass_kg", "count", "lost"],
    "temperature": ["T_mean_K", "T_min_K", "T_max_K", "count"],
    "structure": ["max_displacement_m", "max_von_mises_Pa", "T_mean_K", "load_x_N",
                  "load_y_N", "load_z_N"],
    "particles": ["count", "lost", "kinetic_energy_J", "contacts", "bed_top_m"],
    "mixing": ["lacey", "cells", "mean_count"],
    "energy": ["kinetic_J", "elastic_J", "gravity_J", "thermal_J", "lost_J", "added_J",
               "wall_work_J",
               "boundary_heat_J", "friction_to_walls_J", "heat_generated_J", "drift_J",
               "drift_rel"],
}


@dataclass(kw_only=True)
class Monitor:
    """A time series of one kind of measurement (see the module docstring)."""

    name: str = param(doc="name of the series (file monitors/<name>.csv)")
    kind: str = param(check=one_of(*MONITOR_KINDS), doc="what it measures")
    target: Optional[str] = param(None, doc="wall or structure name (wall, structure)")
    group: Optional[str] = param(None, doc="particle source name (temperature; mixing: "
                                 "species A)")
    region: Optional[Region] = param(None, doc="region of the particles (temperature); "
                                     "sampled box (mixing)")
    cells: Optional[tuple[int, ...]] = param(None, length=3,
                                             doc="sample cells along x, y, z (mixing)")
    min_count: int = param(4, check=positive(), doc="fewest particles of a kept cell (mixing)")
    point: tuple[float, ...] = param((0.0, 0.0, 0.0), unit="m", length=3,
                                     doc="torque reference point (wall); plane point (discharge)")
    normal: Optional[tuple[float, ...]] = param(None, unit="-", length=3,
                                                doc="discharge side of the plane (discharge)")
    interval: Optional[float] = param(None, unit="s", check=positive(),
                                      doc="sampling interval (default: output.interval)")

    def validate(self, path: str) -> None:
        need = {"wall": ("target",), "wall_motion": ("target",), "structure": ("target",), "discharge": ("normal",),
                "temperature": (), "particles": (), "energy": (),
                "mixing": ("group", "region", "cells")}[self.kind]
        for key in need:
            if getattr(self, key) is None:
                raise GsiInputError(f"{path}.{key}: missing; a '{self.kind}' monitor needs "
                                    f"{', '.join(need)}")
        uses = {"wall": ("target", "point"), "wall_motion": ("target",), "structure": ("target",),
                "discharge": ("point", "normal"), "temperature": ("group", "region"),
                "particles": (), "energy": (),
                "mixing": ("group", "region", "cells", "min_count")}[self.kind]
        for key in ("target", "group", "region", "cells", "normal"):
            if getattr(self, key) is not None and key not in uses:
                raise GsiInputError(f"{path}.{key}: a '{self.kind}' monitor does not use it "
                                    f"(it uses {', '.join(uses) or 'no options'}); remove it "
                                    f"or change {path}.kind")
        if self.kind == "temperature" and (self.group is None) == (self.region is None):
            raise GsiInputError(f"{path}: a 'temperature' monitor needs exactly one of group "
                                f"or region")
        if self.kind == "mixing":
            if self.region.kind != "box":
                raise GsiInputError(f"{path}.region.kind = {self.region.kind!r}: a 'mixing' "
                                    f"monitor samples a box; use kind = 'box'")
            if any(c < 1 for c in self.cells):
                raise GsiInputError(f"{path}.cells = {list(self.cells)}: must be three "
                                    f"integers >= 1")
        if self.kind == "discharge" and not any(self.normal):
            raise GsiInputError(f"{path}.normal = {list(self.normal)}: must be a nonzero vector")

    @property
    def columns(self) -> list[str]:
        """CSV column names after ``time_s``."""
        return list(_COLUMNS[self.kind])

    def check(self, path: str, *, walls: set, structures: set, groups: set,
              thermal: bool, driven: set = frozenset()) -> None:
        """Names that must exist in the case (before a run)."""
        if self.kind == "wall" and self.target not in walls | structures:
            raise GsiInputError(f"{path}.target = {self.target!r}: no wall or structure of that "
                                f"name; known: {', '.join(sorted(walls | structures)) or 'none'}")
        if self.kind == "wall_motion" and self.target not in driven:
            raise GsiInputError(f"{path}.target = {self.target!r}: no wall of that name with "
                                f"a motion of kind oscillation, servo or free; known: "
                                f"{', '.join(sorted(driven)) or 'none'}")
        if self.kind == "structure" and self.target not in structures:
            raise GsiInputError(f"{path}.target = {self.target!r}: no structure of that name; "
                                f"known: {', '.join(sorted(structures)) or 'none'}")
        if self.kind == "mixing" and self.group not in groups:
            raise GsiInputError(f"{path}.group = {self.group!r}: no [[particles]] of that "
                                f"name; known: {', '.join(sorted(groups)) or 'none'}")
        if self.kind == "temperature":
            if self.group is not None and self.group not in groups:
                raise GsiInputError(f"{path}.group = {self.group!r}: no [[particles]] of that "
                                    f"name; known: {', '.join(sorted(groups)) or 'none'}")
            if not thermal:
                raise GsiInputError(f"{path}.kind = 'temperature': needs dem.heat other than "
                                    f"'none'")

    # ------------------------------------------------------------------ sampling
    def sample(self, run) -> Optional[list[float]]:
        """The row of values at the runner's current time (collective for ``structure``;
        the DEM values exist on the DEM rank only, None elsewhere)."""
        if self.kind == "structure":
            st = run.structure(self.target)
            row = [st.max_displacement(), st.max_von_mises(), st.mean_temperature(),
                   *st.interface_load()]
            return row if run.is_root else None
        if not run.is_root:
            return None
        sim = run.sim
        if self.kind == "wall":
            p = np.asarray(self.point, float)
            F = np.zeros(3)
            T = np.zeros(3)
            for h in run.wall_handles(self.target):
                ref = h.point if hasattr(h, "point") else h.centre
                F += h.force
                T += h.torque + np.cross(ref - p, h.force)
            return [*F, *T]
        if self.kind == "wall_motion":
            h = run.wall_handles(self.target)[0]
            d = next((d for d in sim.drivers.items if d.walls[0] is h), None)
            if d is None:
                raise GsiInputError(f"monitors: {self.name}.target = {self.target!r}: the "
                                    "wall's motion is not oscillation, servo or free")
            return [d.position, d.velocity, d.load, d.target]
        if self.kind == "discharge":
            n = np.asarray(self.normal, float)
            n = n / np.linalg.norm(n)
            beyond = (sim.x - np.asarray(self.point, float)) @ n > 0.0
            return [float(sim.mass[beyond].sum()), int(beyond.sum()), int(sim.n_lost)]
        if self.kind == "temperature":
            if self.group is not None:
                ids = run.group_ids(self.group)
                rows = np.flatnonzero(np.isin(sim.ids, ids))
            else:
                rows = np.flatnonzero(self.region.contains(sim.x, sim.radius * 0.0))
            if len(rows) == 0:
                return [math.nan, math.nan, math.nan, 0]
            mcp = run.heat_capacity()[rows]
            T = sim.T[rows]
            return [float((mcp * T).sum() / mcp.sum()), float(T.min()), float(T.max()),
                    len(rows)]
        if self.kind == "energy":
            return self._energy_row(sim)
        if self.kind == "mixing":
            from gsi.post.mixing import lacey_index
            is_a = np.isin(sim.ids, run.group_ids(self.group))
            M, kept, mean = lacey_index(sim.x, is_a, self.region.lo, self.region.hi,
                                        self.cells, min_count=self.min_count)
            return [M, kept, mean]
        # particles
        g = np.asarray(run.case.dem.gravity, float)
        up = -g / np.linalg.norm(g) if np.any(g) else np.array([0.0, 0.0, 1.0])
        top = float((sim.x @ up + sim.radius).max()) if sim.n else math.nan
        return [int(sim.n), int(sim.n_lost), sim.kinetic_energy(), int(sim.contact_count()),
                top]

    def _energy_row(self, sim) -> list[float]:
        """The ``energy`` row; the book's reference is the run's first sample, kept in
        the simulation and its checkpoints (:meth:`gsi.dem.energy.EnergyAudit.of_run`)."""
        from gsi.dem.energy import EnergyAudit
        audit = getattr(self, "_audit", None)
        if audit is None or audit.sim is not sim:
            audit = self._audit = EnergyAudit.of_run(sim)
        p = audit.sample()
        return [p[k[:-2]] for k in _COLUMNS["energy"][:-1]] + [p["drift_rel"]]
