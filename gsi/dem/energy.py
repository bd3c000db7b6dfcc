"""The energy book of a DEM run (docs/design.md, "Energy audit").

    E_book = E_kin + E_el + E_grav + E_th - W_walls - Q_walls + Q_friction,walls

is constant in a run whose particles stay in the domain:

- ``kinetic``: sum 1/2 m v^2 + 1/2 I omega^2 (J);
- ``elastic``: the contact springs -- the normal overlap, Hertz 8/15 E* sqrt(R*)
  delta^(5/2) or linear 1/2 k_n delta^2, and the tangential spring 1/2 k_t |xi|^2 with
  the k_t of the current overlap (J);
- ``gravity``: -sum m g . x (J);
- ``thermal``: sum m c_p T of the particles (J);
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
  contact and step, and a spring's energy at its contact's end
  (:mod:`gsi.dem.contact.dissipation`, :mod:`gsi.dem.spring_heat`), so they leave no
  drift -- except a mesh-triangle contact's spring at its end, which leaves the book;
- particles that leave the domain take their energy with them (not booked).

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


@njit
def contact_elastic_energy(P, pairs, wc, table, hertz):
    """(normal, tangential) elastic energy (J) of the contacts of the last step: sphere
    pairs (``pairs.active``), planes (``wc.plane_mask``; ``P`` and the plane geometry as
    the engine left them) and mesh triangles (``wc.count`` slots)."""
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
def wall_elastic_energy(P, pairs, pl, M, wc, table, hertz):
    """(normal, tangential) elastic energy (J) of the particles' plane and triangle
    contacts of the last step."""
    nt = table.shape[0]
    tab = table.reshape((nt * nt, table.shape[2]))
    npl = pl.point.shape[0]
    En = 0.0
    Et = 0.0
    x = P.x
    for i in range(x.shape[0]):
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


def energy_parts(sim):
    """The parts of the energy book of ``sim`` now (module docstring), in J, and
    ``book`` = their sum with the signs of the book; ``heat_generated``: the frictional
    heat so far (particles and walls)."""
    P, pl, M = sim.particles, sim.plane_state, sim.mesh_state
    hertz = int(sim.engine.model[M_NORMAL]) == _HERTZ
    En = Et = 0.0
    if sim.flags.built:
        a = contact_elastic_energy(P, sim.pairs, sim.wall_contacts, sim.table, hertz)
        b = wall_elastic_energy(P, sim.pairs, pl, M, sim.wall_contacts, sim.table, hertz)
        En, Et = a[0] + b[0], a[1] + b[1]
    v, w = P.v, P.omega
    kin = 0.5 * float(P.mass @ (v * v).sum(1) + P.inertia @ (w * w).sum(1))
    grav = -float(P.mass @ (P.x @ np.asarray(sim.g, float)))
    thermal = float((P.T / P.mcp_inv).sum()) if len(P.T) else 0.0
    work = float(pl.work.sum() + M.wall_work.sum())
    # plane and wall accumulators hold conduction and radiation; the enclosure its own
    q_in = float(pl.heat.sum() + M.wall_heat.sum()) + sim.walls.heat_reset
    q_in += float(getattr(sim.radiation, "enclosure_heat", 0.0))
    fr_walls = float(pl.friction_heat.sum() + M.wall_friction_heat.sum())
    parts = dict(kinetic=kin, elastic=En + Et, elastic_tangential=Et, gravity=grav,
                 thermal=thermal, wall_work=work, boundary_heat=q_in,
                 friction_to_walls=fr_walls,
                 heat_generated=float(P.heat_friction.sum()) + fr_walls)
    parts["book"] = kin + En + Et + grav + thermal - work - q_in + fr_walls
    return parts


class EnergyAudit:
    """The drift of the energy book since :meth:`start` (module docstring).

    ``drift`` (J) = book - book at the start; ``drift_rel`` = drift / E_ref with
    E_ref = heat generated + kinetic + elastic energy now: the mechanical energy that has
    been in play (dissipated or still moving).  ``time_integration`` is not separated
    here; the validation (docs/validation.md) shows the part that falls with dt.
    """

    def __init__(self, sim):
        self.sim = sim
        self.book0 = energy_parts(sim)["book"]

    def sample(self):
        """The parts now, with ``drift`` and ``drift_rel``."""
        p = energy_parts(self.sim)
        p["drift"] = p["book"] - self.book0
        ref = p["heat_generated"] + p["kinetic"] + p["elastic"]
        p["drift_rel"] = p["drift"] / ref if ref > 0.0 else 0.0
        return p
