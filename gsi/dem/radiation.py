r"""Thermal radiation of the particles: particle-particle, particle-wall and an enclosure.

The model of the packed-bed pyrolysis paper (seed 000, eqs. 22-23): a particle i emits
eps_i sigma T_i^4 from its surface and absorbs, with alpha_i = eps_i (grey, Kirchhoff),
the flux its neighbours j send towards it, weighted by the view factor F_i->j:

.. math::
    q_{rad,i} = \alpha_i \sum_j F_{i\to j}\, q_{rad,j} - \varepsilon_i \sigma T_i^4,
    \qquad F_{i\to j} = \frac{A_j}{\sum_{k} A_k}            \quad\text{(eqs. 22, 23)}

with the sums over the neighbours inside a radiation cut-off.

How eq. 23 is read. The printed formula puts A_i over the sum of the neighbours' areas
A_j, while the text says "the ratio of the surface of particle i to the sum of the
surfaces of all neighbouring particles j". Taken literally, F_i->j would then not depend
on j and sum_j F_i->j = k A_i / sum_j A_j, which is 1 only for equal spheres. We read it
as the share of i's view taken by neighbour j, F_i->j = A_j / sum_k A_k: it is the
printed value for equal spheres (1/k for k neighbours), it sums to one (all of i's
emission reaches its neighbours, the closure the eq. 22 balance needs), and a larger
neighbour takes a larger share. The unseen part of the surface is then empty whenever a
particle has a neighbour; the model has no open-sky term (the free surface of a bed
radiates only to its neighbours).

Neighbours (``cutoff`` c, a multiple of the radius, default :data:`CUTOFF_DEFAULT`):

* particles j with centre distance |x_i - x_j| < c (R_i + R_j) (c = 1.5: equal spheres up
  to a gap of one radius, about the first neighbour shell of a packing);
* radiating walls: a wall that has a temperature and an emissivity > 0. A plane within
  c R_i of the centre (on its side of the plane) and each mesh wall with a triangle within
  c R_i count as ONE neighbour of area A_i: the particle's mirror image in the wall (an
  image at distance 2 d is inside the particle cut-off c (R_i + R_i) exactly when d < c
  R_i). A mesh wall exchanges at its closest point to the particle (over all its
  triangles within the cut-off), at the FE temperature interpolated there with the
  barycentric weights, T_w = sum_k w_k T_k, and its heat goes to the wall's nodes
  with the same weights (P2 walls: the parent face's P2 basis), through the very
  accumulators of the particle-wall conduction (``vertex_heat``, ``wall_heat``) that the
  thermal coupling turns into nodal heat loads of the FE. A particle in a concave
  corner of one mesh wall sees it once. Planes feed ``plane_state.heat``.
* Walls without a temperature, or with emissivity 0, are not neighbours: adiabatic,
  re-radiating surfaces whose share the closure hands to the particles around.

Pairwise-conservative form. With alpha = eps, the heat i absorbs of j's emission minus
the heat j absorbs of i's is eps_i eps_j sigma (A_j F_j->i T_j^4 - A_i F_i->j T_i^4); the
part a neighbour does not absorb counts as returned to the emitter (one reflection).
Reciprocity A_i F_i->j = A_j F_j->i does not hold for eq. 23 (the two sums differ), so
the exchange area of a pair is symmetrised to the smaller of the two,

.. math::
    S_{ij} = \min(A_i F_{i\to j},\ A_j F_{j\to i})
           = \frac{A_i A_j}{\max(\Sigma_i, \Sigma_j)}, \qquad \Sigma_i = \sum_k A_k,

    Q_{i \leftarrow j} = \sigma\, \varepsilon_i \varepsilon_j\, S_{ij}\,(T_j^4 - T_i^4)
    = -Q_{j \leftarrow i}.

The minimum keeps sum_j S_ij <= A_i: no particle exchanges through more than its
surface, which makes the stability bound below rigorous. Each pair is visited from both
sides with the same operands in the same order, so Q_ij = -Q_ji bit for bit and
sum m c_p T changes only by round-off. A wall's exchange area is S_iw = A_i A_i / Sigma_i,
with the wall's emissivity eps_w; its heat leaves or enters the wall's books.

Enclosure (``T_enclosure``, K, default None: none): a particle with no neighbour at all
exchanges with a black enclosure at T_enclosure through its whole surface,
Q = sigma eps_i A_i (T_enc^4 - T_i^4) (a single particle in a cold room; the heat goes to
:attr:`Radiation.enclosure_heat`). Without it such a particle does not radiate.

Time integration (operator splitting beside the compiled step engine, which integrates
the contact heat every step): every ``every`` DEM steps, at the start of the interval,
the exchange is evaluated at the current temperatures (explicit at T_n) and applied over
the interval dt_rad = every x dt: T_i += dt_rad Q_i / (m_i c_p,i), and the walls'
accumulators take Q dt_rad. The neighbour search is a cell list at the cut-off, made
afresh at each evaluation (cells >= 2 c R_max; :mod:`gsi.dem.cells`).

Stability: with S summing to at most A_i, the update is a convex combination (no new
extremum) while dt_rad 4 eps_i sigma T_max^3 A_i / (m_i c_p,i) <= 1, T_max the highest
particle, radiating wall or enclosure temperature; each evaluation checks it and refuses
larger steps with a one-line GsiInputError naming ``dem.radiation_every``.

Temperatures must be absolute (K).
"""
from __future__ import annotations

import math
from collections import namedtuple

import numpy as np

from gsi.dem import cells
from gsi.dem import neighbour as nbr
from gsi.dem.radiation_kernels import (SIGMA, CellGrid, Emitters, RateArrays, Surfaces,
                                      Views, exchange, scatter_wall_heat, view_sums)
from gsi.errors import GsiInputError

__all__ = ["Radiation", "Rates", "SIGMA", "CUTOFF_DEFAULT", "emissivity_by_type"]

#: default radiation cut-off c: neighbours closer than c (R_i + R_j) between centres
CUTOFF_DEFAULT = 1.5


# ---------------------------------------------------------------------- the model
Rates = namedtuple("Rates", [
    "Q",            # (n,) W: heat rate into each particle
    "Q_plane",      # (n, n_planes) W: from each plane into each particle
    "Q_wall",       # (n, n_mesh_walls) W: from each mesh wall into each particle
    "Q_enclosure",  # (n,) W: from the enclosure (particles without neighbours)
    "area_sum",     # (n,) m^2: Sigma_i, the area of each particle's neighbours
    "wall_tri",     # (n, n_mesh_walls) int64: closest triangle of each wall (-1: none)
    "wall_w",       # (n, n_mesh_walls, 3): its barycentric weights
    "S",            # (n, n) m^2 or None: exchange area S_ij of each pair
    "Q_pair",       # (n, n) W or None: Q_i<-j of each pair
])
"""The radiation rates at one state (:meth:`Radiation.rates`)."""


def emissivity_by_type(emissivity: dict, material_names) -> np.ndarray:
    """Emissivities by material type index (-) from a dict by material name (materials not
    named: 0); a one-line GsiInputError names a wrong material or value."""
    names = list(material_names)
    eps = np.zeros(len(names))
    for name, e in dict(emissivity).items():
        if name not in names:
            raise GsiInputError(f"materials.{name}.emissivity: {name!r} is not a material; "
                                f"known: {names}")
        if not (isinstance(e, (int, float)) and 0.0 <= e <= 1.0):
            raise GsiInputError(f"materials.{name}.emissivity = {e!r}: must be in [0, 1] (-)")
        eps[names.index(name)] = float(e)
    return eps


class Radiation:
    """Radiation of a simulation's particles (module docstring); made by
    :meth:`gsi.dem.Simulation.set_radiation`.

    The model holds the data it works on, not the simulation: the particle store, the
    wall registry and the domain box; the step count, dt and whether the time-step
    checks are waived reach it as arguments of :meth:`step_due`.

    Parameters
    ----------
    store : gsi.dem.storage.ParticleStore
        The particles (positions, radii, types, temperatures, 1/(m c_p)).
    walls : gsi.dem.wall_registry.Walls
        The planes and mesh walls (their states and handles).
    domain : (lo, hi)
        The simulation box (m): the cell grid of the neighbour search spans it.
    eps_type : (n_types,) float
        Emissivity (-, in [0, 1]) by material type index (:func:`emissivity_by_type`);
        materials with 0 occupy view but neither emit nor absorb; their walls do not
        radiate.
    cutoff : float, optional
        Radiation cut-off c (-, >= 1; default :data:`CUTOFF_DEFAULT`): particles closer
        than c (R_i + R_j) between centres, walls closer than c R_i, are neighbours.
    every : int, default 1
        DEM steps per evaluation; the exchange is applied over every x dt.
    T_enclosure : float, optional
        Temperature (K) of a black enclosure seen by particles with no neighbour.

    Attributes
    ----------
    plane_heat : ndarray (n_planes,)
        Heat radiated from each plane into the particles since the start (J).
    wall_heat : ndarray (n_mesh_walls,)
        Heat radiated from each mesh wall into the particles since the start (J).
    enclosure_heat : float
        Heat from the enclosure into the particles since the start (J).
    evaluations : int
        Evaluations so far.
    """

    def __init__(self, store, walls, *, domain, eps_type, cutoff: float | None = None,
                 every: int = 1, T_enclosure: float | None = None):
        cutoff = CUTOFF_DEFAULT if cutoff is None else cutoff
        if not (isinstance(cutoff, (int, float)) and math.isfinite(cutoff) and cutoff >= 1.0):
            raise GsiInputError(f"dem.radiation_cutoff = {cutoff!r}: must be >= 1 (a multiple "
                                "of R_i + R_j; 1 reaches touching particles only)")
        if isinstance(every, bool) or int(every) != every or every < 1:
            raise GsiInputError(f"dem.radiation_every = {every!r}: must be an integer >= 1")
        if T_enclosure is not None and not (math.isfinite(T_enclosure) and T_enclosure >= 0):
            raise GsiInputError(f"dem.radiation_T_enclosure = {T_enclosure!r}: must be >= 0 (K)")
        self.store, self.walls = store, walls
        self.lo, self.hi = (np.asarray(b, float) for b in domain)
        self.eps_type = np.asarray(eps_type, float)
        self.cutoff = float(cutoff)
        self.every = int(every)
        self.T_enclosure = None if T_enclosure is None else float(T_enclosure)
        self.plane_heat = np.zeros(0)
        self.wall_heat = np.zeros(0)
        self.enclosure_heat = 0.0
        self.evaluations = 0
        self._done_at = -1

    # ------------------------------------------------------------------ stepping hook
    def step_due(self, step_count: int, dt: float, *, force_dt: bool = False) -> int:
        """Called by the step loop before each compiled chunk at step ``step_count`` of
        length ``dt`` (s): apply the exchange over the next ``every`` steps when the step
        count is a multiple of ``every`` (once per step count), and return how many steps
        the chunk may run before the next evaluation.  ``force_dt`` waives the stability
        refusal (``dem.force_dt``)."""
        k = int(step_count)
        if k % self.every == 0 and self._done_at != k:
            self._done_at = k
            if self.store.n:
                self.apply(self.every * dt, step_count=k, force_dt=force_dt)
        return self.every - k % self.every

    # ------------------------------------------------------------------ evaluation
    def _walls(self):
        pl, M = self.walls.plane_state, self.walls.mesh_state
        pl_eps = self.eps_type[pl.type] if len(pl.type) else np.zeros(0)
        pl_rad = (pl.has_T.astype(bool) & (pl_eps > 0)).astype(np.uint8)
        wall_eps = self.eps_type[M.wall_type] if len(M.wall_type) else np.zeros(0)
        wall_rad = (M.wall_has_T.astype(bool) & (wall_eps > 0)).astype(np.uint8)
        if len(self.plane_heat) < len(pl_eps):
            self.plane_heat = np.concatenate([self.plane_heat,
                                              np.zeros(len(pl_eps) - len(self.plane_heat))])
        if len(self.wall_heat) < len(wall_eps):
            self.wall_heat = np.concatenate([self.wall_heat,
                                             np.zeros(len(wall_eps) - len(self.wall_heat))])
        return pl, M, pl_eps, pl_rad, wall_eps, wall_rad

    def stability(self, dt: float) -> float:
        """max_i dt_rad 4 eps_i sigma T_max^3 A_i/(m_i c_p,i) (-), dt_rad = every x ``dt``
        (s), T_max the highest particle, radiating wall or enclosure temperature (K): the
        explicit update is stable below 1 (module docstring)."""
        P = self.store.particles()
        if self.store.n == 0:
            return 0.0
        pl, M, pl_eps, pl_rad, wall_eps, wall_rad = self._walls()
        T_max = float(P.T.max())
        if pl_rad.any():
            T_max = max(T_max, float(pl.T[pl_rad.astype(bool)].max()))
        if wall_rad.any():
            hot = wall_rad.astype(bool)[M.vertex_wall]
            if hot.any():
                T_max = max(T_max, float(M.T[hot].max()))
        if self.T_enclosure is not None:
            T_max = max(T_max, self.T_enclosure)
        r = P.radius
        c = self.eps_type[P.type] * 4.0 * math.pi * r * r * P.mcp_inv
        return float(self.every * dt * 4.0 * SIGMA * T_max ** 3 * c.max())

    def _check(self, dt, step_count, force_dt):
        T_min = float(self.store.particles().T.min())
        if T_min < 0.0:
            raise GsiInputError(f"dem.radiation: particle temperature {T_min:g} < 0; radiation "
                                "needs absolute temperatures (K)")
        ratio = self.stability(dt)
        if ratio > 1.0 and not force_dt:
            limit = max(1, int(self.every / ratio))
            raise GsiInputError(
                f"dem.radiation_every = {self.every}: the explicit radiation update is unstable "
                f"(radiation_every x dt x 4 eps sigma T^3 A/(m c_p) = {ratio:.3g} > 1 at step "
                f"{step_count}); use dem.radiation_every <= {limit} or a smaller run.dt")

    def rates(self, *, record: bool = False) -> Rates:
        """The heat rates at the current state, without applying them (:class:`Rates`;
        ``record``: also the dense (n, n) pair matrices, for small systems)."""
        P = self.store.particles()
        n = self.store.n
        lo = self.lo
        pl, M, pl_eps, pl_rad, wall_eps, wall_rad = self._walls()
        x, r = P.x, P.radius
        area = 4.0 * math.pi * r * r
        eps = self.eps_type[P.type]
        T = P.T
        T4 = T * T * T * T
        rmax = float(r.max()) if n else 0.0
        dims, inv_cs = cells.grid_for(lo, self.hi, 2.0 * self.cutoff * rmax, n)
        cell_of = np.empty(n, np.int64)
        cells.cell_index(n, x, lo, inv_cs, dims, cell_of)
        cell_start, cell_list = cells.bin_cells(n, cell_of, int(dims.prod()))
        nw = len(wall_eps)
        if wall_rad.any():
            tcell_start, tcell_list = nbr.bin_triangles(M.x, M.tri, lo, inv_cs, dims,
                                                        self.cutoff * rmax)
        else:
            tcell_start = np.zeros(int(dims.prod()) + 1, np.int64)
            tcell_list = np.zeros(0, np.int32)
        E = Emitters(x, r, area, eps, T4)
        G = CellGrid(self.cutoff, lo, inv_cs, dims, cell_start, cell_list, tcell_start,
                     tcell_list)
        has_enc = self.T_enclosure is not None
        S = Surfaces(pl.point, pl.normal, pl_rad, pl_eps, pl.T ** 4, M.x, M.tri, M.T,
                     M.tri_wall, wall_rad, wall_eps,
                     self.T_enclosure ** 4 if has_enc else 0.0, has_enc)
        V = Views(np.empty(n), np.full((n, nw), -1, np.int64), np.zeros((n, nw, 3)))
        view_sums(E, G, S, V)
        pair = (n, n) if record else (0, 0)
        out = RateArrays(np.empty(n), np.zeros((n, len(pl_eps))), np.zeros((n, nw)),
                         np.zeros(pair), np.zeros(pair))
        exchange(E, G, S, V, out)
        Q, Q_plane, Q_wall, S_mat, Q_mat = out
        area_sum, wall_tri, wall_w = V
        Q_enc = np.where(area_sum == 0.0, Q, 0.0) if has_enc else np.zeros(n)
        return Rates(Q, Q_plane, Q_wall, Q_enc, area_sum, wall_tri, wall_w,
                     S_mat if record else None, Q_mat if record else None)

    def apply(self, dt_rad: float, *, step_count: int = 0, force_dt: bool = False) -> None:
        """Evaluate at the current temperatures and apply over ``dt_rad`` (s): particle
        temperatures, the walls' accumulators (``plane_state.heat``, ``mesh_state``
        ``vertex_heat`` and ``wall_heat``) and this model's own totals.  Refuses an
        unstable ``dt_rad`` unless ``force_dt``; ``step_count`` names the step in the
        message."""
        self._check(dt_rad / self.every, step_count, force_dt)
        R = self.rates()
        P = self.store.particles()
        P.T[:] += dt_rad * R.Q * P.mcp_inv
        if R.Q_plane.shape[1]:
            qp = R.Q_plane.sum(0) * dt_rad
            self.walls.plane_state.heat[:] += qp
            self.plane_heat += qp
        if R.Q_wall.shape[1]:
            M = self.walls.mesh_state
            scatter_wall_heat(dt_rad, Views(R.area_sum, R.wall_tri, R.wall_w), R.Q_wall, M,
                              self.wall_heat)
        self.enclosure_heat += float(R.Q_enclosure.sum()) * dt_rad
        self.evaluations += 1

    def heat_from(self, wall) -> float:
        """Heat radiated from ``wall`` (a PlaneWall or MeshWall of this simulation) into
        the particles since the start (J)."""
        if wall in self.walls.planes:
            k, acc = self.walls.planes.index(wall), self.plane_heat
        elif wall in self.walls.mesh_walls:
            k, acc = self.walls.mesh_walls.index(wall), self.wall_heat
        else:
            raise GsiInputError("radiation.heat_from: not a wall of this simulation")
        return float(acc[k]) if k < len(acc) else 0.0

    # ------------------------------------------------------------------ checkpoints
    def state(self) -> dict:
        """The running totals (J) as arrays (for checkpoints)."""
        return {"rad.plane_heat": self.plane_heat.copy(), "rad.wall_heat": self.wall_heat.copy(),
                "rad.scalars": np.array([self.enclosure_heat, self.evaluations], np.float64)}

    def set_state(self, d: dict) -> None:
        """Restore :meth:`state` (missing keys: totals start at 0)."""
        self.plane_heat = np.array(d.get("rad.plane_heat", np.zeros(0)), float)
        self.wall_heat = np.array(d.get("rad.wall_heat", np.zeros(0)), float)
        enc, ev = d.get("rad.scalars", np.zeros(2))
        self.enclosure_heat, self.evaluations = float(enc), int(ev)
        self._done_at = -1
