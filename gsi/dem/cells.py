"""The cell grid of the particle searches (neighbour lists, radiation): the domain box
cut into cells, particles binned into them, and the walk over the 27 cells around a
cell (:func:`neighbour_cell`, in the order x slowest, z fastest)."""
import math

import numpy as np

from gsi.jit import njit


def grid_for(lo, hi, cell_min, n):
    """Cell grid of the domain: ``(dims (3,) int64, inv_cs (3,) float)``.

    Cells are at least ``cell_min`` (m) wide; the count is capped near max(4096, 8 n)
    by widening them (a sparse system in a large box).
    """
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    ext = hi - lo
    cs = max(cell_min, 1e-300)
    while True:
        dims = np.maximum(1, np.floor(ext / cs)).astype(np.int64)
        if dims.prod() <= max(4096, 8 * n):
            break
        cs *= 1.26
    return dims, dims / ext


def particle_grid(b_lo, b_hi, lo, hi, cell_min, n):
    """Cell grid of the neighbour search over the bounding box [``b_lo``, ``b_hi``] of n
    particles (:func:`bounding_box`) clipped into the domain [``lo``, ``hi``]:
    ``(grid_lo (3,), dims, inv_cs)`` as :func:`grid_for`.  A dense bed in a large domain
    (the hopper: 2,000 spheres in a 0.9 x 0.9 x 1.3 m box) then gets cells of the cutoff
    instead of cells widened by :func:`grid_for`'s cap on the count (2.7 times as many
    candidates to test).  Every particle lies inside its own cell (the triangle search
    relies on it); an axis thinner than a cell gets one cell ``cell_min`` wide."""
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    g_lo = np.fmin(np.fmax(b_lo, lo), hi)          # fmax, fmin: a NaN gives the domain's
    g_hi = np.fmax(np.fmin(np.fmax(b_hi, lo), hi), g_lo + max(cell_min, 1e-300))
    dims, inv_cs = grid_for(g_lo, g_hi, cell_min, n)
    return g_lo, dims, inv_cs


@njit
def bounding_box(x):
    """Lowest and highest coordinates of the points ``x`` (n >= 1, 3): two arrays (3,)
    (numpy's reductions along axis 0 of an (n, 3) array cost ten times more)."""
    b_lo = x[0].copy()
    b_hi = x[0].copy()
    for i in range(1, x.shape[0]):
        for d in range(3):
            b_lo[d] = min(b_lo[d], x[i, d])
            b_hi[d] = max(b_hi[d], x[i, d])
    return b_lo, b_hi


@njit
def cell_index(n, x, lo, inv_cs, dims, cell_of):
    """Cell of each particle (clamped into the grid)."""
    for i in range(n):
        c = 0
        for d in range(3):          # c = (kx dims[1] + ky) dims[2] + kz
            k = int(math.floor((x[i, d] - lo[d]) * inv_cs[d]))
            if k < 0:
                k = 0
            elif k >= dims[d]:
                k = dims[d] - 1
            c = c * dims[d] + k
        cell_of[i] = c


@njit
def bin_cells(n, cell_of, ncell):
    """Counting sort of particles by cell: ``(cell_start (ncell+1), cell_list (n))``."""
    cell_start = np.zeros(ncell + 1, np.int64)
    for i in range(n):
        cell_start[cell_of[i] + 1] += 1
    for c in range(ncell):
        cell_start[c + 1] += cell_start[c]
    fill = cell_start[:-1].copy()
    cell_list = np.empty(n, np.int32)
    for i in range(n):
        c = cell_of[i]
        cell_list[fill[c]] = i
        fill[c] += 1
    return cell_start, cell_list


@njit(inline="always")
def cell_coords(c, dims):
    """Cell coordinates (kx, ky, kz) of cell index ``c``."""
    cx = c // (dims[1] * dims[2])
    r = c - cx * dims[1] * dims[2]
    cy = r // dims[2]
    cz = r - cy * dims[2]
    return cx, cy, cz


@njit(inline="always")
def point_cell(x0, x1, x2, lo, inv_cs, dims):
    """Cell coordinates of a point (clamped into the grid), as :func:`cell_index`."""
    k0 = min(max(int(math.floor((x0 - lo[0]) * inv_cs[0])), 0), dims[0] - 1)
    k1 = min(max(int(math.floor((x1 - lo[1]) * inv_cs[1])), 0), dims[1] - 1)
    k2 = min(max(int(math.floor((x2 - lo[2]) * inv_cs[2])), 0), dims[2] - 1)
    return k0, k1, k2


@njit(inline="always")
def neighbour_cell(cx, cy, cz, k, dims):
    """The k-th (0..26) of the 27 cells around cell (cx, cy, cz), x slowest and z
    fastest, as a cell index; -1 where it lies outside the grid. A walk::

        for k in range(27):
            c = neighbour_cell(cx, cy, cz, k, dims)
            if c >= 0:
                for m in range(cell_start[c], cell_start[c + 1]): ...
    """
    ax = cx + k // 9 - 1
    ay = cy + (k // 3) % 3 - 1
    az = cz + k % 3 - 1
    if ax < 0 or ax >= dims[0] or ay < 0 or ay >= dims[1] or az < 0 or az >= dims[2]:
        return -1
    return (ax * dims[1] + ay) * dims[2] + az
