r"""A built FE structure coupled to the DEM: the runtime object a runner drives.

Made by :meth:`gsi.case.structure.Structure.build` (the one structure set-up). It holds
the structure's problems (:class:`gsi.fem.elasticity.Elasticity`, :class:`gsi.fem.heat.Heat`),
its one contact interface (:class:`gsi.coupling.interface.SurfaceInterface`) and, after
:meth:`CoupledStructure.attach`, its one DEM wall and the couplings
(:class:`gsi.coupling.staggered.StaggeredCoupling` for forces and motion,
:class:`gsi.coupling.thermal.ThermalCoupling` for heat; with ``mode = "both"`` the thermal
coupling drives the mechanical one on the same wall).

A coupling interval of this structure (dt_FE = n_sub dt_DEM)::

    cs.begin()                 # wall accumulators reset, wall T and thermal strain from the FE
    sim.step(n)                # the runner: exactly n_sub DEM steps in total, in any pieces
    rec = cs.finish()          # loads and heat to the FE, FE step(s), wall moves

Every method is collective over the structure's communicator (the DEM ``sim`` lives on
rank ``root``, None elsewhere), except :meth:`summary`'s and the attributes' reads.
Several structures may share one DEM with different n_sub: each touches only its own
wall's accumulators, so their begin/finish may interleave.
"""
from __future__ import annotations

import math

import numpy as np
from mpi4py import MPI

from gsi.coupling.records import IntervalRecord

__all__ = ["CoupledStructure", "IntervalRecord"]


class CoupledStructure:
    """A built structure and its couplings (see the module docstring).

    Attributes
    ----------
    name : str
        Output prefix (``<name>.xdmf``, ``<name>.csv``, ``<name>_coupling.csv``,
        ``<name>_energy.csv``).
    mesh : gsi.meshes.StructureMesh
    material : gsi.fem.materials.StructuralMaterial
        Physical (unscaled) material.
    elasticity : gsi.fem.elasticity.Elasticity or None
        None for a thermal-only contact.
    heat : gsi.fem.heat.Heat or None
        Heat problem (capacity c / heat_scale), None without thermal coupling.
    interface : gsi.coupling.interface.SurfaceInterface
        The one contact interface (forces and heat).
    n_sub : int
        DEM steps per coupling interval.
    dt : float
        Coupling (FE) step n_sub dt_DEM (s).
    T_1 : float
        Estimated lowest period (s) (nan without elasticity).
    a0 : float
        Mass-proportional Rayleigh coefficient in use (1/s).
    mode : {"mechanical", "thermal", "both"}
    wall_material : str
        DEM material name of the wall.
    heat_scale : float
        Heat-capacity scale s (t_thermal = s t).
    mechanics, thermal : the couplings (after :meth:`attach`), or None
    wall : gsi.dem.MeshWall or None
        The DEM wall (rank ``root``, after :meth:`attach`).
    """

    def __init__(self, *, name, mesh, material, elasticity, heat, interface, n_sub, dt_dem,
                 T_1, a0, mode, wall_material, relaxation=1.0, T_ref=0.0, heat_scale=1.0,
                 root=0):
        self.name = name
        self.mesh = mesh
        self.material = material
        self.elasticity = elasticity
        self.heat = heat
        self.interface = interface
        self.comm = mesh.mesh.comm
        self.n_sub = int(n_sub)
        self.dt_dem = float(dt_dem)
        self.dt = self.n_sub * self.dt_dem
        self.T_1 = float(T_1)
        self.a0 = float(a0)
        self.mode = mode
        self.wall_material = wall_material
        self.relaxation = float(relaxation)
        self.T_ref = float(T_ref)
        self.heat_scale = float(heat_scale)
        self.root = root
        self.mechanics = None
        self.thermal = None
        self.wall = None
        self.output = None            # StructureOutput, after open_output()
        self._open = False

    # ------------------------------------------------------------------ coupling
    def attach(self, sim) -> None:
        """Make the DEM wall of the contact surface and the couplings (collective).

        ``sim`` (rank ``root``; None elsewhere) must hold the wall material
        (:meth:`gsi.case.structure.Structure.dem_wall_material`) and have dt = dt_DEM of
        the build; with heat, a particle conduction model.
        """
        from gsi.coupling.staggered import StaggeredCoupling
        from gsi.coupling.thermal import ThermalCoupling
        if self.mechanics is not None or self.thermal is not None:
            raise RuntimeError(f"structure {self.name!r}: attach() called twice")
        if self.mode in ("mechanical", "both"):
            self.mechanics = StaggeredCoupling(
                sim, self.elasticity, wall_material=self.wall_material, n_sub=self.n_sub,
                relaxation=self.relaxation, root=self.root, interface=self.interface)
        if self.mode in ("thermal", "both"):
            self.thermal = ThermalCoupling(
                sim, self.heat, mechanics=self.mechanics,
                interface=self.interface if self.mechanics is None else None,
                wall_material=self.wall_material, n_sub=self.n_sub, tag=self.interface.tags,
                T_ref=self.T_ref, time_scale=self.heat_scale, root=self.root)
        self.wall = (self.thermal or self.mechanics).wall
        if self.output is not None:
            self.output.open_csvs(self.mechanics, self.thermal)

    def _coupling(self):
        c = self.thermal or self.mechanics
        if c is None:
            raise RuntimeError(f"structure {self.name!r}: call attach(sim) first")
        return c

    def begin(self) -> None:
        """Start a coupling interval (collective): reset this wall's accumulators; with
        heat, the wall takes the FE temperature and the elasticity its thermal strain.
        The runner then advances the DEM exactly ``n_sub`` steps."""
        self._coupling().begin()

    def finish(self) -> IntervalRecord:
        """End the interval (collective): loads and heat to the FE, FE step(s), the wall
        takes the new positions, velocities and temperatures. Returns the records."""
        rec = self._coupling().finish()
        if self.thermal is not None:
            mech = self.mechanics.records[-1] if self.mechanics is not None else None
            return IntervalRecord(self.name, self.t, mech, rec)
        return IntervalRecord(self.name, self.t, rec, None)

    def load_heat(self) -> None:
        """First part of :meth:`finish` for a structure in an FE-FE thermal contact group
        (collective): forces, motion and the particles' heat in; the heat is stepped by the
        group (:class:`gsi.fem.contact_heat.ContactHeatSystem`), then :meth:`record`."""
        self.thermal.load_heat()

    def record(self) -> IntervalRecord:
        """Last part of :meth:`finish` after the group's heat step (collective)."""
        rec = self.thermal.record()
        mech = self.mechanics.records[-1] if self.mechanics is not None else None
        return IntervalRecord(self.name, self.t, mech, rec)

    @property
    def contact_group(self):
        """The FE-FE thermal contact group that steps this structure's heat, or None."""
        return None if self.heat is None else self.heat.contact_system

    def step(self, sim) -> IntervalRecord:
        """One interval on its own: begin, ``sim.step(n_sub)`` on root, finish."""
        self.begin()
        if self.comm.rank == self.root:
            sim.step(self.n_sub)
        return self.finish()

    @property
    def t(self) -> float:
        """Time at the end of the last finished interval (s)."""
        c = self.thermal or self.mechanics
        return 0.0 if c is None else c.t

    @property
    def n_intervals(self) -> int:
        """Finished coupling intervals."""
        c = self.thermal or self.mechanics
        return 0 if c is None else c.step_count

    # ------------------------------------------------------------------ monitors
    def max_displacement(self) -> float:
        """Largest nodal |u| of the structure (m); nan without elasticity (collective)."""
        return self.elasticity.max_displacement() if self.elasticity is not None else math.nan

    def max_von_mises(self) -> float:
        """Largest cell von Mises stress (Pa); nan without elasticity (collective)."""
        if self.elasticity is None:
            return math.nan
        from gsi.fem import compat
        vm = self.elasticity.von_mises()
        n = compat.num_cells_local(self.elasticity.mesh)
        local = float(vm.x.array[:n].max()) if n else 0.0
        return self.comm.allreduce(local, op=MPI.MAX)

    def mean_temperature(self) -> float:
        """Volume mean temperature (K); nan without heat (collective)."""
        return self.heat.mean_temperature() if self.heat is not None else math.nan

    def max_temperature(self) -> float:
        """Largest nodal temperature (K); nan without heat (collective)."""
        return self.heat.min_max()[1] if self.heat is not None else math.nan

    def interface_load(self) -> np.ndarray:
        """Sum of the nodal loads the FE holds from the particles (N), (3,) (collective);
        zeros for a thermal-only contact or before the first interval."""
        if self.mechanics is None:
            return np.zeros(3)
        return self.mechanics.held_load()

    def reaction(self, tag: str | None = None) -> np.ndarray:
        """Force of the supports on the structure (N), (3,) (collective)."""
        if self.elasticity is None:
            return np.full(3, math.nan)
        return self.elasticity.reaction(tag)

    def summary(self) -> dict:
        """Key numbers of the run so far (same on every rank; collective)."""
        out = dict(name=self.name, mode=self.mode, n_sub=self.n_sub, dt=self.dt,
                   T_1=self.T_1, t=self.t, intervals=self.n_intervals,
                   max_displacement=self.max_displacement(),
                   max_von_mises=self.max_von_mises())
        if self.elasticity is not None:
            out["n_dofs"] = self.elasticity.n_dofs
        if self.mechanics is not None and self.mechanics.records:
            h = self.mechanics.history()
            load = self.interface_load()
            out.update(load_x=float(load[0]), load_y=float(load[1]), load_z=float(load[2]),
                       load_z_min=float(h["load_z"].min()),
                       max_deflection=float(h["max_deflection"].max()),
                       balance_max=float(h["balance_rel"].max()), work=self.mechanics.work,
                       wall_dem=float(h["wall_dem"].sum()), wall_fe=float(h["wall_fe"].sum()),
                       wall_transfer=float(h["wall_transfer"].sum()))
        if self.heat is not None:
            out.update(T_mean=self.mean_temperature(), T_max=self.max_temperature(),
                       heat_scale=self.heat_scale, t_thermal=self.heat_scale * self.t)
        if self.thermal is not None and self.thermal.records:
            h = self.thermal.history()
            out.update(Q_particles=float(h["Q_particles"].sum()),
                       Q_radiation=float(h["Q_radiation"].sum()),
                       Q_structure=float(h["Q_structure"].sum()),
                       Q_boundary_loss=float(h["Q_boundary_loss"].sum()),
                       Q_contact=float(h["Q_contact"].sum()),
                       heat_balance_max=float(np.abs(h["balance_error"]).max()),
                       drift_max=float(np.abs(h["drift"]).max()))
        return out

    # ------------------------------------------------------------------ checkpoints
    def state(self) -> dict:
        """This rank's state as plain arrays (for checkpoints): the elasticity's
        (``el.*``: owned u, v, a, the previous load vector, t, n_steps; plus the nodal
        loads it holds and the temperature of its thermal strain) and the heat
        problem's (``heat.*``: owned T, the previous step's T, the nodal heat loads,
        t, n_steps), and the couplings' (``mech.*``, ``therm.*``: records, work, step
        counters, last loads, surface temperatures, energy baseline, open interval).
        Restore with :meth:`set_state` on the structure built from the same case and
        number of ranks."""
        d = {}
        if self.elasticity is not None:
            el = self.elasticity
            d.update({f"el.{k}": v for k, v in el.state().items()})
        if self.heat is not None:
            h = self.heat
            d.update({f"heat.{k}": v for k, v in h.state().items()})
        for prefix, c in (("mech", self.mechanics), ("therm", self.thermal)):
            if c is not None:
                d.update({f"{prefix}.{k}": v for k, v in c.state().items()})
        return d

    def set_state(self, d: dict) -> None:
        """Restore :meth:`state` (collective: the FE fields are scattered to the ghosts)."""

        def part(prefix):
            return {k[len(prefix) + 1:]: v for k, v in d.items() if k.startswith(prefix + ".")}
        if self.elasticity is not None:
            self.elasticity.set_state(part("el"))
        if self.heat is not None:
            self.heat.set_state(part("heat"))
        if self.mechanics is not None:
            self.mechanics.set_state(part("mech"))
        if self.thermal is not None:
            self.thermal.set_state(part("therm"))

    # ------------------------------------------------------------------ output
    def open_output(self, out_dir, *, xdmf: bool = True, resume: int | None = None) -> None:
        """Write under ``out_dir`` (collective; :class:`gsi.coupling.structure_output.
        StructureOutput`): ``<name>.xdmf`` (+ .h5) and ``<name>.csv`` at every
        :meth:`write_output`, and every interval's records to ``<name>_coupling.csv``
        (mechanical) and ``<name>_energy.csv`` (thermal). ``resume=n`` (after
        :meth:`set_state`) continues the files of an earlier run."""
        from gsi.coupling.structure_output import StructureOutput
        self.output = StructureOutput(self.name, out_dir, elasticity=self.elasticity,
                                      heat=self.heat, xdmf=xdmf, resume=resume)
        self.output.open_csvs(self.mechanics, self.thermal)

    @property
    def n_writes(self) -> int:
        """Field writes so far (0 without output)."""
        return 0 if self.output is None else self.output.n_writes

    def write_output(self, t: float) -> dict:
        """Append the fields at time ``t`` (s) and a row of ``<name>.csv`` (collective).
        Returns the row."""
        if self.output is None:
            raise RuntimeError(f"structure {self.name!r}: call open_output(out_dir) first")
        return self.output.write(t)

    def output_files(self) -> list:
        """Paths written so far under the output directory."""
        return [] if self.output is None else self.output.files(self.mechanics, self.thermal)

    def close(self) -> None:
        """Close the output files (collective)."""
        if self.output is not None:
            self.output.close()
