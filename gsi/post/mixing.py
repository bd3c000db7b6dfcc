"""Mixing index of two particle species: Lacey's index on a grid of sample cells.

Lacey (1954), "Developments in the theory of particle mixing", J. Appl. Chem. 4, 257:

    M = (s0^2 - s^2) / (s0^2 - sr^2)

with ``p`` the number fraction of species A among the sampled particles, ``s^2`` the
variance of the fraction of A over the sample cells, ``s0^2 = p (1 - p)`` its value when
the species are fully segregated and ``sr^2 = p (1 - p) / n`` its value for a random
mixture of cells of ``n`` particles. M = 0: segregated, M = 1: randomly mixed.

The cells are a regular grid over a box; cells holding fewer than ``min_count`` particles
are left out (their fraction is mostly noise). ``s^2`` is weighted by the particle count
of each cell and ``n`` is the mean count of the cells kept, the usual choice for cells of
unequal occupation (e.g. a rotating drum's bed: full cells in its core, few at its
surface).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["lacey_index"]


def lacey_index(x, is_a, lo, hi, cells, *, min_count: int = 4) -> tuple[float, int, float]:
    """Lacey's mixing index of the particles at ``x`` (k, 3) (m).

    Parameters
    ----------
    x : (k, 3) array
        Particle centres (m); those outside the box ``lo``..``hi`` are ignored.
    is_a : (k,) bool array
        True for the particles of species A.
    lo, hi : sequence of 3 float
        Corners of the sampled box (m).
    cells : sequence of 3 int
        Sample cells along x, y, z.
    min_count : int
        Cells with fewer particles are left out.

    Returns
    -------
    (M, n_cells, n_mean): the index (nan if no cell is kept or only one species is
    present), the number of cells kept and their mean particle count.
    """
    x = np.asarray(x, float)
    is_a = np.asarray(is_a, bool)
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    nc = np.asarray(cells, int)
    inside = np.all((x >= lo) & (x < hi), axis=1)
    x, is_a = x[inside], is_a[inside]
    idx = np.minimum(((x - lo) / (hi - lo) * nc).astype(int), nc - 1)
    flat = np.ravel_multi_index(idx.T, nc) if len(x) else np.zeros(0, int)
    count = np.bincount(flat, minlength=int(nc.prod()))
    count_a = np.bincount(flat, weights=is_a.astype(float), minlength=int(nc.prod()))
    keep = count >= min_count
    if not keep.any():
        return math.nan, 0, 0.0
    n, na = count[keep].astype(float), count_a[keep]
    p = na.sum() / n.sum()
    if p <= 0.0 or p >= 1.0:
        return math.nan, int(keep.sum()), float(n.mean())
    s2 = float((n * (na / n - p) ** 2).sum() / n.sum())
    s0 = p * (1.0 - p)
    sr = s0 / n.mean()
    return float((s0 - s2) / (s0 - sr)), int(keep.sum()), float(n.mean())
