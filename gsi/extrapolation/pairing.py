"""Pairing of the particles at t0 and t1 (Haydar, Martin & Bonnefoy 2023, eq. 6): the
bijection sigma minimising sum_a |x_a(t0) - x_sigma(a)(t1)|, dense (scipy) or by a sparse
auction on a k-nearest graph with a check on all pairs (:func:`pair_particles`)."""
from __future__ import annotations

import math

import numpy as np

from gsi.errors import GsiInputError
from gsi.jit import njit, pjit, prange


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
        from gsi.dem.cells import bin_cells, cell_index, grid_for
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


