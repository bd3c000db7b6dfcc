r"""Thermal (and thermo-mechanical) staggered coupling of the DEM to an FE structure.

DESIGN.md "Coupling", "Heat in particles", "Thermo-elastic". One coupling step of size
dt_FE = n_sub dt_DEM:

1. The DEM wall (a :class:`gsi.dem.MeshWall` made of the triangles of the tagged contact
   surface, :class:`gsi.fem.surface.ContactSurface`) takes the FE temperature at the surface
   vertices (``wall.vertex_temperature``); the DEM interpolates it at each contact point
   with the barycentric weights, T_w = sum_k w_k T_k. (A P2 mechanical interface splits
   each triangle at its edge midpoints and weights heat by the P2 basis of the parent
   face; a midpoint takes the mean of its edge's end temperatures and hands half of its
   heat to each end, so the wall temperature is the P1 field of the FE triangle and the
   heat its P1-consistent nodal load: l_a(2 l_a - 1) + (4 l_a l_b + 4 l_c l_a)/2 = l_a.)
2. The DEM runs n_sub steps. Each particle-wall contact conducts
   Q = H (T_w - T_i) into the particle, with the DEM's conductance model and the wall
   material's conductivity (H = 4 k_i k_w/(k_i + k_w) sqrt(pi a^2) for ``area``, ...),
   while the particles conduct among themselves (particle-particle, same model).
   The DEM accumulates ``vertex_heat`` = sum over steps of -Q w_k dt_DEM (J).
3. The structure receives the nodal heat loads W_k = vertex_heat_k / dt_FE (W), held over
   the FE step: a Neumann flux whose integral over the step is exactly the heat the
   particles gave up; the heat problem steps from T_k to T_k+1.
4. Thermo-elastic structure (``mechanics``, a
   :class:`gsi.coupling.staggered.StaggeredCoupling` of the same DEM and surface): before
   its step the elasticity takes the FE temperature T_k for the thermal strain,
   sigma = C : (eps(u) - alpha (T - T_ref) I); its step runs the DEM sub-cycle of 2.,
   turns the particle forces into nodal loads, solves (stress = particle loads + thermal
   strain) and moves the wall to x0 + u (the thermal deformation moves the walls the DEM
   sees). The thermal strain of the solve at step k thus lags the heat solution by one
   coupling step, O(dt_FE) against thermal time scales of seconds to hours. (A hook in
   StaggeredCoupling.step between the load transfer and the solve would remove the lag.)

Energy record, per coupling step (``CouplingStep``; also ``energy.csv``):

* ``Q_particles`` heat leaving the particles into this wall over the step (J),
  ``Q_structure`` heat entering the structure through the nodal loads (J, summed over the
  owned dofs of all ranks), ``balance_error`` = Q_structure - Q_particles (round-off);
* ``Q_boundary_loss`` heat leaving the structure through its boundary over the step (J):
  convection/flux tags theta-weighted exactly as the theta-scheme applies them, plus the
  Dirichlet residual flow on fixed-temperature tags;
* ``E_particles`` = sum m c_p (T - T_ref), ``E_structure`` = int rho c (T - T_ref) dx (J);
* ``drift`` = E_particles + E_structure + (cumulative boundary loss) - (initial
  E_particles + E_structure) - (cumulative heat from DEM planes with a temperature) (J):
  zero to round-off while no particle leaves the domain or is inserted.

Parallel runs: the FE mesh is distributed; the DEM lives on rank ``root`` only (pass
``sim=None`` elsewhere). The gathered surface temperature/positions are on every rank;
loads are broadcast from ``root`` and each rank adds those at the vertices it owns.

Time scaling (documented choice; a simpler alternative to seed 003's long-time
extrapolation): a run (e.g. :mod:`gsi.drivers.thermal_silo`) may divide the heat
capacities of particles AND structure by the same factor s. All thermal time constants
shrink by s (conduction, contact, convection), so the scaled run at time t shows the
temperatures of the physical system at t_thermal = s t; heat flows (W) and temperatures
are physical, stored and exchanged energies are the physical ones divided by s. The
balance above holds exactly in the scaled run. The mechanics is not scaled.
"""
from __future__ import annotations

import csv
import dataclasses
import math
import pathlib

import numpy as np
from mpi4py import MPI

from gsi.errors import GsiInputError

__all__ = ["ThermalCoupling", "CouplingStep"]


@dataclasses.dataclass
class CouplingStep:
    """The energy record and key numbers of one coupling step (SI units, see module doc)."""

    step: int
    t: float                 # s, simulated time at the end of the step
    t_thermal: float         # s, time of the physical system (time_scale * t)
    Q_particles: float       # J, heat leaving the particles into the wall over the step
    Q_structure: float       # J, heat entering the structure through the nodal loads
    balance_error: float     # J, Q_structure - Q_particles
    heat_flow: float         # W, Q_structure / dt_FE: heat flow into the wall
    Q_boundary_loss: float   # J, heat leaving the structure through its boundary (convection)
    Q_planes: float          # J, heat from DEM planes with a temperature into the particles
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


CSV_COLUMNS = [f.name for f in dataclasses.fields(CouplingStep)]


class ThermalCoupling:
    """Staggered DEM <-> FE heat (and thermo-elastic) coupling through one contact surface.

    Parameters
    ----------
    sim : gsi.dem.Simulation or None
        The DEM (on rank ``root``; None on the other ranks). Its heat model must not be
        None.
    heat : gsi.fem.heat.Heat
        The structure's heat problem (P1 or P2); its time step is the coupling step dt_FE.
    mechanics : gsi.coupling.staggered.StaggeredCoupling, optional
        The mechanical coupling of the same DEM to the structure's elasticity (built first,
        same ``tag``). When given it owns the DEM wall and the DEM sub-cycle: each coupling
        step the FE temperature loads the thermal strain of its elasticity, its step runs
        the DEM, transfers the forces, solves and moves the wall; then the heat loads go to
        the heat problem and the heat steps. The thermal strain of the solve at step k
        uses T_k (the heat solution of the previous step): an O(dt_FE) lag, small against
        the thermal time scales (documented choice; see the module docstring).
        None: heat only, the wall (made here) does not move.
    wall_material : str
        DEM material name of the wall when ``mechanics`` is None (its k is the wall
        conductivity of the particle-wall conductance; give it the structure's k).
    n_sub : int
        DEM steps per coupling step when ``mechanics`` is None: heat.dt must equal
        n_sub sim.dt (with ``mechanics``: its n_sub and dt).
    tag : str
        Contact surface tag (default "contact").
    T_ref : float
        Reference temperature of the stored energies (K).
    time_scale : float
        Heat-capacity scaling factor s of the run (only reported: t_thermal = s t).
    root : int
        Rank that holds the DEM (with ``mechanics``: its root).
    csv_path : path, optional
        Write the per-step records there as CSV (rank ``root``).
    """

    def __init__(self, sim, heat, *, mechanics=None, wall_material: str | None = None,
                 n_sub: int | None = None, tag: str = "contact", T_ref: float = 0.0,
                 time_scale: float = 1.0, root: int = 0, csv_path=None):
        from gsi.fem.surface import ContactSurface
        self.comm = heat.comm
        self.mechanics = mechanics
        self.root = root = mechanics.root if mechanics is not None else root
        self.is_root = self.comm.rank == root
        self.sim = sim if self.is_root else None
        if self.is_root and sim is None:
            raise GsiInputError(f"coupling.sim = None on rank {root}: the DEM must live on the root rank")
        if self.is_root and sim.heat is None:
            raise GsiInputError("dem.heat = 'none': the thermal coupling needs a particle "
                                "conduction model ('area', 'radius' or 'constant')")
        if mechanics is not None:
            n_sub = mechanics.n_sub
        if n_sub is None or isinstance(n_sub, bool) or int(n_sub) != n_sub or n_sub < 1:
            raise GsiInputError(f"coupling.n_sub = {n_sub!r}: must be an integer >= 1")
        self.n_sub = int(n_sub)
        dt_dem = self.comm.bcast(sim.dt if self.is_root else None, root=root)
        self.dt = heat.dt
        if not math.isclose(self.dt, self.n_sub * dt_dem, rel_tol=1e-12):
            raise GsiInputError(f"structure.heat.dt = {self.dt:g}: must equal coupling.n_sub x "
                                f"dem dt = {self.n_sub} x {dt_dem:g} s")
        self.heat = heat
        self.elasticity = mechanics.elasticity if mechanics is not None else None
        self.T_ref = float(T_ref)
        self.time_scale = float(time_scale)
        self.surface = ContactSurface(heat=heat, tag=tag)
        self._T_surf = self.surface.temperature()     # collective: every rank
        self._prolong = None
        if mechanics is not None:
            itf = mechanics.interface
            if not np.array_equal(itf.surface.global_ids, self.surface.global_ids):
                raise GsiInputError(f"coupling.tag = {tag!r}: the mechanical coupling uses "
                                    "another contact surface")
            if itf.n_midpoints:
                self._prolong = itf.midpoint_edges
            self.wall = mechanics.wall
            if self.is_root:
                self.wall.vertex_temperature = self._wall_T(self._T_surf)
        else:
            self.wall = None
            if self.is_root:
                if wall_material not in sim.materials:
                    raise GsiInputError(f"coupling.wall_material = {wall_material!r}: not a "
                                        f"DEM material; known: {sorted(sim.materials)}")
                self.wall = sim.add_mesh_wall(self.surface.x0, self.surface.triangles,
                                              material=wall_material,
                                              vertex_temperature=self._T_surf)
        # boundary tags whose heat flow is part of the balance
        self._flux_tags = [n for n in heat.h if heat.h[n] > 0.0 or heat.q[n].value != 0.0
                           or n in heat._bc_dofs_by_tag]
        self._volume = None
        self.records: list[CouplingStep] = []
        self.step_count = 0
        self.t = 0.0
        self._cum_loss = 0.0
        self._cum_planes = 0.0
        self._E0 = None
        self.csv_path = pathlib.Path(csv_path) if csv_path is not None else None
        if self.csv_path is not None and self.is_root:
            self.csv_path.parent.mkdir(parents=True, exist_ok=True)
            with self.csv_path.open("w", newline="") as fh:
                csv.writer(fh).writerow(CSV_COLUMNS)

    # ------------------------------------------------------------------ state
    def _wall_T(self, T_surf):
        """Wall-vertex temperatures: the surface vertices', then (P2 walls) the edge
        midpoints' as the mean of their two ends (the P1 field on the refined wall)."""
        if self._prolong is None:
            return T_surf
        return np.concatenate([T_surf, 0.5 * T_surf[self._prolong].sum(axis=1)])

    def _vertex_heat(self, heat_nodes):
        """Heat on the wall nodes (J) -> heat on the surface vertices (J): a midpoint's share
        goes half to each end, the transpose of :meth:`_wall_T` (total kept exactly)."""
        if self._prolong is None:
            return heat_nodes
        nv = self.surface.n_vertices
        out = heat_nodes[:nv].copy()
        half = 0.5 * heat_nodes[nv:]
        np.add.at(out, self._prolong[:, 0], half)
        np.add.at(out, self._prolong[:, 1], half)
        return out

    def particle_energy(self) -> float:
        """sum m c_p (T - T_ref) over the particles (J), on every rank (collective)."""
        e = None
        if self.is_root:
            e = _particle_energy(self.sim, self.T_ref)[0]
        return self.comm.bcast(e, root=self.root)

    def structure_energy(self) -> float:
        """int rho c (T - T_ref) dx (J) (collective)."""
        if self._volume is None:
            from gsi.fem import compat
            self._volume = compat.assemble_scalar(
                compat.form(compat.constant(self.heat.mesh, 1.0)
                            * compat.measure("dx", self.heat.mesh)), self.comm)
        m = self.heat.material
        return self.heat.stored_heat() - m.rho * m.c * self.T_ref * self._volume

    def _boundary_inflow(self, tags) -> float:
        return sum(self.heat.heat_flow(n) for n in tags)

    # ------------------------------------------------------------------ stepping
    def step(self) -> CouplingStep:
        """One coupling step (collective): DEM sub-cycle with the wall at T_k, forces and
        motion (``mechanics``), heat loads to the FE, heat step to T_k+1."""
        heat, el, mech, root = self.heat, self.elasticity, self.mechanics, self.root
        if self._E0 is None:
            self._E0 = self.particle_energy() + self.structure_energy()
        W = info = None
        if self.is_root:
            sim, wall = self.sim, self.wall
            wall.vertex_temperature = self._wall_T(self._T_surf)
            for p in sim.planes:
                p.reset_accumulators()
        if mech is not None:
            el.set_temperature(heat.T)                  # thermal strain of this solve: T_k
            mech.step()                                 # DEM sub-cycle, loads, solve, wall
        else:
            if self.is_root:
                self.wall.reset_accumulators()
                self.sim.step(self.n_sub)
        if self.is_root:
            W = self._vertex_heat(wall.vertex_heat) / self.dt   # W into the structure
            E_p, T_mean, T_max = _particle_energy(sim, self.T_ref)
            info = dict(Q_particles=-wall.heat_to_particles,
                        Q_planes=sum(p.heat_to_particles for p in sim.planes
                                     if p.temperature is not None),
                        E_particles=E_p, T_pm=T_mean, T_px=T_max, n=int(sim.n),
                        nc=int(sim.contact_count()),
                        Fz=float(-wall.impulse_on_particles[2] / self.dt))
        info = self.comm.bcast(info, root=root)
        heat.clear_nodal_heat()
        self.surface.add_nodal_heat(W if W is not None else np.zeros(self.surface.n_vertices),
                                    root=root)
        theta_tags = [n for n in self._flux_tags if n not in heat._bc_dofs_by_tag]
        dir_tags = [n for n in self._flux_tags if n in heat._bc_dofs_by_tag]
        inflow_old = self._boundary_inflow(theta_tags) if theta_tags else 0.0
        heat.step()
        Q_structure = heat.nodal_heat() * self.dt
        inflow_new = self._boundary_inflow(theta_tags) if theta_tags else 0.0
        inflow = heat.theta * inflow_new + (1.0 - heat.theta) * inflow_old
        inflow += self._boundary_inflow(dir_tags) if dir_tags else 0.0
        Q_loss = -inflow * self.dt
        vm = disp = math.nan
        if el is not None:
            disp = el.max_displacement()
            vm = self.max_von_mises()
        self._T_surf = self.surface.temperature()
        self.step_count += 1
        self.t += self.dt
        self._cum_loss += Q_loss
        self._cum_planes += info["Q_planes"]
        E_s = self.structure_energy()
        E_p = info["E_particles"]
        drift = E_p + E_s + self._cum_loss - self._cum_planes - self._E0
        _, T_max = heat.min_max()
        m = heat.material
        rec = CouplingStep(
            step=self.step_count, t=self.t, t_thermal=self.time_scale * self.t,
            Q_particles=info["Q_particles"], Q_structure=Q_structure,
            balance_error=Q_structure - info["Q_particles"], heat_flow=Q_structure / self.dt,
            Q_boundary_loss=Q_loss, Q_planes=info["Q_planes"], E_particles=E_p,
            E_structure=E_s, drift=drift, T_wall_max=T_max,
            T_wall_mean=self.T_ref + E_s / (m.rho * m.c * self._volume),
            T_contact_max=float(self._T_surf.max()), T_particles_mean=info["T_pm"],
            T_particles_max=info["T_px"], max_von_mises=vm, max_displacement=disp,
            wall_force_z=info["Fz"], n_particles=info["n"], n_contacts=info["nc"])
        self.records.append(rec)
        if self.csv_path is not None and self.is_root:
            with self.csv_path.open("a", newline="") as fh:
                csv.writer(fh).writerow([_fmt(getattr(rec, c)) for c in CSV_COLUMNS])
        return rec

    def run(self, n_steps: int, *, callback=None, every: int = 1):
        """``n_steps`` coupling steps; ``callback(self, record)`` every ``every`` steps
        (on every rank)."""
        for k in range(int(n_steps)):
            rec = self.step()
            if callback is not None and (k + 1) % every == 0:
                callback(self, rec)
        return self.records

    # ------------------------------------------------------------------ results
    def max_von_mises(self) -> float:
        """Largest cell von Mises stress (Pa) over all ranks (needs elasticity)."""
        from gsi.fem import compat
        vm = self.elasticity.von_mises()
        ncell = compat.num_cells_local(self.heat.mesh)
        local = float(vm.x.array[:ncell].max()) if ncell else 0.0
        return self.comm.allreduce(local, op=MPI.MAX)

    def history(self) -> dict:
        """The records as arrays: {column: ndarray}."""
        return {c: np.array([getattr(r, c) for r in self.records]) for c in CSV_COLUMNS}


def _particle_energy(sim, T_ref):
    """(sum m c_p (T - T_ref) (J), m c_p-weighted mean T, max T) of the DEM particles."""
    if sim.n == 0:
        return 0.0, math.nan, math.nan
    mcp = 1.0 / sim._p("mcp_inv")
    T = sim.T
    return (float(np.sum(mcp * (T - T_ref))), float(np.sum(mcp * T) / mcp.sum()),
            float(T.max()))


def _fmt(v):
    return f"{v:.12g}" if isinstance(v, float) else str(v)
