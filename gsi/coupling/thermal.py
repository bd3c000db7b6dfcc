r"""Thermal (and thermo-mechanical) staggered coupling of the DEM to an FE structure.

docs/design.md, "Coupling", "Heat in particles", "Thermo-elastic". One coupling step of size
dt_FE = n_sub dt_DEM:

1. The DEM wall (a :class:`gsi.dem.MeshWall` made of the triangles of the contact
   surface, :class:`gsi.coupling.interface.SurfaceInterface` -- the same interface and
   wall as the mechanical coupling's) takes the FE temperature at the surface
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

Energy record, per coupling step (``ThermalRecord``; also ``energy.csv``):

* ``Q_particles`` heat leaving the particles into this wall over the step (J), conduction
  and (``dem.radiation``, :mod:`gsi.dem.radiation`) radiation; ``Q_radiation`` the
  radiated part of it (J); ``Q_friction`` the wall's share of the frictional heat
  (``dem.frictional_heating``, :mod:`gsi.dem.contact.dissipation`; J), which reaches the
  structure through the same nodal loads;
  ``Q_structure`` heat entering the structure through the nodal loads (J, summed over the
  owned dofs of all ranks), ``balance_error`` = Q_structure - Q_particles - Q_friction
  (round-off);
* ``Q_boundary_loss`` heat leaving the structure through its boundary over the step (J):
  convection/flux tags theta-weighted exactly as the theta-scheme applies them, plus the
  Dirichlet residual flow on fixed-temperature tags, plus the radiation of radiating tags
  (explicit, at T_n, as the step applies it);
* ``E_particles`` = sum m c_p (T - T_ref), ``E_structure`` = int rho c (T - T_ref) dx (J);
* ``Q_contact`` heat entering the structure over the step through its FE-FE thermal
  contacts with other structures (J; :mod:`gsi.fem.contact_heat`, 0 without);
* ``drift`` = E_particles + E_structure + (cumulative boundary loss) - (initial
  E_particles + E_structure) - (cumulative heat from DEM planes with a temperature)
  - (cumulative Q_contact) - (cumulative heat from the radiation enclosure)
  - (cumulative frictional heat made in the particles and this wall) (J):
  zero to round-off while no particle leaves the domain or is inserted, and while this
  is the only heated wall of the DEM (with two coupled structures on one DEM the
  particles' energy also changes by the other's heat; ``balance_error`` still holds
  per structure). The plane heat is the change of each plane's running total over the
  interval: the coupling never resets accumulators it does not own.

Parallel runs: the FE mesh is distributed; the DEM lives on rank ``root`` only (pass
``sim=None`` elsewhere). The gathered surface temperature/positions are on every rank;
loads are broadcast from ``root`` and each rank adds those at the vertices it owns.

Time scaling (documented choice; a simpler alternative to the long-time extrapolation of
DEM heat conduction by collision pairing): a run may divide the heat capacities of
particles AND structure by the same factor s (:func:`scale_heat_capacity` for the DEM
materials; ``gsi.case.structure.Structure.build(heat_scale=s)`` for the structure). All
thermal time constants shrink by s (conduction, contact, convection), so the scaled run
at time t shows the temperatures of the physical system at t_thermal = s t; heat flows
(W) and temperatures are physical, stored and exchanged energies are the physical ones
divided by s. The balance above holds exactly in the scaled run. The mechanics is not
scaled.

Split step: :meth:`ThermalCoupling.step` is :meth:`~ThermalCoupling.begin`,
``sim.step(n_sub)`` on ``root`` and :meth:`~ThermalCoupling.finish`, as for
:class:`gsi.coupling.staggered.StaggeredCoupling`. :meth:`~ThermalCoupling.finish` is
itself :meth:`~ThermalCoupling.load_heat` (loads in), the heat step and
:meth:`~ThermalCoupling.record`; structures joined by FE-FE thermal contacts
(:class:`gsi.fem.contact_heat.ContactHeatSystem`) take all their loads first, then step
together, then record.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
from mpi4py import MPI

from gsi.coupling.records import RecordLog, ThermalRecord
from gsi.errors import GsiInputError

__all__ = ["ThermalCoupling", "ThermalRecord", "scale_heat_capacity", "particle_heat_capacity",
           "load_nodal_heat", "BoundaryMeter"]


def scale_heat_capacity(materials: dict, s: float) -> dict:
    """DEM materials with every cp divided by the heat-capacity scale ``s`` (>= 1 speeds the
    thermal evolution up by s; see the module docstring). Returns a new dict."""
    if not (s > 0 and math.isfinite(s)):
        raise GsiInputError(f"heat_scale = {s!r}: must be a number > 0")
    return {name: dataclasses.replace(m, cp=m.cp / s) for name, m in materials.items()}


def particle_heat_capacity(sim) -> np.ndarray:
    """m c_p of the DEM particles (n,) (J/K)."""
    return np.asarray(sim.heat_capacity, float)


CSV_COLUMNS = [f.name for f in dataclasses.fields(ThermalRecord)]


class ThermalCoupling(RecordLog):
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
    interface : gsi.coupling.interface.SurfaceInterface, optional
        Without ``mechanics``: a ready interface of ``heat`` (default: built on ``tag``).
        With ``mechanics`` its interface is used (the heat problem is added to it).
    wall_material : str
        DEM material name of the wall when ``mechanics`` is None (its k is the wall
        conductivity of the particle-wall conductance; give it the structure's k).
    n_sub : int
        DEM steps per coupling step when ``mechanics`` is None: heat.dt must equal
        n_sub sim.dt (with ``mechanics``: its n_sub and dt).
    tag : str or sequence of str
        Contact surface tag(s) (default "contact").
    T_ref : float
        Reference temperature of the stored energies (K).
    time_scale : float
        Heat-capacity scaling factor s of the run (only reported: t_thermal = s t).
    root : int
        Rank that holds the DEM (with ``mechanics``: its root).
    csv_path : path, optional
        Write the per-step records there as CSV (rank ``root``).
    """

    RECORD = ThermalRecord

    def __init__(self, sim, heat, *, mechanics=None, interface=None,
                 wall_material: str | None = None, n_sub: int | None = None, tag="contact",
                 T_ref: float = 0.0, time_scale: float = 1.0, root: int = 0, csv_path=None):
        from gsi.coupling.interface import SurfaceInterface
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
        if mechanics is not None:
            itf = mechanics.interface
            tags = (tag,) if isinstance(tag, str) else tuple(tag)
            if interface is not None and interface is not itf:
                raise GsiInputError("coupling.interface: with mechanics, the mechanical "
                                    "coupling's interface is the one interface")
            if set(tags) != set(itf.tags):
                raise GsiInputError(f"coupling.tag = {tag!r}: the mechanical coupling uses "
                                    f"another contact surface {list(itf.tags)}")
            itf.add_heat(heat)
            self.interface = itf
            self._T_surf = itf.surface_temperature()     # collective: every rank
            self.wall = mechanics.wall
            if self.is_root:
                self.wall.vertex_temperature = itf.wall_temperature(self._T_surf)
        else:
            if interface is None:
                interface = SurfaceInterface(heat=heat, tag=tag)
            elif interface.heat is None:
                interface.add_heat(heat)
            elif interface.heat is not heat:
                raise GsiInputError("coupling.interface: built on another heat problem")
            self.interface = itf = interface
            self._T_surf = itf.surface_temperature()
            self.wall = None
            if self.is_root:
                self.wall = itf.make_wall(sim, material=wall_material,
                                          vertex_temperature=itf.wall_temperature(self._T_surf))
        self.step_count = 0
        self.t = 0.0
        self._cum_loss = 0.0
        self._cum_planes = 0.0
        self._cum_contact = self._cum_friction = 0.0
        self._pending = None
        self._E0 = None
        self._interval = None
        self._init_log(csv_path)


    @property
    def surface(self):
        """The gathered contact surface (:class:`gsi.fem.surface.ContactSurface`)."""
        return self.interface.surface

    # ------------------------------------------------------------------ state
    def surface_temperature(self) -> np.ndarray:
        """FE temperature at the contact-surface vertices at the end of the last interval
        (n_vertices,) (K), on every rank (no MPI call)."""
        return self._T_surf.copy()

    def wall_temperature(self) -> np.ndarray:
        """Temperature the DEM wall takes at the next :meth:`begin` (n_nodes,) (K): the
        surface vertices' and (P2 walls) the midpoints' means. On every rank, no MPI call."""
        return self.interface.wall_temperature(self._T_surf)

    def particle_energy(self) -> float:
        """sum m c_p (T - T_ref) over the particles (J), on every rank (collective)."""
        e = None
        if self.is_root:
            e = _particle_energy(self.sim, self.T_ref)[0]
        return self.comm.bcast(e, root=self.root)

    def structure_energy(self) -> float:
        """int rho c (T - T_ref) dx (J) (collective)."""
        m = self.heat.material
        return self.heat.stored_heat() - m.rho * m.c * self.T_ref * self.heat.volume()

    # ------------------------------------------------------------------ stepping
    def begin(self) -> None:
        """Start a coupling interval (collective): the wall takes the FE temperature T_k,
        the elasticity (``mechanics``) takes T_k for its thermal strain, this wall's
        accumulators are reset; the planes' heat totals are noted (not reset). The DEM
        then advances exactly ``n_sub`` steps."""
        if self._interval is not None:
            raise RuntimeError("ThermalCoupling.begin: the previous interval is not finished")
        if self._E0 is None:
            self._E0 = self.particle_energy() + self.structure_energy()
        planes0 = None
        if self.is_root:
            self.wall.vertex_temperature = self.wall_temperature()
            planes0 = [p.heat_to_particles for p in self.sim.planes] + _radiation_totals(
                self.sim, self.wall) + _friction_totals(self.sim, self.wall)
        if self.mechanics is not None:
            self.elasticity.set_temperature(self.heat.T)     # thermal strain of this solve: T_k
            self.mechanics.begin()
        elif self.is_root:
            self.wall.reset_accumulators()
            self._dem_step0 = self.sim.step_count
        self._interval = dict(planes0=planes0)

    def finish(self) -> ThermalRecord:
        """End the interval after the DEM's ``n_sub`` steps (collective): forces and motion
        (``mechanics``), heat loads to the FE, heat step to T_k+1. Returns the record."""
        self.load_heat()
        self.heat.step()
        return self.record()

    def load_heat(self) -> None:
        """First part of :meth:`finish` (collective): forces and motion (``mechanics``), the
        particles' heat to the FE as nodal loads; the heat problem is not stepped."""
        if self._interval is None:
            raise RuntimeError("ThermalCoupling.finish: call begin() first")
        planes0, self._interval = self._interval["planes0"], None
        heat, mech, root, itf = self.heat, self.mechanics, self.root, self.interface
        W = info = None
        if mech is not None:
            mech.finish()                               # loads, solve, wall
        if self.is_root:
            sim, wall = self.sim, self.wall
            W = itf.vertex_heat(wall.vertex_heat) / self.dt   # W into the structure
            E_p, T_mean, T_max = _particle_energy(sim, self.T_ref)
            rad_wall, rad_enc, fr_wall, fr_part = (a - b for a, b in zip(  # older: no friction
                _radiation_totals(sim, wall) + _friction_totals(sim, wall),
                (planes0[len(sim.planes):] + [0.0, 0.0])[:4]))
            info = dict(Q_particles=-wall.heat_to_particles, Q_radiation=-rad_wall,
                        Q_friction=fr_wall, Q_friction_made=fr_wall + fr_part,
                        Q_planes=rad_enc + sum(p.heat_to_particles - q0 for p, q0 in
                                               zip(sim.planes, planes0)
                                               if p.temperature is not None),
                        E_particles=E_p, T_pm=T_mean, T_px=T_max, n=int(sim.n),
                        nc=int(sim.contact_count()),
                        Fz=float(-wall.impulse_on_particles[2] / self.dt),
                        n_dem=(self.n_sub if mech is not None
                               else sim.step_count - self._dem_step0))
        info = self.comm.bcast(info, root=root)
        if info["n_dem"] != self.n_sub:
            raise RuntimeError(f"ThermalCoupling.finish: the DEM advanced {info['n_dem']} steps "
                               f"since begin(), the coupling interval is n_sub = {self.n_sub}")
        load_nodal_heat(heat, itf, W if W is not None else np.zeros(itf.n_vertices),
                        root=root)
        self._pending = dict(info=info, meter=BoundaryMeter(heat), n_steps=heat.n_steps)

    def record(self) -> ThermalRecord:
        """Last part of :meth:`finish`, after the heat step (collective): the energy record
        of the interval."""
        pending, self._pending = getattr(self, "_pending", None), None
        heat, el, itf = self.heat, self.elasticity, self.interface
        if pending is None or heat.n_steps != pending["n_steps"] + 1:
            raise RuntimeError("ThermalCoupling.record: needs load_heat() and one heat step")
        info = pending["info"]
        Q_structure = heat.nodal_heat() * self.dt
        Q_contact = self.comm.allreduce(float(heat.contact_heat.sum()), op=MPI.SUM) * self.dt
        Q_loss = -pending["meter"].heat_in()
        vm = disp = math.nan
        if el is not None:
            disp = el.max_displacement()
            vm = self.max_von_mises()
        self._T_surf = itf.surface_temperature()
        self.step_count += 1
        self.t += self.dt
        self._cum_loss += Q_loss
        self._cum_planes += info["Q_planes"]
        self._cum_contact += Q_contact
        self._cum_friction += info["Q_friction_made"]
        E_s = self.structure_energy()
        E_p = info["E_particles"]
        drift = E_p + E_s + self._cum_loss - self._cum_planes - self._cum_contact - self._E0
        drift -= self._cum_friction
        _, T_max = heat.min_max()
        m = heat.material
        rec = ThermalRecord(
            step=self.step_count, t=self.t, t_thermal=self.time_scale * self.t,
            Q_particles=info["Q_particles"], Q_radiation=info["Q_radiation"],
            Q_friction=info["Q_friction"], Q_structure=Q_structure, heat_flow=Q_structure / self.dt,
            balance_error=Q_structure - info["Q_particles"] - info["Q_friction"],
            Q_boundary_loss=Q_loss, Q_planes=info["Q_planes"], Q_contact=Q_contact,
            E_particles=E_p, E_structure=E_s, drift=drift, T_wall_max=T_max,
            T_wall_mean=self.T_ref + E_s / (m.rho * m.c * heat.volume()),
            T_contact_max=float(self._T_surf.max()), T_particles_mean=info["T_pm"],
            T_particles_max=info["T_px"], max_von_mises=vm, max_displacement=disp,
            wall_force_z=info["Fz"], n_particles=info["n"], n_contacts=info["nc"])
        return self._log(rec)

    def step(self) -> ThermalRecord:
        """One coupling step (collective): :meth:`begin`, the DEM sub-cycle of ``n_sub``
        steps on ``root`` with the wall at T_k, :meth:`finish`."""
        self.begin()
        if self.is_root:
            self.sim.step(self.n_sub)
        return self.finish()

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

    # ------------------------------------------------------------------ checkpoints
    def state(self) -> dict:
        """This rank's coupling state as plain arrays (for checkpoints): counters, time
        (s), cumulative boundary loss and plane heat (J), the energy baseline (J; nan
        before the first interval), the surface temperatures, the records
        (``rec.<column>``) and the open interval (the planes' heat totals at its start).
        The heat problem's state is saved by its owner (:class:`CoupledStructure`)."""
        d = self._records_state()
        iv = self._interval
        planes0 = iv["planes0"] if iv is not None and iv["planes0"] is not None else []
        d.update(counters=np.array([self.step_count, iv is not None,
                                    iv is not None and iv["planes0"] is not None,
                                    getattr(self, "_dem_step0", -1)], np.int64),
                 scalars=np.array([self.t, self._cum_loss, self._cum_planes,
                                   math.nan if self._E0 is None else self._E0,
                                   self._cum_contact, self._cum_friction], np.float64),
                 T_surf=np.array(self._T_surf), planes0=np.array(planes0, np.float64))
        return d

    def set_state(self, d: dict) -> None:
        """Restore :meth:`state` (no MPI call, nothing recomputed)."""
        self.step_count, is_open, has_planes, dem_step0 = (int(v) for v in d["counters"])
        self.t, self._cum_loss, self._cum_planes, E0, self._cum_contact, self._cum_friction = (
            float(v) for v in (list(d["scalars"]) + [0.0])[:6])    # older: no friction
        self._E0 = None if math.isnan(E0) else E0
        self._T_surf = np.array(d["T_surf"])
        self._set_records_state(d)
        self._interval = (dict(planes0=d["planes0"].tolist() if has_planes else None)
                          if is_open else None)
        if self.is_root and dem_step0 >= 0:
            self._dem_step0 = dem_step0


def load_nodal_heat(heat, interface, heat_flow, *, root: int | None = 0) -> None:
    """The heat loads of one coupling interval (collective): the structure's nodal heat
    loads become ``heat_flow`` (n_vertices,) (W, into the structure) at the contact-surface
    vertices (map wall-node heat with ``interface.vertex_heat`` first), held over the next
    heat step.  The live coupling and the long-time replay with an FE wall
    (:class:`gsi.extrapolation.FEWallReplay`) both load the FE through it."""
    heat.clear_nodal_heat()
    interface.add_nodal_heat(heat_flow, root=root)


class BoundaryMeter:
    """Heat entering a heat problem through its boundary over its next step (J), as the
    theta-scheme applies it: convection and flux tags theta-weighted between the start and
    the end of the step, the Dirichlet residual flow on fixed-temperature tags, and the
    radiation of radiating tags (explicit, at T_n).  Make it before the step (collective),
    call :meth:`heat_in` after it."""

    def __init__(self, heat):
        self.heat = heat
        flux_tags = heat.exchange_tags()
        fixed = set(heat.fixed_tags)
        self.theta_tags = [n for n in flux_tags if n not in fixed]
        self.dir_tags = [n for n in flux_tags if n in fixed]
        self.inflow_old = sum(heat.heat_flow(n) for n in self.theta_tags)

    def heat_in(self) -> float:
        """Heat into the body over the step just taken (J) (collective)."""
        heat = self.heat
        inflow = (heat.theta * sum(heat.heat_flow(n) for n in self.theta_tags)
                  + (1.0 - heat.theta) * self.inflow_old)
        inflow += sum(heat.heat_flow(n) for n in self.dir_tags)
        inflow += sum(heat.radiation_heat_flow(n) for n in heat.radiation)
        return inflow * heat.dt


def _radiation_totals(sim, wall):
    """[heat radiated from ``wall`` into the particles, heat from the radiation enclosure]
    since the start (J; zeros without radiation)."""
    rad = sim.radiation
    if rad is None:
        return [0.0, 0.0]
    return [rad.heat_from(wall), rad.enclosure_heat]


def _friction_totals(sim, wall):
    """[frictional heat into ``wall``, frictional heat into the particles] since the start
    (J; ``dem.frictional_heating``, :mod:`gsi.dem.contact.dissipation`)."""
    return [wall.friction_heat, float(sim.particles.heat_friction.sum())]


def _particle_energy(sim, T_ref):
    """(sum m c_p (T - T_ref) (J), m c_p-weighted mean T, max T) of the DEM particles."""
    if sim.n == 0:
        return 0.0, math.nan, math.nan
    mcp = particle_heat_capacity(sim)
    T = sim.T
    return (float(np.sum(mcp * (T - T_ref))), float(np.sum(mcp * T) / mcp.sum()),
            float(T.max()))

