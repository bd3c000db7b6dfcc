"""The replay with an FE heat structure as a wall: :class:`FEWallReplay` (the FE steps
once per coupling interval with the wall rows' heat as its nodal loads)."""
from __future__ import annotations

import math
import time

import numpy as np

from gsi.errors import GsiInputError
from gsi.jit import njit
from gsi.extrapolation.replay import Replay, particle_row


@njit
def _replay_rows_fe(T, a, b, w, Tw, inv_C, tri, r0, r1, tn, tw, hn, hw, T_nodes, node_heat):
    """Rows r0..r1 - 1 of :func:`_replay_rows`, and rows with b = -2 against an FE wall:
    the particle exchanges H m (T_w - T) with the wall at T_w = sum_j tw[t, j]
    T_nodes[tn[t, j]] (t = tri[r]), and that heat leaves the wall nodes hn[t, j] in the
    shares hw[t, j] (``node_heat``, J into the wall)."""
    for r in range(r0, r1):
        ka = a[r]
        if b[r] >= -1:
            particle_row(T, ka, b[r], w[r], Tw[r], inv_C)
        else:
            t = tri[r]
            Tn = 0.0
            for j in range(tn.shape[1]):
                Tn += tw[t, j] * T_nodes[tn[t, j]]
            q = w[r] * (Tn - T[ka])
            T[ka] += q * inv_C[ka]
            for j in range(hn.shape[1]):
                node_heat[hn[t, j]] -= q * hw[t, j]


def rotate(x, axis, centre, angle):
    """Points ``x`` (n, 3) turned by ``angle`` (rad) about ``axis`` (unit) through
    ``centre`` (Rodrigues)."""
    r = np.asarray(x, float) - centre
    c, s = math.cos(angle), math.sin(angle)
    return (centre + r * c + np.cross(axis, r) * s
            + np.outer(r @ axis, axis) * (1.0 - c))


class FEWallReplay(Replay):
    """The replay of a kiln: Algorithm 3 with a wall that is an FE heat structure.

    The rows of particle-particle contacts are those of :class:`Replay`.  The rows of the
    structure's contact wall (logged with their wall triangle) exchange heat with the FE
    wall as the live coupling (:mod:`gsi.coupling.thermal`) does, interval by interval:

    1. the period is cut into the coupling intervals of the structure (dt_FE = n_sub dt);
       at the start of interval k the wall takes the FE temperature T_k at its nodes
       (``interface.wall_temperature``);
    2. the rows that start in the interval are replayed in log order; a wall row on
       triangle t moves Q = H m (T_w - T_p) into its particle, with T_w the triangle's
       mean node temperature, and puts -Q on the triangle's nodes with the weights of its
       centroid (P1: 1/3 each; the wall of a P2 mechanical interface: the P2 basis of
       the parent face at the sub-triangle's centroid, as the DEM's scatter -- a
       thermal-only structure of a case has a P1 wall) -- the contact point inside the
       triangle is not logged, the centroid stands for it;
    3. the wall-node heat becomes the nodal heat loads of the interval through the live
       coupling's own transfer (``interface.vertex_heat``,
       :func:`gsi.coupling.thermal.load_nodal_heat`) and the heat problem takes one step.

    Each row conserves C_p T_p + (heat on the wall nodes); each FE step turns the nodal
    loads and the boundary heat (flux, convection, fixed temperature: the
    :class:`gsi.coupling.thermal.BoundaryMeter` of the step) into stored heat, so
    sum m c_p T + int rho c T dx - (heat in through the boundary) is conserved to the
    round-off of the FE solve (direct solver).

    A turning wall (a rotary kiln's shell): its triangles are numbered in the body's frame
    and the FE lives in it.  After p periods the drum has turned p omega tau further, so a
    logged contact on triangle t at the lab position x now meets the body point under x,
    R(-p omega tau) c_t: the replay uses the triangle whose centroid is nearest to it
    (the identity when tau is a whole number of turns).

    Parameters
    ----------
    log : gsi.dem.contact_log.ContactLog
    structure : gsi.coupling.coupled_structure.CoupledStructure
        The kiln wall (``heat`` and ``interface``; one MPI rank), in its state at t1.
    fe_wall : int
        The wall's index in the log (planes first, then mesh walls).
    omega : (3,) float
        Angular velocity of the wall during the log and after it (rad/s; zeros: fixed).
    centre : (3,) float
        A point of the rotation axis (m).
    sigma, on_unstable, pairing
        As :class:`Replay`.
    """

    def __init__(self, log, structure, *, fe_wall, omega=(0.0, 0.0, 0.0),
                 centre=(0.0, 0.0, 0.0), sigma=None, on_unstable="substep", pairing="auto"):
        from gsi.dem.wall_kernels import p2_weight
        super().__init__(log, sigma=sigma, on_unstable=on_unstable, pairing=pairing,
                         fe_wall=fe_wall)
        self.structure = structure
        heat, itf = structure.heat, structure.interface
        if heat is None:
            raise GsiInputError(f"structures.{structure.name}: the kiln replay needs its "
                                "heat (contact.mode = 'thermal')")
        if heat.comm.size > 1:
            raise GsiInputError("extrapolation with a structure: run on one MPI rank")
        self.n_sub = int(round(structure.dt / log.dt))
        K = int(round(log.period / log.dt))
        if K % self.n_sub:
            raise GsiInputError(f"extrapolation.period = {log.period:g}: must be a whole "
                                f"number of coupling intervals of structures."
                                f"{structure.name} (n_sub x dt = {structure.dt:g} s)")
        self.n_intervals = K // self.n_sub
        self.bounds = np.searchsorted(self._start, np.arange(self.n_intervals + 1)
                                      * self.n_sub).astype(np.int64)
        self.bounds[-1] = self.n_rows
        tri = itf.triangles
        nt = len(tri)
        self._tn = tri.astype(np.int64)
        self._tw = np.full((nt, 3), 1.0 / 3.0)
        if itf.n_midpoints == 0:
            self._hn, self._hw = self._tn, self._tw
        else:
            lam = itf.parent_coords.mean(axis=1)          # centroid in the parent face
            self._hn = itf.parent_nodes.astype(np.int64)
            self._hw = np.array([[p2_weight(j, *lam[t]) for j in range(6)]
                                 for t in range(nt)])
        self._centroids = itf.x0[tri].mean(axis=1)
        omega = np.asarray(omega, float)
        w = float(np.linalg.norm(omega))
        self.axis = omega / w if w > 0 else np.array([0.0, 0.0, 1.0])
        self.centre = np.asarray(centre, float)
        self.turn_per_period = w * log.period                  # rad
        fe_rows = self._b == -2
        self._fe_rows = fe_rows
        self._fe_tri = self._tri[fe_rows]
        self._maps = {}

    def triangle_map(self, p):
        """Triangles (wall numbering) the logged triangles stand for in period p."""
        phi = math.remainder(p * self.turn_per_period, 2.0 * math.pi)
        if abs(phi) < 1e-9:
            return None
        key = round(phi, 9)
        if key not in self._maps:
            from scipy.spatial import cKDTree
            if not hasattr(self, "_tree"):
                self._tree = cKDTree(self._centroids)
            self._maps[key] = np.asarray(self._tree.query(
                rotate(self._centroids, self.axis, self.centre, -phi))[1], np.int32)
        return self._maps[key]

    def run(self, periods, *, T=None, store=(), hot=None, say=None):
        """Extrapolate ``periods`` periods from t1, the FE wall stepping once per coupling
        interval (it ends in its state at t1 + periods tau).

        Parameters
        ----------
        periods : int
        T : (N,) float, optional
            Temperatures at t1 (log order), default ``log.T1``.
        store : iterable of int
            Periods n whose temperatures (and extrapolated positions) are returned.
        hot : (N,) bool, optional
            A group of particles (log order) whose mean temperature is recorded with the
            rest's.

        Returns
        -------
        dict
            ``time`` (periods + 1,) s; per period (index 0: t1) ``T_mean`` (m c_p-weighted
            bed mean, K), ``T_hot``, ``T_cold`` (with ``hot``), ``E_particles``,
            ``E_structure`` (int rho c T dx), ``Q_boundary`` (cumulative heat in through
            the structure's boundary since t1), ``Q_wall`` (heat from the wall into the
            particles in the period, J), ``T_wall_mean`` (K); ``stored``: {n: (T (N,),
            x (N, 3))}; ``balance``: max |drift| of E_particles + E_structure -
            Q_boundary relative to E at t1; ``seconds`` (wall time), ``fe_seconds``
            (its FE part).
        """
        from gsi.coupling.thermal import BoundaryMeter, load_nodal_heat
        log, st = self.log, self.structure
        heat, itf = st.heat, st.interface
        n = log.n_particles
        C = np.asarray(log.heat_capacity, float)
        T_real = np.array(log.T1 if T is None else T, float)
        if T_real.shape != (n,):
            raise GsiInputError(f"T: must have {n} temperatures (log order)")
        inv_C_real = 1.0 / C
        store = set(int(p) for p in store)
        vol = heat.volume()
        rc = heat.material.rho * heat.material.c
        keys = ("T_mean", "E_particles", "E_structure", "Q_boundary", "Q_wall",
                "T_wall_mean") + (("T_hot", "T_cold") if hot is not None else ())
        rec = {k: np.zeros(periods + 1) for k in keys}

        def note(p, Q_b, Q_w):
            E_s = heat.stored_heat()
            rec["E_particles"][p] = float(C @ T_real)
            rec["T_mean"][p] = rec["E_particles"][p] / C.sum()
            rec["E_structure"][p] = E_s
            rec["Q_boundary"][p] = Q_b
            rec["Q_wall"][p] = Q_w
            rec["T_wall_mean"][p] = E_s / (rc * vol)
            if hot is not None:
                rec["T_hot"][p] = T_real[hot].mean()
                rec["T_cold"][p] = T_real[~hot].mean()

        note(0, 0.0, 0.0)
        stored = {}
        if 0 in store:
            stored[0] = (T_real.copy(), log.x1.copy())
        node_heat = np.zeros(itf.n_nodes)
        role = np.arange(n)
        Q_b = 0.0
        fe_s = 0.0
        t = time.perf_counter()
        for p in range(1, periods + 1):
            role = role[self.sigma]
            Tt = T_real[role]
            inv_C = inv_C_real[role]
            tri = self._tri
            m = self.triangle_map(p)
            if m is not None:
                tri = tri.copy()
                tri[self._fe_rows] = m[self._fe_tri]
            Q_w = 0.0
            for k in range(self.n_intervals):
                t_fe = time.perf_counter()
                T_nodes = itf.wall_temperature(itf.surface_temperature())
                fe_s += time.perf_counter() - t_fe
                node_heat[:] = 0.0
                _replay_rows_fe(Tt, self._a, self._b, self._w, self._Tw, inv_C, tri,
                                self.bounds[k], self.bounds[k + 1], self._tn, self._tw,
                                self._hn, self._hw, T_nodes, node_heat)
                t_fe = time.perf_counter()
                Q_w -= float(node_heat.sum())
                load_nodal_heat(heat, itf, itf.vertex_heat(node_heat) / heat.dt, root=0)
                meter = BoundaryMeter(heat)
                heat.step()
                Q_b += meter.heat_in()
                fe_s += time.perf_counter() - t_fe
            T_real[role] = Tt
            note(p, Q_b, Q_w)
            if p in store:
                x = np.empty_like(log.x1)
                x[role] = log.x1
                stored[p] = (T_real.copy(), x)
            if say is not None and periods >= 10 and p % max(1, periods // 10) == 0:
                say(f"extrapolation: period {p}/{periods}, bed {rec['T_mean'][p]:.2f} K")
        heat.clear_nodal_heat()
        seconds = time.perf_counter() - t
        E = rec["E_particles"] + rec["E_structure"] - rec["Q_boundary"]
        rec.update(time=log.t1 + log.period * np.arange(periods + 1), stored=stored,
                   balance=float(np.abs(E - E[0]).max() / abs(E[0])), seconds=seconds,
                   fe_seconds=fe_s)
        return rec

