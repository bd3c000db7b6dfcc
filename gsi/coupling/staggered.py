r"""Two-way staggered coupling of the DEM to an elastic FE structure (forces and motion).

docs/design.md, "Coupling". One coupling step of size dt_FE = n_sub dt_DEM, from t_k to t_k+1:

1. The DEM wall (:class:`gsi.coupling.interface.SurfaceInterface` as a mesh wall) has the
   FE positions x_k = x0 + u_k and velocities v_k; during the n_sub DEM steps its vertices
   move on with that velocity (x += v dt, the DEM's ``set_vertices`` contract), so the
   particles see the structure move.
2. The DEM accumulates ``vertex_impulse`` = sum over its steps of -F w_k dt_DEM. The load
   on the structure, held over the FE step, is the sub-cycle average
   P_k = vertex_impulse_k / dt_FE (N).
3. The FE steps once with these loads: dynamic (Newmark / generalized-alpha of
   :class:`gsi.fem.elasticity.Elasticity`, dt = dt_FE) or quasi-static (a static solve
   K u = P each coupling step; the wall velocity is then (u_k+1 - u_k)/dt_FE).
4. The wall takes the new positions x0 + u_k+1 and velocities v_k+1.

Balance record (:class:`MechanicalRecord`, in ``records`` and a CSV), every coupling step:

* ``load`` = sum over the FE's owned dofs, all ranks, of the nodal loads it actually
  holds (N) -- after the broadcast and the scatter to the owners;
* ``wall_force`` = minus the time-averaged force of the wall on the particles,
  -impulse_on_particles / dt_FE (N);
* ``balance_rel`` = |load - wall_force| / |wall_force| (0 without contact): round-off;
* ``work_step`` = sum over nodes of P_k . (u_k+1 - u_k) (J), the work of the interface
  loads on the structure over the step, and ``work`` its running sum.

Choice of n_sub (docs/design.md is silent; documented here): the structure's lowest period
T_1 is estimated by Rayleigh's quotient with the static deflection shape under a uniform
body force, omega_1^2 ~ u^T K u / u^T M u (an upper bound on omega_1 within a few
percent for a plate's fundamental mode; :func:`lowest_period`). The coupling step is the
largest multiple of dt_DEM not above T_1 / ``steps_per_period`` (default 20: the
fundamental vibration is resolved with a period error of (2 pi/20)^2/12 = 0.8 % by the
second-order integrators, the next modes with a few percent; 40 halves the sub-cycle and
doubles the FE cost: FE + transfer measured 18 % instead of 10 % of the coupled wall
time in the quick hopper demo, benchmarks/coupled_hopper.py):
n_sub = max(1, floor(T_1 / (steps_per_period dt_DEM))). A user-given n_sub overrides it.

Stability (measured; docs/design.md is silent): explicit staggering lags the interface force
by about half an FE step. When the particles resting on the structure outweigh it and
dt_FE is long compared with their contact period, a step-to-step (period 2 dt_FE)
oscillation grows: in the full hopper demo, once the heap (3 kg) outweighed the membrane
(2.6 kg), the loads turned into a growing sawtooth, the work on the membrane went
negative (-1.9 J) and particles were thrown off, with generalized-alpha rho_inf = 0.8.
Numerical damping of that frequency cures it (rho_inf = 0.3: loads settle to the heap's
weight, work +0.26 J); a shorter dt_FE (larger steps_per_period) also helps.
Quasi-static coupling has the analogous fixed-point limit (``relaxation``).

MPI: the FE mesh is distributed; the DEM lives on rank ``root`` only (``sim=None``
elsewhere). Positions and velocities are gathered on every rank, loads are broadcast
from ``root``; the results do not depend on the number of ranks beyond solver round-off.

Split step: :meth:`StaggeredCoupling.step` is :meth:`~StaggeredCoupling.begin` (reset this
wall's accumulators), ``sim.step(n_sub)`` on ``root``, :meth:`~StaggeredCoupling.finish`
(loads, FE step, wall update). A runner that drives several structures on one DEM calls
begin and finish itself and advances the DEM exactly ``n_sub`` steps in between, in as
many ``sim.step`` calls as it likes; the other walls' begin/finish may come in between,
since each touches only its own wall's accumulators.
"""
from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
from mpi4py import MPI

from gsi.coupling.records import MechanicalRecord, RecordLog
from gsi.errors import GsiInputError

__all__ = ["StaggeredCoupling", "MechanicalRecord", "lowest_period", "choose_n_sub"]


def lowest_period(static, *, direction=(0.0, 0.0, -1.0)) -> float:
    """Estimate of the structure's lowest natural period T_1 (s), Rayleigh's quotient.

    Parameters
    ----------
    static : gsi.fem.elasticity.Elasticity
        A *static* problem on the structure with its supports already clamped. Its
        gravity is set to ``direction`` (1 m/s^2) for the solve and reset to zero, and
        its displacement is reset to zero afterwards. Collective.
    direction : (3,) float
        Direction of the uniform body force whose static deflection is the trial shape.

    Returns
    -------
    float
        T_1 = 2 pi / omega_1, omega_1^2 = u^T K u / u^T M u (s).
    """
    import ufl
    from gsi.fem import compat
    if static.scheme != "static":
        raise GsiInputError(f"lowest_period: scheme = {static.scheme!r}: pass a static problem")
    g = np.asarray(direction, float)
    static.set_gravity(g / np.linalg.norm(g))
    static.solve()
    uKu = 2.0 * static.energies()["strain"]
    rho = static.material.rho
    uMu = compat.assemble_scalar(
        compat.form(rho * ufl.inner(static.u, static.u) * compat.measure("dx", static.mesh)),
        static.comm)
    static.set_gravity((0.0, 0.0, 0.0))
    static.u.x.array[:] = 0.0
    if not (uKu > 0 and uMu > 0):
        raise GsiInputError("structure: zero static deflection; check the supports and material")
    return 2.0 * math.pi / math.sqrt(uKu / uMu)


def choose_n_sub(dt_dem: float, T_1: float, *, steps_per_period: float = 20.0) -> int:
    """DEM steps per coupling step: max(1, floor(T_1 / (steps_per_period dt_DEM)))."""
    if not steps_per_period > 0:
        raise GsiInputError(f"coupling.steps_per_period = {steps_per_period}: must be > 0")
    return max(1, int(math.floor(T_1 / (steps_per_period * dt_dem) * (1 + 1e-12))))


CSV_COLUMNS = [f.name for f in dataclasses.fields(MechanicalRecord)]


class StaggeredCoupling(RecordLog):
    """Staggered DEM <-> elastic structure coupling through one contact surface.

    Parameters
    ----------
    sim : gsi.dem.Simulation or None
        The DEM on rank ``root`` (None on the other ranks). It gets one new mesh wall
        (``self.wall``) made of the interface triangles.
    elasticity : gsi.fem.elasticity.Elasticity
        The structure, supports set; "static" (quasi-static coupling) or dynamic with
        ``dt = n_sub * sim.dt``.
    wall_material : str
        DEM material of the wall (its E, nu, e, mu enter the particle-wall contact law).
    n_sub : int
        DEM steps per coupling step (see :func:`choose_n_sub`).
    tag : str or sequence of str
        Contact surface tag(s) (default "contact"; several make one surface).
    relaxation : float
        Quasi-static only: u_k+1 = (1 - r) u_k + r K^-1 P_k with 0 < r <= 1 (default 1).
        The staggered fixed point diverges when the contact stiffness of the particles
        exceeds the structure's stiffness (amplification 1 - r (1 + k_contact/k_structure));
        r < 1 restores convergence. A bed of soft spheres on a rubber plate needed
        r = 0.03 (r = 0.1 still chatters). Dynamic coupling does not need it.
    root : int
        Rank of the DEM.
    csv_path : path, optional
        Per-step records as CSV (written by rank ``root``).
    interface : gsi.coupling.interface.SurfaceInterface, optional
        A ready interface of ``elasticity`` (shared with a thermal coupling); default:
        built here on ``tag``.

    Attributes
    ----------
    interface : gsi.coupling.interface.SurfaceInterface
        Interface nodes (P1 vertices, or P2 vertices + edge midpoints) and wall triangles.
    wall : gsi.dem.MeshWall or None
        The coupled wall in the DEM (rank ``root`` only).
    dt : float
        Coupling (FE) step n_sub dt_DEM (s).
    records : list of MechanicalRecord
        One per coupling step; :meth:`history` gives them as arrays.
    last_loads : ndarray (n_nodes, 3)
        Nodal loads of the last step (N), on every rank.
    work : float
        Cumulative work of the interface loads on the structure (J).

    Notes
    -----
    A step in which no particle touched the wall while the structure is exactly at rest
    and unloaded (u = v = a = 0, no load, no prescribed displacement) skips the FE solve:
    the linear structure stays at rest exactly (filling phases cost no FE time).
    """

    RECORD = MechanicalRecord

    def __init__(self, sim, elasticity, *, wall_material: str, n_sub: int,
                 tag="contact", relaxation: float = 1.0, root: int = 0,
                 csv_path=None, interface=None):
        from gsi.coupling.interface import SurfaceInterface
        self.comm = elasticity.comm
        self.root = root
        self.is_root = self.comm.rank == root
        if self.is_root and sim is None:
            raise GsiInputError(f"coupling: sim = None on rank {root}: the DEM must live on the root rank")
        self.sim = sim if self.is_root else None
        if isinstance(n_sub, bool) or int(n_sub) != n_sub or n_sub < 1:
            raise GsiInputError(f"coupling.n_sub = {n_sub!r}: must be an integer >= 1")
        self.n_sub = int(n_sub)
        dt_dem = self.comm.bcast(sim.dt if self.is_root else None, root=root)
        self.dt = self.n_sub * dt_dem
        self.elasticity = el = elasticity
        self.static = el.scheme == "static"
        if not 0.0 < relaxation <= 1.0:
            raise GsiInputError(f"coupling.relaxation = {relaxation!r}: must be in (0, 1]")
        self.relaxation = float(relaxation)
        if not self.static and not math.isclose(el.dt, self.dt, rel_tol=1e-12):
            raise GsiInputError(f"structure.dt = {el.dt:g}: must equal coupling.n_sub x dem dt "
                                f"= {self.n_sub} x {dt_dem:g} = {self.dt:g} s")
        if interface is None:
            interface = SurfaceInterface(el, tag=tag)
        elif interface.elasticity is not el:
            raise GsiInputError("coupling.interface: built on another elasticity problem")
        self.interface = itf = interface
        self.wall = itf.make_wall(sim, material=wall_material) if self.is_root else None
        self._u = itf.displacement()
        self._sync_wall(self._u, itf.velocity())
        self.step_count = 0
        self.t = 0.0
        self.work = 0.0
        self.last_loads = np.zeros((itf.n_nodes, 3))
        self._t_begin = None
        self._init_log(csv_path)


    def _sync_wall(self, u, v) -> None:
        if self.is_root:
            self.wall.set_vertices(self.interface.x0 + u, v)

    def held_load(self) -> np.ndarray:
        """Sum of the nodal loads the FE holds (N), (3,), over all ranks (collective)."""
        return self.comm.allreduce(self.elasticity.nodal.values.reshape(-1, 3).sum(axis=0),
                                   op=MPI.SUM)

    # ------------------------------------------------------------------ stepping
    def begin(self) -> None:
        """Start a coupling interval (collective; no MPI call): reset this wall's
        accumulators on ``root``. The DEM then advances exactly ``n_sub`` steps."""
        if self._t_begin is not None:
            raise RuntimeError("StaggeredCoupling.begin: the previous interval is not finished")
        if self.is_root:
            self.wall.reset_accumulators()
            self._dem_step0 = self.sim.step_count
        self._t_begin = time.perf_counter()

    def finish(self) -> MechanicalRecord:
        """End the interval after the DEM's ``n_sub`` steps (collective): sub-cycle-averaged
        loads to the FE, FE step, wall update. Returns the interval's record."""
        if self._t_begin is None:
            raise RuntimeError("StaggeredCoupling.finish: call begin() first")
        el, itf, root = self.elasticity, self.interface, self.root
        t0, self._t_begin = self._t_begin, None
        P = info = None
        if self.is_root:
            sim, wall = self.sim, self.wall
            P = wall.vertex_impulse / self.dt
            info = (-wall.impulse_on_particles / self.dt, int(sim.n),
                    int(np.count_nonzero(np.abs(wall.triangle_force).sum(axis=1))),
                    not P.any(), sim.step_count - self._dem_step0)
        t1 = time.perf_counter()
        *info, n_dem = self.comm.bcast(info, root=root)
        if n_dem != self.n_sub:
            raise RuntimeError(f"StaggeredCoupling.finish: the DEM advanced {n_dem} steps "
                               f"since begin(), the coupling interval is n_sub = {self.n_sub}")
        el.clear_nodal_loads()
        P = self.last_loads = itf.add_nodal_loads(P, root=root)
        load = self.held_load()
        t2 = time.perf_counter()
        wall_force, n_particles, n_contacts, no_contact = info
        if no_contact and self._at_rest():
            # exact shortcut: a linear structure at rest without any load stays at rest
            el.advance_time(self.dt)
            return self._record(load, wall_force, 0.0, self._u, n_particles, n_contacts,
                                t1 - t0, time.perf_counter() - t2, t2 - t1)
        if self.static:
            u_old = el.u.x.array.copy()
            el.solve()
            if self.relaxation < 1.0:
                el.u.x.array[:] = (1.0 - self.relaxation) * u_old + self.relaxation * el.u.x.array
        else:
            el.step()
        t3 = time.perf_counter()
        u = itf.displacement()
        v = (u - self._u) / self.dt if self.static else itf.velocity()
        work_step = float(np.sum(P * (u - self._u)))
        self._u = u
        self._sync_wall(u, v)
        return self._record(load, wall_force, work_step, u, n_particles, n_contacts,
                            t1 - t0, t3 - t2, (t2 - t1) + (time.perf_counter() - t3))

    def step(self) -> MechanicalRecord:
        """One coupling step (collective): :meth:`begin`, the DEM sub-cycle of ``n_sub``
        steps on ``root``, :meth:`finish`."""
        self.begin()
        if self.is_root:
            self.sim.step(self.n_sub)
        return self.finish()

    def _at_rest(self) -> bool:
        """True if u = v = a = 0, no prescribed displacement and no load (collective)."""
        el = self.elasticity
        if self.step_count == 0 or el.has_prescribed_motion():
            return False     # the first step always runs (sets up the solver)
        loaded = bool(np.any(el.load_vector().array))     # collective: on every rank
        busy = loaded or any(np.any(f.x.array) for f in (el.u, el.v, el.a))
        return not self.comm.allreduce(busy, op=MPI.LOR)

    def _record(self, load, wall_force, work_step, u, n_particles, n_contacts, t_dem, t_fe,
                t_transfer) -> MechanicalRecord:
        self.work += work_step
        self.step_count += 1
        self.t += self.dt
        ref = float(np.linalg.norm(wall_force))
        bal = float(np.linalg.norm(load - wall_force)) / ref if ref > 0 else \
            float(np.linalg.norm(load))
        umag = np.sqrt((u ** 2).sum(axis=1))
        rec = MechanicalRecord(
            step=self.step_count, t=self.t, load_x=load[0], load_y=load[1], load_z=load[2],
            wall_force_x=wall_force[0], wall_force_y=wall_force[1],
            wall_force_z=wall_force[2], balance_rel=bal, work_step=work_step,
            work=self.work, max_deflection=float(umag.max()), min_uz=float(u[:, 2].min()),
            n_particles=n_particles, n_loaded_triangles=n_contacts,
            wall_dem=t_dem, wall_fe=t_fe, wall_transfer=t_transfer)
        return self._log(rec)

    def run(self, n_steps: int, *, callback=None):
        """``n_steps`` coupling steps; ``callback(self, record)`` after each (all ranks)."""
        for _ in range(int(n_steps)):
            rec = self.step()
            if callback is not None:
                callback(self, rec)
        return self.records

    # ------------------------------------------------------------------ checkpoints
    def state(self) -> dict:
        """This rank's coupling state as plain arrays (for checkpoints): counters, time
        (s), work (J), the last loads (N), the wall displacement it holds, the records
        (``rec.<column>``) and whether an interval is open (with its DEM start step).
        The elasticity's state is saved by its owner (:class:`CoupledStructure`)."""
        d = self._records_state()
        d.update(counters=np.array([self.step_count, self._t_begin is not None,
                                    getattr(self, "_dem_step0", -1)], np.int64),
                 scalars=np.array([self.t, self.work], np.float64),
                 last_loads=self.last_loads.copy(), u=np.array(self._u))
        return d

    def set_state(self, d: dict) -> None:
        """Restore :meth:`state` (no MPI call, nothing recomputed)."""
        self.step_count, is_open, dem_step0 = (int(v) for v in d["counters"])
        self.t, self.work = (float(v) for v in d["scalars"])
        self.last_loads = np.array(d["last_loads"])
        self._u = np.array(d["u"])
        self._set_records_state(d)
        self._t_begin = time.perf_counter() if is_open else None
        if self.is_root and dem_step0 >= 0:
            self._dem_step0 = dem_step0


