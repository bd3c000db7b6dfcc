"""The compiled kernels of particle radiation (the model: :mod:`gsi.dem.radiation`): the
view sums of the first pass, the exchange of the second, and the wall heat's scatter to
the wall vertices."""
import numpy as np

from gsi.dem.cells import neighbour_cell, point_cell
from gsi.dem.contact_geometry import plane_distance
from gsi.dem.geometry import closest_point_triangle
from gsi.dem.wall_kernels import p2_weight
from gsi.jit import njit, pjit, prange

#: Stefan-Boltzmann constant (W/(m^2 K^4)), CODATA 2018 (exact in the 2019 SI; 10 digits)
SIGMA = 5.670374419e-8


@njit
def _view_one(i, x, radius, area, cutoff, lo, inv_cs, dims, cell_start, cell_list,
              pl_point, pl_normal, pl_rad, tcell_start, tcell_list, mx, mtri, tri_wall,
              wall_rad, wall_tri, wall_w):
    """Sigma_i, the area of i's neighbours (particles, and A_i per radiating wall); the
    closest triangle of each radiating mesh wall within the cut-off into
    ``wall_tri[i]`` (-1: none) with its barycentric weights ``wall_w[i]``."""
    ri = radius[i]
    xi0 = x[i, 0]
    xi1 = x[i, 1]
    xi2 = x[i, 2]
    cx, cy, cz = point_cell(xi0, xi1, xi2, lo, inv_cs, dims)
    s = 0.0
    for k in range(27):
        c2 = neighbour_cell(cx, cy, cz, k, dims)
        if c2 >= 0:
            for m in range(cell_start[c2], cell_start[c2 + 1]):
                j = cell_list[m]
                if j == i:
                    continue
                rc = cutoff * (ri + radius[j])
                d2 = ((x[j, 0] - xi0) ** 2 + (x[j, 1] - xi1) ** 2
                      + (x[j, 2] - xi2) ** 2)
                if d2 < rc * rc:
                    s += area[j]
    reach = cutoff * ri
    for p in range(pl_point.shape[0]):
        if not pl_rad[p]:
            continue
        dist = plane_distance(xi0, xi1, xi2, pl_point[p, 0], pl_point[p, 1], pl_point[p, 2],
                              pl_normal[p, 0], pl_normal[p, 1], pl_normal[p, 2])
        if 0.0 < dist < reach:
            s += area[i]
    nw = wall_rad.shape[0]
    if nw > 0:
        best = np.full(nw, reach * reach)
        for w in range(nw):
            wall_tri[i, w] = -1
        c = (cx * dims[1] + cy) * dims[2] + cz
        for m in range(tcell_start[c], tcell_start[c + 1]):
            t = tcell_list[m]
            w = tri_wall[t]
            if not wall_rad[w]:
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
def view_sums(x, radius, area, cutoff, lo, inv_cs, dims, cell_start, cell_list, pl_point,
              pl_normal, pl_rad, tcell_start, tcell_list, mx, mtri, tri_wall, wall_rad,
              area_sum, wall_tri, wall_w):
    """First pass: Sigma_i of every particle into ``area_sum`` (m^2), and the closest
    point of each radiating mesh wall (:func:`_view_one`)."""
    for i in prange(x.shape[0]):
        area_sum[i] = _view_one(i, x, radius, area, cutoff, lo, inv_cs, dims, cell_start,
                                cell_list, pl_point, pl_normal, pl_rad, tcell_start,
                                tcell_list, mx, mtri, tri_wall, wall_rad, wall_tri, wall_w)


@njit
def _exchange_one(i, x, radius, area, eps, T4, cutoff, lo, inv_cs, dims, cell_start,
                  cell_list, area_sum, pl_point, pl_normal, pl_rad, pl_eps, pl_T4, mtri,
                  mT, wall_eps, wall_tri, wall_w, T_enc4, has_enc, Q_plane, Q_wall,
                  S_mat, Q_mat):
    """Heat rate into particle i (W): its pairs (each from i's side; the same operands
    as from j's side, so Q_ij = -Q_ji exactly), its radiating walls (rates into
    ``Q_plane[i]``, ``Q_wall[i]``) and the enclosure. ``S_mat``, ``Q_mat`` (n, n) record
    each pair's exchange area and rate when they are not empty (tests)."""
    ri = radius[i]
    xi0 = x[i, 0]
    xi1 = x[i, 1]
    xi2 = x[i, 2]
    Si = area_sum[i]
    record = S_mat.shape[0] > 0
    cx, cy, cz = point_cell(xi0, xi1, xi2, lo, inv_cs, dims)
    q = 0.0
    for k in range(27):
        c2 = neighbour_cell(cx, cy, cz, k, dims)
        if c2 >= 0:
            for m in range(cell_start[c2], cell_start[c2 + 1]):
                j = cell_list[m]
                if j == i:
                    continue
                rc = cutoff * (ri + radius[j])
                d2 = ((x[j, 0] - xi0) ** 2 + (x[j, 1] - xi1) ** 2
                      + (x[j, 2] - xi2) ** 2)
                if d2 < rc * rc:
                    S = area[i] * area[j] / max(Si, area_sum[j])
                    Qij = SIGMA * (eps[i] * eps[j]) * S * (T4[j] - T4[i])
                    q += Qij
                    if record:
                        S_mat[i, j] = S
                        Q_mat[i, j] = Qij
    if Si > 0.0:
        Sw = area[i] * area[i] / Si
        reach = cutoff * ri
        for p in range(pl_point.shape[0]):
            Q_plane[i, p] = 0.0
            if not pl_rad[p]:
                continue
            dist = plane_distance(xi0, xi1, xi2, pl_point[p, 0], pl_point[p, 1],
                                  pl_point[p, 2], pl_normal[p, 0], pl_normal[p, 1],
                                  pl_normal[p, 2])
            if 0.0 < dist < reach:
                Qw = SIGMA * (eps[i] * pl_eps[p]) * Sw * (pl_T4[p] - T4[i])
                Q_plane[i, p] = Qw
                q += Qw
        for w in range(wall_tri.shape[1]):
            Q_wall[i, w] = 0.0
            t = wall_tri[i, w]
            if t < 0:
                continue
            Tw = (wall_w[i, w, 0] * mT[mtri[t, 0]] + wall_w[i, w, 1] * mT[mtri[t, 1]]
                  + wall_w[i, w, 2] * mT[mtri[t, 2]])
            Qw = SIGMA * (eps[i] * wall_eps[w]) * Sw * (Tw * Tw * Tw * Tw - T4[i])
            Q_wall[i, w] = Qw
            q += Qw
    elif has_enc:
        q = SIGMA * eps[i] * area[i] * (T_enc4 - T4[i])
    return q


@pjit
def exchange(x, radius, area, eps, T4, cutoff, lo, inv_cs, dims, cell_start, cell_list,
             area_sum, pl_point, pl_normal, pl_rad, pl_eps, pl_T4, mtri, mT, wall_eps,
             wall_tri, wall_w, T_enc4, has_enc, Q, Q_plane, Q_wall, S_mat, Q_mat):
    """Second pass: the heat rate into every particle ``Q`` (W) (:func:`_exchange_one`);
    each particle writes only its own rows."""
    for i in prange(x.shape[0]):
        Q[i] = _exchange_one(i, x, radius, area, eps, T4, cutoff, lo, inv_cs, dims,
                             cell_start, cell_list, area_sum, pl_point, pl_normal, pl_rad,
                             pl_eps, pl_T4, mtri, mT, wall_eps, wall_tri, wall_w, T_enc4,
                             has_enc, Q_plane, Q_wall, S_mat, Q_mat)


@njit
def scatter_wall_heat(dt, wall_tri, wall_w, Q_wall, mtri, tri_p6, tri_lam, tri_wall,
                      vertex_heat, wall_heat, rad_wall_heat):
    """Serial: each particle's radiation from mesh wall w at its closest point on
    triangle t goes into the wall's books as the conduction's does
    (:func:`gsi.dem.wall_kernels.mesh_scatter`): vertex_heat += -Q N_k dt (N_k the
    barycentric weights, or the P2 basis of the parent face), wall_heat += Q dt; and
    into ``rad_wall_heat[w]`` (the radiative part, J into the particles)."""
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
