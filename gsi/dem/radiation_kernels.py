"""The compiled kernels of particle radiation (the model: :mod:`gsi.dem.radiation`): the
view sums of the first pass, the exchange of the second, and the wall heat's scatter to
the wall vertices.

The kernels take their data in bundles, named tuples of arrays (and scalars) as
:mod:`gsi.dem.state` does for the engine; each has fewer than 16 fields, so it passes
into a ``prange`` body as it is (see :mod:`gsi.dem.state`):

- :data:`Emitters`: the particles as radiation sees them;
- :data:`CellGrid`: the cell list at the radiation cut-off, with the triangles binned
  into the same cells;
- :data:`Surfaces`: planes, mesh walls and the enclosure;
- :data:`Views`: what the first pass finds (Sigma_i, each wall's closest point);
- :data:`RateArrays`: what the second pass writes (:class:`gsi.dem.radiation.Rates`
  adds the enclosure's part).
"""
from collections import namedtuple

import numpy as np

from gsi.dem.cells import neighbour_cell, point_cell
from gsi.dem.contact_geometry import plane_distance
from gsi.dem.geometry import closest_point_triangle
from gsi.dem.wall_kernels import p2_weight
from gsi.jit import njit, pjit, prange

#: Stefan-Boltzmann constant (W/(m^2 K^4)), CODATA 2018 (exact in the 2019 SI; 10 digits)
SIGMA = 5.670374419e-8

Emitters = namedtuple("Emitters", [
    "x",            # (n, 3) m: centres
    "radius",       # (n,) m
    "area",         # (n,) m^2: 4 pi R^2
    "eps",          # (n,) -: emissivity (0: does not radiate)
    "T4",           # (n,) K^4: T^4
])

CellGrid = namedtuple("CellGrid", [
    "cutoff",       # c (-): neighbours closer than c (R_i + R_j), walls closer than c R_i
    "lo",           # (3,) m: the domain's lower corner
    "inv_cs",       # (3,) 1/m: inverse cell sizes
    "dims",         # (3,) int64: cells per axis
    "cell_start",   # (ncells + 1,) int64: particles of cell c at cell_list[start[c]:start[c+1]]
    "cell_list",    # (n,) int64
    "tcell_start",  # (ncells + 1,) int64: triangles near cell c (only radiating walls)
    "tcell_list",   # int32
])

Surfaces = namedtuple("Surfaces", [
    "pl_point",     # (npl, 3) m: plane points
    "pl_normal",    # (npl, 3): unit normals into the domain
    "pl_rad",       # (npl,) uint8: 1 if the plane radiates (has a temperature, eps > 0)
    "pl_eps",       # (npl,) -: emissivity
    "pl_T4",        # (npl,) K^4
    "mx",           # (nv, 3) m: mesh vertices
    "mtri",         # (ntri, 3) int: triangle vertices
    "mT",           # (nv,) K: vertex temperatures
    "tri_wall",     # (ntri,) int: mesh wall of each triangle
    "wall_rad",     # (nw,) uint8: 1 if the mesh wall radiates
    "wall_eps",     # (nw,) -: emissivity
    "T_enc4",       # K^4: the enclosure's T^4 (0 without one)
    "has_enc",      # bool: particles without neighbours see the enclosure
])

Views = namedtuple("Views", [
    "area_sum",     # (n,) m^2: Sigma_i, the area of i's neighbours
    "wall_tri",     # (n, nw) int64: closest triangle of each radiating wall (-1: none)
    "wall_w",       # (n, nw, 3): its barycentric weights
])

RateArrays = namedtuple("RateArrays", [
    "Q",            # (n,) W: heat rate into each particle
    "Q_plane",      # (n, npl) W: from each plane
    "Q_wall",       # (n, nw) W: from each mesh wall
    "S",            # (n, n) m^2 or (0, 0): exchange area of each pair (recorded if not empty)
    "Q_pair",       # (n, n) W or (0, 0): rate of each pair
])


@njit
def _view_one(i, E, G, S, V):
    """Sigma_i, the area of i's neighbours (particles, and A_i per radiating wall); the
    closest triangle of each radiating mesh wall within the cut-off into
    ``V.wall_tri[i]`` (-1: none) with its barycentric weights ``V.wall_w[i]``."""
    x, radius, area = E.x, E.radius, E.area
    wall_tri, wall_w = V.wall_tri, V.wall_w
    mx, mtri = S.mx, S.mtri
    ri = radius[i]
    xi0 = x[i, 0]
    xi1 = x[i, 1]
    xi2 = x[i, 2]
    dims = G.dims
    cx, cy, cz = point_cell(xi0, xi1, xi2, G.lo, G.inv_cs, dims)
    s = 0.0
    for k in range(27):
        c2 = neighbour_cell(cx, cy, cz, k, dims)
        if c2 >= 0:
            for m in range(G.cell_start[c2], G.cell_start[c2 + 1]):
                j = G.cell_list[m]
                if j == i:
                    continue
                rc = G.cutoff * (ri + radius[j])
                d2 = ((x[j, 0] - xi0) ** 2 + (x[j, 1] - xi1) ** 2
                      + (x[j, 2] - xi2) ** 2)
                if d2 < rc * rc:
                    s += area[j]
    reach = G.cutoff * ri
    for p in range(S.pl_point.shape[0]):
        if not S.pl_rad[p]:
            continue
        dist = plane_distance(xi0, xi1, xi2, S.pl_point[p, 0], S.pl_point[p, 1],
                              S.pl_point[p, 2], S.pl_normal[p, 0], S.pl_normal[p, 1],
                              S.pl_normal[p, 2])
        if 0.0 < dist < reach:
            s += area[i]
    nw = S.wall_rad.shape[0]
    if nw > 0:
        best = np.full(nw, reach * reach)
        for w in range(nw):
            wall_tri[i, w] = -1
        c = (cx * dims[1] + cy) * dims[2] + cz
        for m in range(G.tcell_start[c], G.tcell_start[c + 1]):
            t = G.tcell_list[m]
            w = S.tri_wall[t]
            if not S.wall_rad[w]:
                continue
            a = mtri[t, 0]
            b = mtri[t, 1]
            c_ = mtri[t, 2]
            qx, qy, qz, wa, wb, wc, reg = closest_point_triangle(
                xi0, xi1, xi2, mx[a, 0], mx[a, 1], mx[a, 2], mx[b, 0], mx[b, 1], mx[b, 2],
                mx[c_, 0], mx[c_, 1], mx[c_, 2])
            d2 = (qx - xi0) ** 2 + (qy - xi1) ** 2 + (qz - xi2) ** 2
            if d2 < best[w]:
                best[w] = d2
                wall_tri[i, w] = t
                wall_w[i, w, 0] = wa
                wall_w[i, w, 1] = wb
                wall_w[i, w, 2] = wc
        for w in range(nw):
            if wall_tri[i, w] >= 0:
                s += area[i]
    return s


@pjit
def view_sums(E, G, S, V):
    """First pass: Sigma_i of every particle into ``V.area_sum`` (m^2), and the closest
    point of each radiating mesh wall (:func:`_view_one`)."""
    area_sum = V.area_sum      # a bundle's field written in a prange body is lost (numba 0.56)
    for i in prange(E.x.shape[0]):
        area_sum[i] = _view_one(i, E, G, S, V)


@njit
def _exchange_one(i, E, G, S, V, R):
    """Heat rate into particle i (W): its pairs (each from i's side; the same operands
    as from j's side, so Q_ij = -Q_ji exactly), its radiating walls (rates into
    ``R.Q_plane[i]``, ``R.Q_wall[i]``) and the enclosure. ``R.S``, ``R.Q_pair`` (n, n)
    record each pair's exchange area and rate when they are not empty (tests)."""
    x, radius, area, eps, T4 = E.x, E.radius, E.area, E.eps, E.T4
    area_sum, wall_tri, wall_w = V.area_sum, V.wall_tri, V.wall_w
    mtri, mT = S.mtri, S.mT
    ri = radius[i]
    xi0 = x[i, 0]
    xi1 = x[i, 1]
    xi2 = x[i, 2]
    Si = area_sum[i]
    record = R.S.shape[0] > 0
    cx, cy, cz = point_cell(xi0, xi1, xi2, G.lo, G.inv_cs, G.dims)
    q = 0.0
    for k in range(27):
        c2 = neighbour_cell(cx, cy, cz, k, G.dims)
        if c2 >= 0:
            for m in range(G.cell_start[c2], G.cell_start[c2 + 1]):
                j = G.cell_list[m]
                if j == i:
                    continue
                rc = G.cutoff * (ri + radius[j])
                d2 = ((x[j, 0] - xi0) ** 2 + (x[j, 1] - xi1) ** 2
                      + (x[j, 2] - xi2) ** 2)
                if d2 < rc * rc:
                    Sij = area[i] * area[j] / max(Si, area_sum[j])
                    Qij = SIGMA * (eps[i] * eps[j]) * Sij * (T4[j] - T4[i])
                    q += Qij
                    if record:
                        R.S[i, j] = Sij
                        R.Q_pair[i, j] = Qij
    if Si > 0.0:
        Sw = area[i] * area[i] / Si
        reach = G.cutoff * ri
        for p in range(S.pl_point.shape[0]):
            R.Q_plane[i, p] = 0.0
            if not S.pl_rad[p]:
                continue
            dist = plane_distance(xi0, xi1, xi2, S.pl_point[p, 0], S.pl_point[p, 1],
                                  S.pl_point[p, 2], S.pl_normal[p, 0], S.pl_normal[p, 1],
                                  S.pl_normal[p, 2])
            if 0.0 < dist < reach:
                Qw = SIGMA * (eps[i] * S.pl_eps[p]) * Sw * (S.pl_T4[p] - T4[i])
                R.Q_plane[i, p] = Qw
                q += Qw
        for w in range(wall_tri.shape[1]):
            R.Q_wall[i, w] = 0.0
            t = wall_tri[i, w]
            if t < 0:
                continue
            Tw = (wall_w[i, w, 0] * mT[mtri[t, 0]] + wall_w[i, w, 1] * mT[mtri[t, 1]]
                  + wall_w[i, w, 2] * mT[mtri[t, 2]])
            Qw = SIGMA * (eps[i] * S.wall_eps[w]) * Sw * (Tw * Tw * Tw * Tw - T4[i])
            R.Q_wall[i, w] = Qw
            q += Qw
    elif S.has_enc:
        q = SIGMA * eps[i] * area[i] * (S.T_enc4 - T4[i])
    return q


@pjit
def exchange(E, G, S, V, R):
    """Second pass: the heat rate into every particle ``R.Q`` (W)
    (:func:`_exchange_one`); each particle writes only its own rows."""
    Q = R.Q                    # a bundle's field written in a prange body is lost (numba 0.56)
    for i in prange(E.x.shape[0]):
        Q[i] = _exchange_one(i, E, G, S, V, R)


@njit
def scatter_wall_heat(dt, V, Q_wall, M, rad_wall_heat):
    """Serial: each particle's radiation ``Q_wall`` (n, nw) from mesh wall w at its
    closest point on triangle t (``V``: :data:`Views`) goes into the books of the mesh
    ``M`` (:data:`gsi.dem.state.Mesh`) as the conduction's does
    (:func:`gsi.dem.wall_kernels.mesh_scatter`): vertex_heat += -Q N_k dt (N_k the
    barycentric weights, or the P2 basis of the parent face), wall_heat += Q dt; and
    into ``rad_wall_heat[w]`` (the radiative part, J into the particles)."""
    wall_tri, wall_w = V.wall_tri, V.wall_w
    mtri, tri_p6, tri_lam, tri_wall = M.tri, M.tri_p6, M.tri_lam, M.tri_wall
    vertex_heat, wall_heat = M.vertex_heat, M.wall_heat
    for i in range(wall_tri.shape[0]):
        for w in range(wall_tri.shape[1]):
            t = wall_tri[i, w]
            if t < 0:
                continue
            Qdt = Q_wall[i, w] * dt
            quad = tri_p6[t, 0] >= 0
            la = 0.0
            lb = 0.0
            lc = 0.0
            if quad:
                for c in range(3):
                    wk = wall_w[i, w, c]
                    la += wk * tri_lam[t, c, 0]
                    lb += wk * tri_lam[t, c, 1]
                    lc += wk * tri_lam[t, c, 2]
            for k in range(6 if quad else 3):
                if quad:
                    a = tri_p6[t, k]
                    wk = p2_weight(k, la, lb, lc)
                else:
                    a = mtri[t, k]
                    wk = wall_w[i, w, k]
                vertex_heat[a] -= Qdt * wk
            wall_heat[tri_wall[t]] += Qdt
            rad_wall_heat[tri_wall[t]] += Qdt
