"""Long-time extrapolation of particle heat conduction from one period of DEM.

The method of Haydar, Martin & Bonnefoy (2023), "Long time extrapolation of DEM with
heat conduction in a moving granular medium", Chem. Eng. Sci. 277, 118815, built on the
motion extrapolation of Bednarek et al. (2019), Chem. Eng. Sci. 197, 223-234:

1. Run the DEM to a pseudo-periodic state at t0 and log every contact until t1 = t0 + tau
   (:meth:`gsi.dem.Simulation.start_contact_log`, :mod:`gsi.dem.contact_log`).
2. Pair the particles (their eq. 6, :func:`pair_particles`): the bijection sigma between
   the particles at t0 and at t1 that minimises the summed distance
   sum_a |x_a(t0) - x_sigma(a)(t1)|.  Particle sigma(a) stands at t1 where a stood at t0,
   so in the next period it does what a did: x_sigma(a)(t2) = x_a(t1).  After p periods
   the role of logged particle a is played by sigma^p(a).
3. Replay the log (their Algorithm 3 with eqs. 7-8, :class:`Replay`): period after
   period, each row (a, b, m, s) in the order of the log, applied to the particles
   k = sigma^p(a), l = sigma^p(b) that play a and b now:

       Q = H (T_k - T_l),  H = c s,  T_k <- T_k - Q m/C_k,  T_l <- T_l + Q m/C_l

   with C = m c_p (J/K) and c s the conductance of the DEM's heat model.  Rows with a
   wall that has a temperature exchange heat with it (T_k <- T_k + H m (T_w - T_k)/C_k,
   the wall's temperature fixed at its t0 value); rows with an adiabatic wall do
   nothing.  Each exchange conserves C_k T_k + C_l T_l, so sum C T is conserved to
   round-off.

   Stability (the explicit update of one row, their section 2.1.3): m < C/(2 K sqrt(a))
   = C/H, here with C the smaller heat capacity of the two.  A row that breaks it is
   replayed as s = floor(m H/C) + 1 equal sub-steps of m/s (each then within the
   bound), counted in :attr:`Replay.n_substepped`; ``on_unstable="error"`` refuses the
   log instead, naming the row and the largest stable ``dt_split``.

4. Between periods nothing else changes: the extrapolated configuration at every t_n is
   the configuration at t1 (particle sigma^(n-1)(a) stands at x_a(t1)), relabelled
   (:meth:`Replay.positions`).

5. A wall that is an FE heat structure (a heated kiln shell, :mod:`gsi.kiln`):
   :class:`FEWallReplay` replays the period interval by interval, the FE stepping once
   per coupling interval with the wall rows' heat as its nodal loads (the live
   coupling's transfer), so the bed, the shell and the heat through the shell's
   boundary balance to round-off.

Error measures of the paper: :func:`cell_error` (its eq. 9, on Voronoi cells) and
:func:`energy_transfer_error` (its eq. 10).  Beside eq. 9, :func:`cell_sampling_level`
gives the eq.-9 error of two fields that hold the same temperatures in each cell but not
the same particles (a yardstick gsi adds: the granular flow is chaotic, so over a period
no method predicts which particle ends in which cell).
"""
from __future__ import annotations

import math
import time

import numpy as np

from gsi.errors import GsiInputError
from gsi.jit import njit, pjit, prange

__all__ = ["pair_particles", "pairing_cost", "Replay", "FEWallReplay", "voronoi_seeds",
           "cell_means",
           "cell_error", "cell_sampling_level", "energy_transfer_error", "period_errors",
           "compare_with_dem",
           "CaseExtrapolation", "DENSE_PAIRING_MAX"]

#: up to this many particles ``pair_particles(method="auto")`` solves the dense
#: assignment problem; above, the sparse auction with its check on all pairs (measured
#: by benchmarks/pairing.py on a drum-like bed, idle machine: dense 0.030 s at 2,000 and
#: 1.5 s at 10,000 particles, sparse 0.045 s and 0.12 s)
DENSE_PAIRING_MAX = 2_000


def pair_particles(x0, x1, *, method="auto", k=16, info=None):
    """The pairing f_ext of eq. 6: the permutation sigma minimising
    sum_a |x0[a] - x1[sigma[a]]| (Euclidean distances); exact (``dense``) or within a
    certified N (1e-14 * (bed size) + round-off margin) of the minimum (``sparse``).

    Parameters
    ----------
    x0, x1 : (N, 3) float
        Positions (m) of the same N particles at t0 and t1.
    method : {"auto", "dense", "sparse"}
        ``dense``: scipy.optimize.linear_sum_assignment on all N^2 distances (8 N^2
        bytes).  ``sparse``: Bertsekas' auction with eps-scaling (Bertsekas 1988,
        "The auction algorithm: a distributed relaxation method for the assignment
        problem") on a sparse graph -- the ``k`` nearest t1 positions of each particle,
        the ``k`` nearest particles of each t1 position, and one bijection so that a
        perfect matching exists --, then a check of eps-complementary slackness on all
        N^2 pairs (a grid over the t1 positions pruned by each cell's nearest point and
        lowest price): the 16 cheapest pairs of every row that breaks it join the graph
        and the auction goes on, until no row does.  eps-CS on all pairs bounds the
        summed distance above the minimum by N (eps + a margin for the round-off of
        the prices), eps = 1e-14 of the bed size (2.0e-9 m in total at 80,000 particles in
        a 0.6 m drum; the optimum of a sparse
        graph alone is not enough: after one turn of that drum, the 8-nearest graph
        made whole by the matching of its unmatched rows has its optimum at 1,455.9 m,
        the certified one is 1,232.6 m).  ``auto``: dense up to :data:`DENSE_PAIRING_MAX`
        particles.
    k : int
        Neighbours per particle of the first sparse graph.
    info : dict, optional
        Filled by ``sparse`` with ``rounds`` (auctions), ``edges`` (of the last graph)
        and ``gap_bound`` (m; N eps with a margin for round-off).

    Returns
    -------
    sigma : (N,) int64
        x1[sigma[a]] is the t1 position paired with x0[a].
    """
    from scipy.optimize import linear_sum_assignment
    x0 = np.asarray(x0, float)
    x1 = np.asarray(x1, float)
    n = len(x0)
    if x0.shape != x1.shape or x0.ndim != 2 or x0.shape[1] != 3:
        raise GsiInputError(f"pair_particles: x0 {x0.shape} and x1 {x1.shape} must both be "
                            "(N, 3)")
    if method not in ("auto", "dense", "sparse"):
        raise GsiInputError(f"pairing method = {method!r}: must be 'auto', 'dense' or "
                            "'sparse'")
    if method == "dense" or (method == "auto" and n <= DENSE_PAIRING_MAX):
        from scipy.spatial.distance import cdist
        rows, cols = linear_sum_assignment(cdist(x0, x1))
        sigma = np.empty(n, np.int64)
        sigma[rows] = cols
        return sigma
    return _sparse_pairing(x0, x1, min(k, n), info)


def _sparse_pairing(x0, x1, k, info=None):
    """The assignment through an auction on a growing sparse graph, certified on all
    N^2 pairs (see :func:`pair_particles`)."""
    from scipy.sparse import csr_matrix
    from scipy.spatial import cKDTree
    n = len(x0)
    scale = float(np.ptp(np.vstack([x0, x1]), axis=0).max()) or 1.0
    # the last auction phase's eps: the certified gap to the optimum is at most n eps
    # (plus the margin below); 1e-14 of the bed size is ~50 ulps of a price of the bed size
    # and ~2 of the largest price level on the 80,000-particle drum (~19 m, from its gap
    # bound); a raise too small to change a price moves it by one ulp: the auction ends
    eps = 1e-14 * scale
    _, j = cKDTree(x1).query(x0, k=k)
    _, i = cKDTree(x0).query(x1, k=k)
    # each particle's k nearest t1 positions, each t1 position's k nearest particles, and
    # one bijection (both sets ranked by height): the graph holds a perfect matching,
    # without which the auction would not end
    a = np.concatenate([np.repeat(np.arange(n), k), np.asarray(i).reshape(-1),
                        np.argsort(x0[:, 2], kind="stable")])
    b = np.concatenate([np.asarray(j).reshape(-1), np.repeat(np.arange(n), k),
                        np.argsort(x1[:, 2], kind="stable")])
    keys = np.unique(a * n + b)
    grid = _PriceGrid(x1)
    price = np.zeros(n)
    sigma = np.full(n, -1, np.int64)
    eps0 = 0.1 * scale
    rounds = 0
    while True:
        rounds += 1
        a, b = keys // n, keys % n
        G = csr_matrix((np.linalg.norm(x0[a] - x1[b], axis=1), (a, b)), shape=(n, n))
        G.sort_indices()                  # no duplicates: data = the distances
        _auction(G.indptr, G.indices.astype(np.int64), G.data, price, sigma, eps0, eps, 8.0)
        # pairs of all N^2 that break eps-complementary slackness (cheaper than sigma[a]
        # by more than eps): the cheapest of each such row join the graph
        # (less a margin of ~10 ulps for the round-off of the sums, which the gap bound
        # below includes)
        level = np.linalg.norm(x0 - x1[sigma], axis=1) + price[sigma]
        margin = eps + 1e-15 * (scale + float(np.abs(level).max()))
        rows, cols = grid.cheaper(x0, price, level - margin, 16)
        ra = np.repeat(rows, cols.shape[1])
        rb = cols.reshape(-1)
        ra, rb = ra[rb >= 0], rb[rb >= 0]
        new = ~np.isin(ra * n + rb, keys)
        if not new.any():
            break
        keys = np.union1d(keys, ra[new] * n + rb[new])
        if len(rows) > n // 100:          # many: a fresh auction from warm prices
            sigma[:] = -1
            eps0 = 1e-4 * scale
        else:                             # few: only those rows bid again
            sigma[rows] = -1
            eps0 = eps
    if info is not None:
        info.update(rounds=rounds, edges=len(keys), gap_bound=n * margin)
    return sigma


@njit
def _auction(indptr, indices, cost, price, sigma, eps0, eps_final, factor):
    """Bertsekas' forward auction with eps-scaling for the minimum-cost perfect matching
    of the bipartite graph of rows 0..n-1 (CSR ``indptr``, ``indices``: columns, ``cost``),
    which must hold one.  ``price`` (of the columns) and ``sigma`` (row -> column, -1
    unassigned) are updated in place; the rows of ``sigma`` with a column keep it in the
    first phase (they must satisfy eps0-CS), the others bid; each later phase starts
    afresh with eps divided by ``factor``, down to ``eps_final``.  At the end every row a
    holds sigma[a] with cost[a, sigma[a]] + price[sigma[a]] <= cost[a, b] + price[b] +
    eps_final for each of its columns b (eps-complementary slackness)."""
    n = price.shape[0]
    owner = np.empty(n, np.int64)
    queue = np.empty(n, np.int64)      # the rows without a column, a ring
    eps = max(eps0, eps_final)
    while True:
        owner[:] = -1
        waiting = 0
        for a in range(n):
            if sigma[a] >= 0:
                owner[sigma[a]] = a
            else:
                queue[waiting] = a
                waiting += 1
        head = 0
        tail = waiting if waiting < n else 0
        while waiting > 0:
            a = queue[head]
            head = head + 1 if head + 1 < n else 0
            waiting -= 1
            best = -1
            v1 = -np.inf                   # the best and second best -(cost + price)
            v2 = -np.inf
            for p in range(indptr[a], indptr[a + 1]):
                v = -cost[p] - price[indices[p]]
                if v > v1:
                    v2 = v1
                    v1 = v
                    best = indices[p]
                elif v > v2:
                    v2 = v
            if v2 == -np.inf:              # one column only: any raise keeps eps-CS
                v2 = v1 - eps0
            raised = price[best] + (v1 - v2 + eps)
            if raised == price[best]:
                raised = np.nextafter(raised, np.inf)
            price[best] = raised
            old = owner[best]
            owner[best] = a
            sigma[a] = best
            if old >= 0:
                sigma[old] = -1
                queue[tail] = old
                tail = tail + 1 if tail + 1 < n else 0
                waiting += 1
        if eps <= eps_final:
            return
        eps = max(eps / factor, eps_final)
        sigma[:] = -1


@pjit
def _cheapest(x0, xs, order, start, pmin, lo, cs, dims, price, low, out_b):
    """For each row a: the m = out_b.shape[1] columns b of lowest
    |x0[a] - x1[b]| + price[b] below low[a] (out_b[a], -1 where fewer).  ``xs``, ``order``,
    ``start``: the t1 positions binned by cell (:func:`gsi.dem.neighbour.bin_cells`);
    ``cs``: the cell sizes; a cell is skipped when its nearest point plus its lowest price
    ``pmin`` cannot beat the row's bound."""
    m = out_b.shape[1]
    p_lo = np.inf
    for c in range(pmin.shape[0]):
        p_lo = min(p_lo, pmin[c])
    for a in prange(x0.shape[0]):
        best = np.full(m, np.inf)
        for s in range(m):
            out_b[a, s] = -1
        rad = low[a] - p_lo
        if rad < 0.0:
            continue
        lo_i = np.empty(3, np.int64)
        hi_i = np.empty(3, np.int64)
        for d in range(3):              # clamped as floats: rad / cs may be huge
            lo_i[d] = int(min(max(math.floor((x0[a, d] - rad - lo[d]) / cs[d]), 0.0),
                              dims[d] - 1.0))
            hi_i[d] = int(min(max(math.floor((x0[a, d] + rad - lo[d]) / cs[d]), 0.0),
                              dims[d] - 1.0))
        for i in range(lo_i[0], hi_i[0] + 1):
            dx = max(lo[0] + i * cs[0] - x0[a, 0], 0.0, x0[a, 0] - lo[0] - (i + 1) * cs[0])
            for j in range(lo_i[1], hi_i[1] + 1):
                dy = max(lo[1] + j * cs[1] - x0[a, 1], 0.0, x0[a, 1] - lo[1] - (j + 1) * cs[1])
                for k in range(lo_i[2], hi_i[2] + 1):
                    c = (i * dims[1] + j) * dims[2] + k
                    if start[c] == start[c + 1]:
                        continue
                    dz = max(lo[2] + k * cs[2] - x0[a, 2], 0.0,
                             x0[a, 2] - lo[2] - (k + 1) * cs[2])
                    bound = min(low[a], best[m - 1])
                    if math.sqrt(dx * dx + dy * dy + dz * dz) + pmin[c] >= bound:
                        continue
                    for q in range(start[c], start[c + 1]):
                        ex = x0[a, 0] - xs[q, 0]
                        ey = x0[a, 1] - xs[q, 1]
                        ez = x0[a, 2] - xs[q, 2]
                        v = math.sqrt(ex * ex + ey * ey + ez * ez) + price[order[q]]
                        if v < low[a] and v < best[m - 1]:
                            s = m - 1
                            while s > 0 and best[s - 1] > v:
                                best[s] = best[s - 1]
                                out_b[a, s] = out_b[a, s - 1]
                                s -= 1
                            best[s] = v
                            out_b[a, s] = order[q]


class _PriceGrid:
    """The t1 positions in the cells of :func:`gsi.dem.neighbour.grid_for` (about 4 per
    cell), for the queries |x0[a] - x1[b]| + price[b] < level[a] over all b at once."""

    def __init__(self, x1):
        from gsi.dem.neighbour import bin_cells, cell_index, grid_for
        n = len(x1)
        self.lo = x1.min(axis=0)
        hi = x1.max(axis=0)
        # a flat set (all at one height, say) gets cells 1e-3 of its size across it
        span = np.maximum(hi - self.lo, max((hi - self.lo).max() * 1e-3, 1e-12))
        h = float(np.cbrt(np.prod(span) * 4.0 / n))
        self.dims, inv_cs = grid_for(self.lo, self.lo + span, h, n)
        self.cs = 1.0 / inv_cs
        self.cell = np.empty(n, np.int64)
        cell_index(n, x1, self.lo, inv_cs, self.dims, self.cell)
        self.start, self.order = bin_cells(n, self.cell, int(self.dims.prod()))
        self.xs = np.ascontiguousarray(x1[self.order])

    def cheaper(self, x0, price, level, m):
        """Rows a with some b where |x0[a] - x1[b]| + price[b] < level[a], and for each
        its m columns of lowest such value (rows, (len(rows), m) columns, -1 where fewer)."""
        pmin = np.full(len(self.start) - 1, np.inf)
        np.minimum.at(pmin, self.cell, price)
        cols = np.empty((len(x0), m), np.int64)
        _cheapest(x0, self.xs, self.order, self.start, pmin, self.lo, self.cs, self.dims,
                  price, level, cols)
        rows = np.flatnonzero(cols[:, 0] >= 0)
        return rows, cols[rows]


def pairing_cost(x0, x1, sigma) -> float:
    """sum_a |x0[a] - x1[sigma[a]]| (m)."""
    return float(np.linalg.norm(np.asarray(x0) - np.asarray(x1)[sigma], axis=1).sum())


@njit(inline="always")
def _particle_row(T, ka, kb, wr, Twr, inv_C):
    """One row of the replay: eqs. 7-8 between particles ka and kb (kb >= 0), or particle
    ka against a fixed-temperature wall at ``Twr`` (kb < 0)."""
    if kb >= 0:
        q = wr * (T[ka] - T[kb])
        T[ka] -= q * inv_C[ka]
        T[kb] += q * inv_C[kb]
    else:
        T[ka] += wr * (Twr - T[ka]) * inv_C[ka]


@njit
def _replay_rows(T, a, b, w, Tw, inv_C):
    """Apply the rows in order to T (the particles' temperatures in the log's frame:
    T[a] belongs to the particle playing logged particle a): eqs. 7-8 for b >= 0, a
    fixed-temperature wall ``Tw`` for b < 0."""
    for r in range(a.shape[0]):
        _particle_row(T, a[r], b[r], w[r], Tw[r], inv_C)


class Replay:
    """The heat extrapolation (Algorithm 3, eqs. 7-8) of a :class:`ContactLog`.

    Parameters
    ----------
    log : gsi.dem.contact_log.ContactLog
    sigma : (N,) int, optional
        The pairing (:func:`pair_particles`); default computed from ``log.x0``,
        ``log.x1`` (its time in :attr:`pairing_seconds`).
    on_unstable : {"substep", "error"}
        What a row breaking the stability bound m < C/H does (module docstring).
    pairing : str
        ``method`` of :func:`pair_particles`.
    fe_wall : int, optional
        Index (in the log) of a wall that is an FE heat structure: its rows are kept with
        b = -2 and their triangle for :class:`FEWallReplay` (plain :meth:`run` does not
        know them).

    Attributes
    ----------
    sigma : (N,) int64
    n_rows : int
        Rows replayed per period (after sub-steps; adiabatic wall rows dropped).
    n_substepped : int
        Log rows split into sub-steps by the stability bound.
    max_stability_ratio : float
        max over rows of m H/C (the bound is < 1).
    pairing_seconds, setup_seconds : float
    pairing_info : dict
        The sparse pairing's ``rounds``, ``edges``, ``gap_bound`` (:func:`pair_particles`;
        empty for the dense one or a given sigma).
    """

    def __init__(self, log, *, sigma=None, on_unstable="substep", pairing="auto",
                 fe_wall=None):
        if on_unstable not in ("substep", "error"):
            raise GsiInputError(f"on_unstable = {on_unstable!r}: must be 'substep' or 'error'")
        self.log = log
        t = time.perf_counter()
        self.pairing_info = {}
        self.sigma = (pair_particles(log.x0, log.x1, method=pairing, info=self.pairing_info)
                      if sigma is None else np.asarray(sigma, np.int64))
        self.pairing_seconds = time.perf_counter() - t
        n = log.n_particles
        if self.sigma.shape != (n,) or not np.array_equal(np.sort(self.sigma), np.arange(n)):
            raise GsiInputError(f"sigma: must be a permutation of 0..{n - 1}")
        t = time.perf_counter()
        C = np.asarray(log.heat_capacity, float)
        typ = log.type
        # particle-particle rows and the wall rows that exchange heat, in log order
        w_pp = (log.pp_dur * log.dt) * log.coef[typ[log.pp_i], typ[log.pp_j]] \
            * log.pp_size.astype(float)
        fe = (log.pw_wall == fe_wall) if fe_wall is not None else np.zeros(len(log.pw_wall),
                                                                            bool)
        keep = (log.wall_has_T[log.pw_wall] | fe) if len(log.pw_wall) else np.zeros(0, bool)
        pw_i, pw_wall = log.pw_i[keep], log.pw_wall[keep]
        w_pw = (log.pw_dur[keep] * log.dt) * log.coef[typ[pw_i], log.wall_type[pw_wall]] \
            * log.pw_size[keep].astype(float)
        start = np.concatenate([log.pp_start, log.pw_start[keep]])
        m = np.concatenate([log.pp_dur, log.pw_dur[keep]]) * log.dt
        a = np.concatenate([log.pp_i, pw_i]).astype(np.int32)
        b = np.concatenate([log.pp_j, np.where(fe[keep], -2, -1).astype(np.int32)]
                           ).astype(np.int32)
        w = np.concatenate([w_pp, w_pw])
        Tw = np.concatenate([np.zeros(len(w_pp)), log.wall_T[pw_wall]])
        tri = np.concatenate([np.full(len(w_pp), -1, np.int32),
                              log.pw_tri[keep].astype(np.int32)])
        order = np.argsort(start, kind="stable")      # pp rows are already in log order
        a, b, w, Tw, m = a[order], b[order], w[order], Tw[order], m[order]
        start, tri = start[order], tri[order]
        C_min = np.where(b >= 0, np.minimum(C[a], C[np.maximum(b, 0)]), C[a])
        ratio = w / C_min                              # m H/C: stable below 1
        self.max_stability_ratio = float(ratio.max()) if len(ratio) else 0.0
        bad = ratio >= 1.0
        self.n_substepped = int(bad.sum())
        if self.n_substepped and on_unstable == "error":
            r = int(np.argmax(ratio))
            m_max = float(np.min(m[ratio > 0] / ratio[ratio > 0]))
            raise GsiInputError(
                f"on_unstable = 'error': {self.n_substepped} rows of the contact log break "
                f"the stability bound m < C/H of the explicit replay (worst: row {r}, "
                f"m H/C = {ratio[r]:.3g}); log with dt_split < {m_max:.3g} s or replay "
                "with on_unstable = 'substep'")
        if self.n_substepped:
            s = np.where(bad, np.floor(ratio) + 1, 1).astype(np.int64)
            a, b, Tw = np.repeat(a, s), np.repeat(b, s), np.repeat(Tw, s)
            start, tri = np.repeat(start, s), np.repeat(tri, s)
            w = np.repeat(w / s, s)
        self._a, self._b, self._w, self._Tw = a, b, w, Tw
        self._start, self._tri = start, tri
        self.n_rows = len(a)
        # load (or compile) the kernel now, so that run() times the replay alone
        _replay_rows(np.zeros(1), a[:0], b[:0], w[:0], Tw[:0], np.ones(1))
        self.setup_seconds = time.perf_counter() - t

    def run(self, periods, *, T=None, positions=False):
        """Extrapolate ``periods`` periods from t1.

        Parameters
        ----------
        periods : int
        T : (N,) float, optional
            Temperatures at t1 (log order), default ``log.T1``.
        positions : bool
            Also return the extrapolated positions at each t_n.

        Returns
        -------
        dict
            ``T`` (periods + 1, N): temperatures of the logged particles (log order, by
            particle identity) at t1, t2, ...; ``time`` (periods + 1,) s; with
            ``positions``, ``x`` (periods + 1, N, 3) m; ``seconds``: replay wall time.
        """
        log = self.log
        n = log.n_particles
        T_real = np.array(log.T1 if T is None else T, float)
        if T_real.shape != (n,):
            raise GsiInputError(f"T: must have {n} temperatures (log order)")
        inv_C_real = 1.0 / np.asarray(log.heat_capacity, float)
        out_T = np.empty((periods + 1, n))
        out_T[0] = T_real
        out_x = np.empty((periods + 1, n, 3)) if positions else None
        if positions:
            out_x[0] = log.x1
        role = np.arange(n)              # role[a]: the particle playing a at the last t_n
        t = time.perf_counter()
        for p in range(1, periods + 1):
            role = role[self.sigma]      # sigma^p
            Tt = T_real[role]
            _replay_rows(Tt, self._a, self._b, self._w, self._Tw, inv_C_real[role])
            T_real[role] = Tt
            out_T[p] = T_real
            if positions:
                out_x[p][role] = log.x1
        seconds = time.perf_counter() - t
        res = {"T": out_T, "time": log.t1 + log.period * np.arange(periods + 1),
               "seconds": seconds}
        if positions:
            res["x"] = out_x
        return res

    def positions(self, periods):
        """Extrapolated positions (periods + 1, N, 3) (m) at t1, t2, ... (log order)."""
        n = self.log.n_particles
        out = np.empty((periods + 1, n, 3))
        out[0] = self.log.x1
        role = np.arange(n)
        for p in range(1, periods + 1):
            role = role[self.sigma]
            out[p][role] = self.log.x1
        return out


@njit
def _replay_rows_fe(T, a, b, w, Tw, inv_C, tri, r0, r1, tn, tw, hn, hw, T_nodes, node_heat):
    """Rows r0..r1 - 1 of :func:`_replay_rows`, and rows with b = -2 against an FE wall:
    the particle exchanges H m (T_w - T) with the wall at T_w = sum_j tw[t, j]
    T_nodes[tn[t, j]] (t = tri[r]), and that heat leaves the wall nodes hn[t, j] in the
    shares hw[t, j] (``node_heat``, J into the wall)."""
    for r in range(r0, r1):
        ka = a[r]
        if b[r] >= -1:
            _particle_row(T, ka, b[r], w[r], Tw[r], inv_C)
        else:
            t = tri[r]
            Tn = 0.0
            for j in range(tn.shape[1]):
                Tn += tw[t, j] * T_nodes[tn[t, j]]
            q = w[r] * (Tn - T[ka])
            T[ka] += q * inv_C[ka]
            for j in range(hn.shape[1]):
                node_heat[hn[t, j]] -= q * hw[t, j]


def _rotate(x, axis, centre, angle):
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
    structure : gsi.coupling.structure.CoupledStructure
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
                _rotate(self._centroids, self.axis, self.centre, -phi))[1], np.int32)
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


def _finite_max(a):
    """Largest finite value of ``a``, NaN if none (a cell level is NaN where no cell
    holds two particles)."""
    a = np.asarray(a, float)
    a = a[np.isfinite(a)]
    return float(a.max()) if a.size else math.nan


def voronoi_seeds(x, count=200, *, seed=0):
    """``count`` seed points of the Voronoi cells of eq. 9: positions of distinct
    particles drawn at random (generator ``seed``) from ``x`` (m), so every cell lies in
    the bed."""
    x = np.asarray(x, float)
    if count > len(x):
        raise GsiInputError(f"voronoi cells = {count}: more than the {len(x)} particles")
    rng = np.random.default_rng(seed)
    return x[rng.choice(len(x), count, replace=False)]


def _cell_index(seeds, x):
    """The Voronoi cell (nearest seed) of each position."""
    from scipy.spatial import cKDTree
    return cKDTree(seeds).query(np.asarray(x, float))[1]


def cell_means(seeds, x, T):
    """Mean of T over the particles of each Voronoi cell (nearest seed); NaN where a
    cell holds none.  Returns (means (v,), counts (v,))."""
    cell = _cell_index(seeds, x)
    v = len(seeds)
    count = np.bincount(cell, minlength=v)
    total = np.bincount(cell, weights=np.asarray(T, float), minlength=v)
    with np.errstate(invalid="ignore", divide="ignore"):
        return total / count, count


def cell_error(seeds, x_dem, T_dem, x_ext, T_ext, *, hot=None):
    """The error of eq. 9 on the Voronoi cells of ``seeds``.

    eps_abs = (1/v) sum_cells |mean T_DEM - mean T_extra| over the v cells that hold
    particles in both fields; eps_rel = eps_abs/|T_hot - T_cold| with T_hot, T_cold the
    DEM means of the particles flagged ``hot`` and the others (if given).

    Returns
    -------
    (eps_abs, eps_rel, cells_used)
    """
    m_dem, c_dem = cell_means(seeds, x_dem, T_dem)
    m_ext, c_ext = cell_means(seeds, x_ext, T_ext)
    both = (c_dem > 0) & (c_ext > 0)
    eps_abs = float(np.abs(m_dem[both] - m_ext[both]).mean())
    eps_rel = np.nan
    if hot is not None:
        hot = np.asarray(hot, bool)
        diff = abs(float(np.mean(T_dem[hot]) - np.mean(T_dem[~hot])))
        eps_rel = eps_abs / diff if diff > 0 else np.inf
    return eps_abs, eps_rel, int(both.sum())


def cell_sampling_level(seeds, x_dem, T_dem, x_ext, T_ext):
    """The eq.-9 error (K) of two fields whose cells hold independent samples of the same
    temperatures: (1/v) sum_cells sqrt(2/pi) sqrt(s_DEM^2/n_DEM + s_extra^2/n_extra),
    over the cells with at least two particles in both fields (NaN if none), where s^2 is
    the variance of the particle temperatures in the cell and n their count.

    sqrt(2/pi) sigma is the mean of |X| for X normal with standard deviation sigma, and
    s^2/n the variance of a mean of n independent draws: an extrapolation that puts the
    right temperatures in each cell, but other particles than the DEM's, has eps_abs near
    this level (within a few per cent on 200 cells), one that also reproduces the
    particles has less, and a biased one more.  The level grows with the spread of the
    temperatures inside a cell (how finely the bed interleaves hot and cold) and falls as
    1/sqrt(particles per cell).
    """
    def moments(x, T):
        cell = _cell_index(seeds, x)
        T = np.asarray(T, float)
        v = len(seeds)
        n = np.bincount(cell, minlength=v).astype(float)
        s1 = np.bincount(cell, weights=T, minlength=v)
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = s1 / n
            dev2 = np.bincount(cell, weights=(T - mean[cell]) ** 2, minlength=v)
            return n, dev2 / (n - 1.0)

    n_d, s2_d = moments(x_dem, T_dem)
    n_e, s2_e = moments(x_ext, T_ext)
    ok = (n_d > 1) & (n_e > 1)
    if not ok.any():
        return math.nan
    return float(np.mean(math.sqrt(2.0 / math.pi)
                         * np.sqrt(s2_d[ok] / n_d[ok] + s2_e[ok] / n_e[ok])))


def energy_transfer_error(T_dem_n, T_dem_next, T_ext_n, T_ext_next):
    """eq. 10: (sum |T_{n+1} - T_n| - sum |T^ext_{n+1} - T^ext_n|)/sum |T_{n+1} - T_n|,
    sums over the particles (by identity); signed (positive: the extrapolation moves
    less heat than the DEM)."""
    dem = float(np.abs(np.asarray(T_dem_next) - T_dem_n).sum())
    ext = float(np.abs(np.asarray(T_ext_next) - T_ext_n).sum())
    return (dem - ext) / dem


def period_errors(log, res, T_dem, x_dem, seeds, hot):
    """The errors at t_2 ... t_{P+1} of a replay ``res`` (:meth:`Replay.run` with
    positions) against the DEM's ``T_dem``, ``x_dem`` (P + 1, N, ...) from t1 (log
    order): eq. 9 (``eps_abs`` K, ``eps_rel``), its sampling level on the same cells
    (``eps_level`` K, :func:`cell_sampling_level`), eq. 10 (``energy_error``), and the
    drift of sum m c_p T of the replay relative to t1 (``energy_drift``, P + 1 values)."""
    eps_abs, eps_rel, eps_e, level = [], [], [], []
    for n in range(1, len(T_dem)):
        ea, er, _ = cell_error(seeds, x_dem[n], T_dem[n], res["x"][n], res["T"][n], hot=hot)
        eps_abs.append(ea)
        eps_rel.append(er)
        level.append(cell_sampling_level(seeds, x_dem[n], T_dem[n], res["x"][n],
                                         res["T"][n]))
        eps_e.append(energy_transfer_error(T_dem[n - 1], T_dem[n], res["T"][n - 1],
                                           res["T"][n]))
    E = res["T"] @ log.heat_capacity
    return dict(eps_abs=np.array(eps_abs), eps_rel=np.array(eps_rel),
                eps_level=np.array(level), energy_error=np.array(eps_e),
                energy_drift=np.abs(E - E[0]) / abs(E[0]))


def compare_with_dem(sim, *, period_steps, periods, samplings=((1, None),), hot=None,
                     cells=200, seed=0, log_dir=None, twin=None, say=None):
    """Extrapolate from one logged period of ``sim`` and compare with its own full DEM.

    From the state of ``sim`` (t0): for each ``(every, dt_split)`` of ``samplings``, log
    the period t0..t1 (``period_steps`` steps) and replay it for ``periods`` periods;
    the first sampling's run then continues as the reference DEM to t1 + periods tau
    (the others restart from the state at t0: the DEM is deterministic, so their t1 is
    the same, which is checked).

    Errors at each t_{n+1} (n = 1..periods): eq. 9 on ``cells`` Voronoi cells whose seeds
    are the positions at t1 of ``cells`` particles drawn at random (generator ``seed``;
    the extrapolated configuration at every t_n is that of t1, relabelled), absolute and
    relative to |T_hot - T_cold| (DEM means of the particles flagged ``hot``, by id);
    eq. 10 from t_n to t_{n+1}; the drift of sum C T of the replay and of the DEM
    relative to its value at t1.

    ``twin`` (m): also run a second DEM from the state at t1 with every position moved by
    a random amount up to ``twin`` in each coordinate, and give eq. 9 between the two
    DEMs at each t_{n+1} (``dem["twin"]``: ``eps_abs``, ``eps_level``): the error of a
    prediction as good as the DEM itself, which the flow's chaos alone sets (0 for
    ``twin = 0``: the DEM is deterministic).

    Returns
    -------
    dict
        ``dem``: reference (``T``, ``x`` (periods + 1, N, ...) by log order, ``seconds``
        (wall) and ``cpu`` (process CPU time) per period, ``energy_drift``, ``twin``
        if asked); ``runs``:
        per sampling a dict with ``every``,
        ``dt_split``, ``log`` (the :class:`ContactLog`), ``log_seconds`` (the DEM period
        with the log on), ``file_bytes``, ``file_seconds``, ``pairing_seconds``,
        ``replay_setup_seconds`` (once, with the pairing), ``replay_seconds`` (per
        period), CPU times ``log_cpu``, ``setup_cpu``, ``replay_cpu``, ``T``, ``x``,
        ``eps_abs``, ``eps_rel``,
        ``energy_error`` (eq. 10), ``energy_drift``, ``n_substepped``,
        ``max_stability_ratio``, ``same_t1``.
    """
    import pathlib
    say = say or (lambda *a: None)
    state0 = sim.state()
    runs = []
    dem = None
    seeds = None
    for k, (every, dt_split) in enumerate(samplings):
        if k:
            sim.set_state(state0)
        t, c = time.perf_counter(), time.process_time()
        sim.start_contact_log(every=every, dt_split=dt_split)
        sim.step(period_steps)
        log = sim.stop_contact_log()
        run = {"every": every, "dt_split": dt_split, "log": log,
               "log_seconds": time.perf_counter() - t, "log_cpu": time.process_time() - c}
        say(f"logged t0..t1 with every = {every}, dt_split = {dt_split}: "
            f"{log.n_collisions} rows in {run['log_seconds']:.1f} s")
        hot_log = None if hot is None else np.asarray(hot)[log.ids]
        if dem is None:
            state1 = sim.state() if twin is not None else None
            t, c = time.perf_counter(), time.process_time()
            T_dem, x_dem = _dem_periods(sim, log.ids, period_steps, periods,
                                        lambda p: say(f"reference DEM: period {p}/{periods}"))
            C = log.heat_capacity
            E = np.array([float(C @ T) for T in T_dem])
            dem = {"T": T_dem, "x": x_dem,
                   "seconds": (time.perf_counter() - t) / periods,
                   "cpu": (time.process_time() - c) / periods,
                   "energy_drift": np.abs(E - E[0]) / abs(E[0]), "T1": log.T1}
            seeds = voronoi_seeds(log.x1, cells, seed=seed)
        run["same_t1"] = bool(np.array_equal(log.T1, dem["T1"]))
        if log_dir is not None:
            path = pathlib.Path(log_dir) / f"contact_log_every{every}.npz"
            path.parent.mkdir(parents=True, exist_ok=True)
            t = time.perf_counter()
            run["file_bytes"] = log.save(path)
            run["file_seconds"] = time.perf_counter() - t
        c = time.process_time()
        rep = Replay(log)
        c_setup = time.process_time() - c
        c = time.process_time()
        res = rep.run(periods, positions=True)
        run["replay_cpu"] = (time.process_time() - c) / periods
        run["setup_cpu"] = c_setup
        run.update(pairing_seconds=rep.pairing_seconds, pairing_info=rep.pairing_info,
                   replay_setup_seconds=rep.setup_seconds,
                   replay_seconds=res["seconds"] / periods,
                   n_substepped=rep.n_substepped, max_stability_ratio=rep.max_stability_ratio,
                   T=res["T"], x=res["x"], n_rows=rep.n_rows)
        run.update(period_errors(log, res, dem["T"], dem["x"], seeds, hot_log))
        runs.append(run)
        say(f"every = {every}: eps_abs max {run['eps_abs'].max():.3g} K, eps_rel max "
            f"{np.nanmax(run['eps_rel']):.3g}, eq. 10 max "
            f"|{np.abs(run['energy_error']).max():.3g}|")
    if twin is not None:
        # a second DEM from t1, every position moved by up to ``twin`` (m): as valid a
        # run as the reference, and as far from it after a period as chaos alone makes it
        sim.set_state(state1)
        rng = np.random.default_rng(seed)
        sim.x[:] += rng.uniform(-twin, twin, sim.x.shape)
        T_tw, x_tw = _dem_periods(sim, log.ids, period_steps, periods,
                                  lambda p: say(f"twin DEM: period {p}/{periods}"))
        dem["twin"] = {
            "amplitude": twin,
            "eps_abs": np.array([cell_error(seeds, dem["x"][n], dem["T"][n], x_tw[n],
                                            T_tw[n])[0] for n in range(1, periods + 1)]),
            "eps_level": np.array([cell_sampling_level(seeds, dem["x"][n], dem["T"][n],
                                                       x_tw[n], T_tw[n])
                                   for n in range(1, periods + 1)])}
    return {"dem": dem, "runs": runs, "seeds": seeds}


def _dem_periods(sim, ids, period_steps, periods, say):
    """Temperatures and positions of the particles ``ids`` (in that order) now and after
    each of ``periods`` periods of DEM: two arrays (periods + 1, N[, 3])."""
    rows = sim.index(ids)
    T = [sim.T[rows].copy()]
    x = [sim.x[rows].copy()]
    for p in range(periods):
        sim.step(period_steps)
        rows = sim.index(ids)
        T.append(sim.T[rows].copy())
        x.append(sim.x[rows].copy())
        say(p + 1)
    return np.array(T), np.array(x)


class CaseExtrapolation:
    """The ``[extrapolation]`` table of a case, run by :class:`gsi.runner.Runner`.

    Parameters
    ----------
    spec : gsi.case.extrapolation.Extrapolation
    dt : float
        DEM step (s).
    out : pathlib.Path
        Output directory (``contact_log.npz``, ``extrapolation.csv``, pictures).
    structure : gsi.coupling.structure.CoupledStructure, optional
        The kiln wall (a thermal-only structure): the replay is :class:`FEWallReplay`, the
        structure's heat returns to its state at t1 after it (the live run goes on).
    """

    def __init__(self, spec, *, dt, out, structure=None):
        self.spec = spec
        self.out = out
        self.structure = structure
        self.n_cmp = spec.n_compare
        self.K = int(round(spec.period / dt))
        self.k_halves = None if spec.halves is None else int(round(spec.halves.t / dt))
        self.k0 = int(round(spec.start / dt))
        self.k1 = self.k0 + self.K
        self.steps = ([] if self.k_halves is None else [self.k_halves]) + [self.k0, self.k1]
        self.steps += [self.k1 + p * self.K for p in range(1, self.n_cmp + 1)]
        self.hot = None
        self.log = None
        self.res = None
        self.dem_T, self.dem_x = [], []
        self.t0_state = None
        self.times = {}

    def at_step(self, k, sim, say=print):
        """Act at DEM step ``k`` (call after every chunk; only event steps do anything)."""
        s = self.spec
        if k == self.k_halves:
            h = s.halves
            d = "xyz".index(h.axis)
            below = sim.x[:, d] < h.at
            sim.T[:] = np.where(below, h.below, h.above)
            self.hot = np.zeros(int(sim.ids.max()) + 1, bool)
            self.hot[sim.ids] = below if h.below >= h.above else ~below
        if k == self.k0:
            order = np.argsort(sim.ids, kind="stable")
            self.t0_state = (sim.x[order].copy(), sim.T[order].copy())
            sim.start_contact_log(every=s.every, dt_split=s.dt_split)
            self.times["log_start"] = time.perf_counter()
        if k == self.k1:
            self.log = sim.stop_contact_log()
            t = time.perf_counter()
            self.times["collision_file_s"] = t - self.times.pop("log_start")
            self.times["file_bytes"] = self.log.save(self.out / "contact_log.npz")
            if self.structure is None:
                rep = Replay(self.log)
                self.res = rep.run(s.periods, positions=True)
            else:
                rep, self.res = self._replay_kiln(sim, say)
            self.times.update(pairing_s=rep.pairing_seconds, replay_setup_s=rep.setup_seconds,
                              extrap_s_per_period=self.res["seconds"] / s.periods,
                              rows=rep.n_rows)
            say(f"extrapolation: {self.log.n_collisions} collisions logged "
                f"({self.log.bytes_per_collision():.1f} bytes each), {s.periods} periods "
                f"extrapolated in {self.res['seconds']:.3g} s")
            self.times["dem_start"] = time.perf_counter()
        if s.compare and k >= self.k1 and (k - self.k1) % self.K == 0 and \
                len(self.dem_T) <= self.n_cmp and self.log is not None:
            rows = sim.index(self.log.ids)
            self.dem_T.append(sim.T[rows].copy())
            self.dem_x.append(sim.x[rows].copy())
            if self.structure is not None:
                self.dem_wall.append(self.structure.heat.stored_heat())
            if len(self.dem_T) == self.n_cmp + 1:
                self.times["dem_s_per_period"] = \
                    (time.perf_counter() - self.times.pop("dem_start")) / self.n_cmp

    def _replay_kiln(self, sim, say):
        """The replay with the FE wall (:class:`FEWallReplay`) from t1; the structure's
        heat is put back to its state at t1 afterwards.  Returns (replay, result) with
        ``T``, ``x`` of the periods 0..n_cmp (and the last) in the form of
        :meth:`Replay.run`."""
        st, s = self.structure, self.spec
        w = st.wall._w
        M = sim.mesh_state
        saved = st.heat.state()
        rep = FEWallReplay(self.log, st, fe_wall=sim._npl + w, omega=M.wall_omega[w].copy(),
                           centre=M.wall_centre[w].copy())
        hot = None if self.hot is None else self.hot[self.log.ids]
        keep = sorted(set(range(self.n_cmp + 1)) | {s.periods})
        res = rep.run(s.periods, store=keep, hot=hot, say=say)
        st.heat.set_state(saved)
        res["stored_periods"] = keep
        res["T"] = np.array([res["stored"][p][0] for p in keep])
        res["x"] = np.array([res["stored"][p][1] for p in keep])
        self.dem_wall = []
        say(f"kiln replay: {s.periods} periods ({s.periods * self.log.period / 3600:.3g} h) "
            f"in {res['seconds']:.3g} s ({res['fe_seconds']:.3g} s FE), energy balance "
            f"{res['balance']:.2g} relative")
        return rep, res

    def finish(self, name="case"):
        """Write ``extrapolation.csv`` and the pictures; return the summary numbers."""
        s, log, res = self.spec, self.log, self.res
        if log is None:
            return {}
        n, c = s.periods, self.n_cmp
        kiln = self.structure is not None
        hot = None if self.hot is None else self.hot[log.ids]
        full = c > 0 and len(self.dem_T) == c + 1
        err = {}
        if full:
            seeds = voronoi_seeds(log.x1, min(s.cells, log.n_particles), seed=0)
            window = {"T": res["T"][:c + 1], "x": res["x"][:c + 1]}
            err = period_errors(log, window, np.array(self.dem_T), np.array(self.dem_x),
                                seeds, hot)
            self._seeds = seeds
        C = log.heat_capacity

        def pad(v):
            out = np.full(n + 1, np.nan)
            out[:len(v)] = v
            return out

        cols = {"time_s": res["time"]}
        if hot is not None:
            if kiln:
                cols["T_hot_extra"], cols["T_cold_extra"] = res["T_hot"], res["T_cold"]
            else:
                cols["T_hot_extra"] = res["T"][:, hot].mean(1)
                cols["T_cold_extra"] = res["T"][:, ~hot].mean(1)
            if full:
                D = np.array(self.dem_T)
                cols["T_hot_dem"] = pad(D[:, hot].mean(1))
                cols["T_cold_dem"] = pad(D[:, ~hot].mean(1))
        cols["T_mean_extra"] = res["T_mean"] if kiln else res["T"] @ C / C.sum()
        if full:
            cols["T_mean_dem"] = pad(np.array(self.dem_T) @ C / C.sum())
            for key in ("eps_abs", "eps_level", "eps_rel", "energy_error"):
                cols[key] = pad(np.concatenate([[np.nan], err[key]]))
            cols["energy_drift"] = pad(err["energy_drift"])
        if kiln:
            st = self.structure
            m = st.heat.material
            cols["T_wall_mean_extra"] = res["T_wall_mean"]
            if full:
                cols["T_wall_mean_dem"] = pad(np.array(self.dem_wall)
                                              / (m.rho * m.c * st.heat.volume()))
            cols["E_particles_extra"] = res["E_particles"]
            cols["E_structure_extra"] = res["E_structure"]
            cols["Q_boundary_extra"] = res["Q_boundary"]
            cols["Q_wall_extra"] = res["Q_wall"]
        with open(self.out / "extrapolation.csv", "w") as f:
            f.write(",".join(cols) + "\n")
            for r in range(n + 1):
                f.write(",".join(f"{cols[k][r]:.17g}" for k in cols) + "\n")
        summary = {"extrap_collisions": log.n_collisions,
                   "extrap_bytes_per_collision": round(log.bytes_per_collision(), 2),
                   "extrap_s_per_period": self.times["extrap_s_per_period"],
                   "pairing_s": self.times["pairing_s"],
                   "replay_setup_s": self.times["replay_setup_s"],
                   "collision_file_s": self.times["collision_file_s"]}
        if full:
            summary.update(dem_s_per_period=self.times["dem_s_per_period"],
                           speedup_per_period=self.times["dem_s_per_period"]
                           / self.times["extrap_s_per_period"],
                           eps_abs_max=float(err["eps_abs"].max()),
                           eps_over_level_max=_finite_max(err["eps_abs"]
                                                          / err["eps_level"]),
                           eps_rel_max=float(np.nanmax(err["eps_rel"])),
                           energy_err_max=float(np.abs(err["energy_error"]).max()),
                           energy_drift_max=float(err["energy_drift"].max()))
        if kiln:
            hours = n * log.period / 3600.0
            summary.update(
                extrap_hours=hours, bed_T_t1=float(res["T_mean"][0]),
                bed_T_end=float(res["T_mean"][-1]),
                wall_T_end=float(res["T_wall_mean"][-1]),
                wall_heat_flow_W=float(res["Q_wall"][1:].sum() / (n * log.period)),
                boundary_heat_flow_W=float(res["Q_boundary"][-1] / (n * log.period)),
                energy_balance_rel=res["balance"])
            if full:
                dT = np.array(self.dem_wall) / (m.rho * m.c * st.heat.volume()) \
                    - res["T_wall_mean"][:c + 1]
                summary["wall_T_err_max"] = float(np.abs(dT).max())
        self.cols = cols
        self.err = err
        self.files = [self.out / "extrapolation.csv", self.out / "contact_log.npz"]
        return summary

    def pictures(self, name="case", view="iso"):
        """The temperature fields at t0, t1 and the last t_n (full DEM and extrapolated,
        projected along the axis of ``view`` -- "+y" looks along y -- or, for "iso", the
        axis the bed spreads least over), the group means against time, and the
        Voronoi-cell error map at the last t_n; returns the files."""
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        log, res, cols = self.log, self.res, self.cols
        if log is None:
            return []
        full = self.n_cmp > 0 and len(self.dem_T) == self.n_cmp + 1
        x0, T0 = self.t0_state
        drop = "xyz".index(view[1]) if view[0] in "+-" else int(np.argmin(np.ptp(log.x1, 0)))
        u, v = [d for d in range(3) if d != drop]
        files = []
        last = self.n_cmp if full else len(res["x"]) - 1
        label = res.get("stored_periods", range(len(res["x"])))[last] + 1
        lo = min(T0.min(), log.T1.min())
        hi = max(T0.max(), log.T1.max())
        panels = [("full DEM, t0", x0, T0), ("full DEM, t1", log.x1, log.T1)]
        if full:
            panels.append((f"full DEM, t{last + 1}", self.dem_x[last], self.dem_T[last]))
        panels += [("extrapolated, t0 (= DEM)", x0, T0), ("extrapolated, t1 (= DEM)", log.x1,
                                                          log.T1),
                   (f"extrapolated, t{label}", res["x"][last], res["T"][last])]
        ncol = 3
        fig, axes = plt.subplots(2 if full else 1, ncol, figsize=(4 * ncol, 3.8 * (2 if full
                                                                                   else 1)),
                                 squeeze=False)
        if not full:
            panels = panels[2:]
        allx = np.vstack([p[1] for p in panels])
        pad = 0.03 * np.ptp(allx, axis=0)
        for ax, (title, x, T) in zip(axes.ravel(), panels):
            sc = ax.scatter(x[:, u], x[:, v], c=T, s=6, cmap="coolwarm", vmin=lo, vmax=hi)
            ax.set_title(title, fontsize=9)
            ax.set_xlim(allx[:, u].min() - pad[u], allx[:, u].max() + pad[u])
            ax.set_ylim(allx[:, v].min() - pad[v], allx[:, v].max() + pad[v])
            ax.set_aspect("equal")
            ax.set_xticks([])
            ax.set_yticks([])
        fig.colorbar(sc, ax=axes.ravel().tolist(), shrink=0.8, label="T (K)")
        fig.savefig(self.out / "extrapolation_fields.png", dpi=90)
        plt.close(fig)
        files.append(self.out / "extrapolation_fields.png")
        if "T_hot_extra" in cols:
            fig, ax = plt.subplots(figsize=(6, 4))
            t = cols["time_s"]
            mk = "o--" if len(t) <= 60 else "--"
            ax.plot(t, cols["T_hot_extra"], mk, color="tab:red", label="hot, extrapolated")
            ax.plot(t, cols["T_cold_extra"], mk, color="tab:blue", label="cold, extrapolated")
            if "T_hot_dem" in cols:
                ax.plot(t, cols["T_hot_dem"], "-", color="tab:red", label="hot, full DEM")
                ax.plot(t, cols["T_cold_dem"], "-", color="tab:blue", label="cold, full DEM")
            ax.set_xlabel("time (s)")
            ax.set_ylabel("mean temperature (K)")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
            ax.set_title(f"{name}: mean temperature of the initially hot and cold halves",
                         fontsize=9)
            fig.tight_layout()
            fig.savefig(self.out / "extrapolation_means.png", dpi=90)
            plt.close(fig)
            files.append(self.out / "extrapolation_means.png")
        if full:
            seeds = self._seeds
            m_dem, c_dem = cell_means(seeds, self.dem_x[last], self.dem_T[last])
            m_ext, c_ext = cell_means(seeds, res["x"][last], res["T"][last])
            ok = (c_dem > 0) & (c_ext > 0)
            fig, ax = plt.subplots(figsize=(5.5, 4.5))
            ax.scatter(log.x1[:, u], log.x1[:, v], s=3, color="0.85")
            sc = ax.scatter(seeds[ok, u], seeds[ok, v], c=np.abs(m_dem - m_ext)[ok], s=40,
                            cmap="viridis", edgecolors="k", linewidths=0.3)
            fig.colorbar(sc, ax=ax, label="|mean T_DEM - mean T_extra| (K)")
            ax.set_aspect("equal")
            ax.set_xticks([])
            ax.set_yticks([])
            ax.set_title(f"eq. 9 per Voronoi cell at t{last + 1} ({ok.sum()} cells, "
                         f"seeds shown)", fontsize=9)
            fig.savefig(self.out / "extrapolation_cells.png", dpi=90)
            plt.close(fig)
            files.append(self.out / "extrapolation_cells.png")
        if self.structure is not None:
            files.append(self.hours_picture(name))
        return files

    def hours_picture(self, name="case"):
        """``extrapolation_hours.png``: the bed's (m c_p-weighted) mean temperature --
        left in the live DEM + FE window (the coupling records, from the moment the
        halves are set, with the extrapolated t_n in it), right against hours of physical
        time on a log axis, the live run beside the extrapolated hours, with the shell's
        mean and the initially hot and cold halves; returns the file."""
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        cols, log = self.cols, self.log
        recs = self.structure.thermal.records
        t_live = np.array([r.t for r in recs])
        bed_live = np.array([r.T_particles_mean for r in recs])
        wall_live = np.array([r.T_wall_mean for r in recs])
        t_set = self.spec.halves.t if self.spec.halves is not None else 0.0
        after = t_live > t_set + 1e-9
        t = cols["time_s"]
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4),
                                     gridspec_kw=dict(width_ratios=[1, 1.6]))
        a1.plot(t_live[after], bed_live[after], "-", color="tab:orange",
                label="bed, DEM + FE")
        win = t <= t_live[-1] + 1e-9
        a1.plot(t[win], cols["T_mean_extra"][win], "o", mfc="none", color="tab:orange",
                label="bed, extrapolated")
        a1.axvspan(log.t0, log.t1, color="tab:green", alpha=0.15, label="logged period")
        a1.set_xlabel("time (s)")
        a1.set_ylabel("bed mean temperature (K)")
        a1.set_title(f"live run window (shell mean {wall_live[-1]:.2f} K)", fontsize=9)
        a1.grid(alpha=0.3)
        a1.legend(fontsize=7)
        h = t / 3600.0
        a2.axvspan(t_live[after][0] / 3600.0, t_live[-1] / 3600.0, color="tab:green",
                   alpha=0.15, label="live DEM + FE window")
        a2.plot(t_live[after] / 3600.0, bed_live[after], "-", lw=3, color="tab:orange",
                alpha=0.6, label="bed, DEM + FE")
        a2.plot(h, cols["T_mean_extra"], "--", color="tab:orange", label="bed, extrapolated")
        a2.plot(h, cols["T_wall_mean_extra"], "-", color="0.3", label="shell, extrapolated")
        if "T_hot_extra" in cols:
            a2.plot(h, cols["T_hot_extra"], ":", color="tab:red", lw=1,
                    label="initially hot half")
            a2.plot(h, cols["T_cold_extra"], ":", color="tab:blue", lw=1,
                    label="initially cold half")
        a2.set_xscale("log")
        a2.set_xlabel("physical time (h)")
        a2.set_ylabel("mean temperature (K)")
        a2.set_title(f"{name}: {len(t) - 1} periods of {log.period:.4g} s extrapolated "
                     f"({h[-1]:.3g} h)", fontsize=9)
        a2.grid(alpha=0.3, which="both")
        a2.legend(fontsize=7)
        fig.tight_layout()
        path = self.out / "extrapolation_hours.png"
        fig.savefig(path, dpi=90)
        plt.close(fig)
        return path
