"""The energy book of a DEM run (docs/design.md, "Energy audit").

    E_book = E_kin + E_el + E_grav + E_th + E_lost - E_added - W_walls - Q_walls
             + Q_friction,walls

is constant:

- ``kinetic``: sum 1/2 m v^2 + 1/2 I omega^2 (J);
- ``elastic``: the contact springs -- the normal overlap, Hertz 8/15 E* sqrt(R*)
  delta^(5/2) or linear 1/2 k_n delta^2, and the tangential spring 1/2 k_t |xi|^2 with
  the k_t of the current overlap (J);
- ``gravity``: -sum m g . x (J);
- ``thermal``: sum m c_p T of the particles (J);
- ``lost``: the energy the particles removed so far carried out of the book
  (:func:`particle_energy`: kinetic, elastic, gravitational and thermal, J; accumulated
  in ``sim.lost_energy`` by :meth:`gsi.dem.Simulation.remove_particles`);
- ``added``: the energy the particles added so far brought in (an inserter's stream, a
  fill; kinetic, gravitational and thermal at their addition, J, ``sim.added_energy``,
  booked by :meth:`gsi.dem.Simulation.add_particles`; particles added before an audit
  starts cancel out of its drift).  Particles added overlapping others bring elastic
  energy too, which the book does not see (an inserter places them apart);
- ``wall_work``: work of the planes and mesh walls on the particles, sum F . v_wall dt
  (J, accumulated by the engine);
- ``boundary_heat``: heat from walls with a temperature (conduction, and radiation from
  walls and the enclosure) into the particles (J);
- ``friction_to_walls``: the walls' share of the frictional heat (J), which leaves the
  particles' book (a thermal structure receives it through its nodal heat loads: the
  FE's own record, :class:`gsi.coupling.records.ThermalRecord`, books its energy).

Without frictional heating the energy that damping, sliding and rolling resistance
dissipate leaves the book: the drift is then that energy.  With it on
(``dem.frictional_heating``), the drift measures what the bookkeeping misses:

- time integration: velocity Verlet conserves a shadow energy, so the mechanical
  energy fluctuates by O(dt^2) around it (the elastic energy of a contact is read at
  x_n, the kinetic at the full-step velocity v_n); the frictional heat is booked to
  second order (:func:`gsi.dem.integrate.integrate_rows`).  Both fall with dt, as dt^2
  where the forces are smooth (a force jump, a contact's first damped step or the
  rolling torque's stop, is first order);
- the incremental tangential spring is not a potential (with Hertz, k_t = 8 G* sqrt(R*
  delta) changes with the overlap while the spring xi stays; the spring is rotated into
  the new tangent plane and truncated at the Coulomb cap; a contact can end with a
  loaded spring): frictional heating books each of these energy changes as heat, per
  contact and step, and a spring's energy at its contact's end -- pair and plane
  contacts (:mod:`gsi.dem.contact.dissipation`, :mod:`gsi.dem.spring_heat`), so they
  leave no drift -- except a mesh-triangle contact's spring at its end, which leaves the
  book (docs/design.md, "Energy audit": its booking was taken out for its cost);
- a particle lost while it touches another body: its energy is booked at the end of
  the step it left in as if only gravity acted on it in that step (exact for a particle
  in free flight), while its partners miss that step's contact force (first order).

A run resumed from a checkpoint continues the same book: the baseline of the run's
audit (:meth:`EnergyAudit.of_run`, ``sim.energy_book0``), ``sim.lost_energy``,
``sim.added_energy`` and the walls' accumulators are in the checkpoint
(:mod:`gsi.dem.checkpoint_state`).

Energies are in J; :func:`energy_parts` returns them as a dict.
"""
import math

import numpy as np

from gsi.jit import njit
from gsi.dem.contact.model import K_T_OVER_K_N, M_NORMAL, NORMAL
from gsi.dem.materials import P_E, P_G, P_KN

_HERTZ = list(NORMAL).index("hertz")


@njit
def _spring_energy(hertz, delta, R_eff, xx, xy, xz, tab, row):
    """Normal and tangential elastic energy (J) of one contact of overlap ``delta`` (m)."""
    xi2 = xx * xx + xy * xy + xz * xz
    if hertz:
        s = math.sqrt(R_eff * delta)
        return (8.0 / 15.0 * tab[row, P_E] * s * delta * delta,
                0.5 * 8.0 * tab[row, P_G] * s * xi2)
    k_n = tab[row, P_KN]
    return 0.5 * k_n * delta * delta, 0.5 * K_T_OVER_K_N * k_n * xi2


#: the parts of ``sim.lost_energy`` and ``sim.added_energy`` (J): what the removed (added)
#: particles carried
LOST_PARTS = ("kinetic", "elastic", "gravity", "thermal", "heat_friction")


def new_flows():
    """``(lost_energy, added_energy, energy_book0)`` of a new simulation: nothing removed
    or added yet (by :data:`LOST_PARTS`, J), no audit of the run started."""
    return np.zeros(len(LOST_PARTS)), np.zeros(len(LOST_PARTS)), None


@njit
def contact_elastic_energy(P, pairs, wc, table, hertz, sel):
    """(normal, tangential) elastic energy (J) of the sphere-pair contacts of the last
    step (``pairs.active``) with at least one particle where ``sel`` (n,) is nonzero."""
    nt = table.shape[0]
    tab = table.reshape((nt * nt, table.shape[2]))
    En = 0.0
    Et = 0.0
    x = P.x
    for i in range(x.shape[0]):
        ri = P.radius[i]
        row_i = P.type[i] * nt
        for k in range(pairs.start[i], pairs.start[i + 1]):
            if not pairs.active[k]:
                continue
            j = pairs.j[k]
            if sel[i] == 0 and sel[j] == 0:
                continue
            rj = P.radius[j]
            d2 = 0.0
            for d in range(3):
                d2 += (x[j, d] - x[i, d]) ** 2
            delta = ri + rj - math.sqrt(d2)
            if delta <= 0.0:
                continue
            h = pairs.hist[k]
            a, b = _spring_energy(hertz, delta, ri * rj / (ri + rj), h[0], h[1], h[2], tab,
                                  row_i + P.type[j])
            En += a
            Et += b
    return En, Et


@njit
def wall_elastic_energy(P, pairs, pl, M, wc, table, hertz, sel):
    """(normal, tangential) elastic energy (J) of the plane and triangle contacts of the
    last step of the particles where ``sel`` (n,) is nonzero (``wc.plane_mask``,
    ``wc.count`` slots; ``P`` and the wall geometry as the engine left them)."""
    nt = table.shape[0]
    tab = table.reshape((nt * nt, table.shape[2]))
    npl = pl.point.shape[0]
    En = 0.0
    Et = 0.0
    x = P.x
    for i in range(x.shape[0]):
        if sel[i] == 0:
            continue
        ri = P.radius[i]
        row_i = P.type[i] * nt
        mask = wc.plane_mask[i]
        for p in range(npl):
            if not (mask >> p) & 1:
                continue
            dist = 0.0
            for d in range(3):
                dist += (x[i, d] - pl.point[p, d]) * pl.normal[p, d]
            delta = ri - dist
            if delta <= 0.0:
                continue
            h = wc.plane_hist[i, p]
            a, b = _spring_energy(hertz, delta, ri, h[0], h[1], h[2], tab, row_i + pl.type[p])
            En += a
            Et += b
        for s in range(wc.count[i]):
            d2 = 0.0
            for d in range(3):
                d2 += (wc.point[i, s, d] - x[i, d]) ** 2
            delta = ri - math.sqrt(d2)
            if delta <= 0.0:
                continue
            h = pairs.tri_hist[wc.cand[i, s]]
            wl = M.tri_wall[wc.tri[i, s]]
            a, b = _spring_energy(hertz, delta, ri, h[0], h[1], h[2], tab,
                                  row_i + M.wall_type[wl])
            En += a
            Et += b
    return En, Et


def _elastic(sim, sel):
    """(normal, tangential) elastic energy (J) of the contacts touching the particles
    where ``sel`` is nonzero (0 while the lists are not those of the current rows: before
    the first build, or after particles were added or removed, until the next step)."""
    if not (sim.flags.built and np.array_equal(sim.ids_at_build, sim.ids)):
        return 0.0, 0.0
    P = sim.particles
    hertz = int(sim.engine.model[M_NORMAL]) == _HERTZ
    sel = np.ascontiguousarray(sel, np.uint8)
    a = contact_elastic_energy(P, sim.pairs, sim.wall_contacts, sim.table, hertz, sel)
    b = wall_elastic_energy(P, sim.pairs, sim.plane_state, sim.mesh_state, sim.wall_contacts,
                            sim.table, hertz, sel)
    return a[0] + b[0], a[1] + b[1]


def particle_energy(sim, mask, *, mid_step=False):
    """The energy (J) of the particles where ``mask`` is true, by :data:`LOST_PARTS`
    (the last, the frictional heat they hold, is part of their thermal energy): what
    they take out of the book when removed.  ``mid_step`` (particles that left the
    domain, :meth:`gsi.dem.Simulation.remove_particles` from the step loop): they have
    drifted to x_(n+1) with v_(n+1/2), and their forces are gravity alone (cleared for
    the step); their velocities are completed by the step's second half kick, v_(n+1) =
    v_(n+1/2) + dt/2 F/m (omega likewise), so a particle in free flight takes exactly the
    energy it had in the book at step n (velocity Verlet conserves it under a constant
    force).  Otherwise (between steps) the state is taken as it is.  The elastic energy
    is that of every contact of the last step with a removed particle."""
    mask = np.asarray(mask, bool)
    P = sim.particles
    v, w = P.v[mask], P.omega[mask]
    m, inertia = P.mass[mask], P.inertia[mask]
    if mid_step:
        free = P.fixed[mask] == 0
        h = 0.5 * sim.dt
        v = v + np.where(free[:, None], (h / m)[:, None] * P.force[mask], 0.0)
        w = w + np.where(free[:, None], (h / inertia)[:, None] * P.torque[mask], 0.0)
    kin = 0.5 * float(m @ (v * v).sum(1) + inertia @ (w * w).sum(1))
    En, Et = _elastic(sim, mask)
    grav = -float(m @ (P.x[mask] @ np.asarray(sim.g, float)))
    thermal = float((P.T[mask] / P.mcp_inv[mask]).sum())
    fr = float(P.heat_friction[mask].sum()) if len(P.heat_friction) else 0.0
    return np.array([kin, En + Et, grav, thermal, fr])


def energy_parts(sim):
    """The parts of the energy book of ``sim`` now (module docstring), in J, and
    ``book`` = their sum with the signs of the book; ``heat_generated``: the frictional
    heat so far (particles, also those removed since, and walls)."""
    P, pl, M = sim.particles, sim.plane_state, sim.mesh_state
    En, Et = _elastic(sim, np.ones(sim.n, np.uint8))
    v, w = P.v, P.omega
    kin = 0.5 * float(P.mass @ (v * v).sum(1) + P.inertia @ (w * w).sum(1))
    grav = -float(P.mass @ (P.x @ np.asarray(sim.g, float)))
    thermal = float((P.T / P.mcp_inv).sum()) if len(P.T) else 0.0
    lost = float(sim.lost_energy[:4].sum())
    added = float(sim.added_energy[:4].sum())
    work = float(pl.work.sum() + M.wall_work.sum())
    # plane and wall accumulators hold conduction and radiation; the enclosure its own
    q_in = float(pl.heat.sum() + M.wall_heat.sum()) + sim.walls.heat_reset
    q_in += float(getattr(sim.radiation, "enclosure_heat", 0.0))
    fr_walls = float(pl.friction_heat.sum() + M.wall_friction_heat.sum())
    fr_particles = float(P.heat_friction.sum()) if len(P.heat_friction) else 0.0
    parts = dict(kinetic=kin, elastic=En + Et, elastic_tangential=Et, gravity=grav,
                 thermal=thermal, lost=lost, added=added, wall_work=work, boundary_heat=q_in,
                 friction_to_walls=fr_walls,
                 heat_generated=fr_particles + float(sim.lost_energy[4]) + fr_walls)
    parts["book"] = kin + En + Et + grav + thermal + lost - added - work - q_in + fr_walls
    return parts


class EnergyAudit:
    """The drift of the energy book since its start (module docstring).

    ``drift`` (J) = book - book at the start; ``drift_rel`` = drift / E_ref with
    E_ref = heat generated + kinetic + elastic energy now: the mechanical energy that has
    been in play (dissipated or still moving).  ``time_integration`` is not separated
    here; the validation (docs/validation.md) shows the part that falls with dt.

    ``EnergyAudit(sim)`` starts its book now (``book0``); :meth:`of_run` gives the
    audit of the run, whose start is kept in the simulation and its checkpoints.
    """

    def __init__(self, sim, book0=None):
        self.sim = sim
        self.book0 = energy_parts(sim)["book"] if book0 is None else float(book0)

    @classmethod
    def of_run(cls, sim):
        """The audit of the run: its book starts at the first call of the run
        (``sim.energy_book0``, set then); a run resumed from a checkpoint continues it."""
        if sim.energy_book0 is None:
            sim.energy_book0 = energy_parts(sim)["book"]
        return cls(sim, sim.energy_book0)

    def sample(self):
        """The parts now, with ``drift`` and ``drift_rel``."""
        p = energy_parts(self.sim)
        p["drift"] = p["book"] - self.book0
        ref = p["heat_generated"] + p["kinetic"] + p["elastic"]
        p["drift_rel"] = p["drift"] / ref if ref > 0.0 else 0.0
        return p
