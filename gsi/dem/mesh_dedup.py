"""Triangle contacts of one particle with the face/edge/vertex de-duplication.

docs/design.md, "Contact geometry": a sphere touches a triangle at its closest point (face,
edge or vertex region, :func:`gsi.dem.geometry.closest_point_triangle`); a particle
touching several triangles of one smooth surface must not be pushed twice.  Per
particle and wall: face contacts are taken first; an edge or vertex contact is dropped
when a face contact of a triangle containing that edge or vertex exists, when the same
edge or vertex already gave a contact, or when an accepted contact lies at the same
point (within :data:`SAME_POINT_TOL` R).

Law-independent: the engine calls :func:`select_triangle_contacts` and then
evaluates its law on the accepted slots.
"""
import numpy as np
from gsi.jit import njit
from gsi.dem.geometry import closest_point_triangle, FACE, VA, VB, VC, EAB, EBC
from gsi.dem.state import MAX_WALL_SLOTS

#: two contact points closer than this fraction of the radius are the same contact
SAME_POINT_TOL = 1e-9


@njit
def feature(t, region, tri, tri_edge):
    """(kind, id) of a closest-point region: kind 0 face (triangle id), 1 edge, 2 vertex."""
    if region == FACE:
        return 0, t
    if region == VA:
        return 2, tri[t, 0]
    if region == VB:
        return 2, tri[t, 1]
    if region == VC:
        return 2, tri[t, 2]
    if region == EAB:
        return 1, tri_edge[t, 0]
    if region == EBC:
        return 1, tri_edge[t, 1]
    return 1, tri_edge[t, 2]


@njit
def _duplicate(i, ns, kind, fid, wall, qx, qy, qz, tol2, M, wc):
    """True if the candidate contact (kind, fid) of ``wall`` at q repeats one of the
    ``ns`` accepted slots of particle i."""
    for s in range(ns):
        ts = wc.tri[i, s]
        if M.tri_wall[ts] != wall:
            continue
        ex = wc.point[i, s, 0] - qx
        ey = wc.point[i, s, 1] - qy
        ez = wc.point[i, s, 2] - qz
        if ex * ex + ey * ey + ez * ez <= tol2:
            return True
        if kind != 0 and wc.kind[i, s] == kind and wc.feature[i, s] == fid:
            return True
        if kind == 1 and wc.kind[i, s] == 0:
            if (M.tri_edge[ts, 0] == fid or M.tri_edge[ts, 1] == fid
                    or M.tri_edge[ts, 2] == fid):
                return True
        elif kind == 2 and wc.kind[i, s] == 0:
            if M.tri[ts, 0] == fid or M.tri[ts, 1] == fid or M.tri[ts, 2] == fid:
                return True
    return False


@njit
def select_triangle_contacts(i, xi0, xi1, xi2, ri, pairs, M, wc):
    """Fill the wall-contact slots of particle i (centre xi, radius ri) from its
    triangle candidates ``pairs.tri[pairs.tri_start[i]:pairs.tri_start[i + 1]]``:
    triangle, feature, candidate row, barycentric weights and closest point of each
    accepted contact.  Springs of candidates without an accepted contact restart from
    zero.  Returns the number of slots used (more than :data:`MAX_WALL_SLOTS` raise
    ``wc.overflow``)."""
    ns = np.int64(0)       # not a literal 0 (gsi.jit: literals)
    c0 = pairs.tri_start[i]
    c1 = pairs.tri_start[i + 1]
    if c1 == c0:
        return 0
    mx = M.x
    r2 = ri * ri
    tol2 = (SAME_POINT_TOL * ri) ** 2
    # faces first, then edges and vertices: the first sweep computes every candidate's
    # closest point and accepts the faces; it marks the candidates (of the first 64) whose
    # edge or vertex lies within reach in ``later``, and the second sweep recomputes only
    # those (and any candidate past the 64th), so a closest point is computed once for
    # nearly every candidate instead of twice (same points, same order: bitwise as two
    # full sweeps)
    later = np.uint64(0)
    for sweep in range(2):
        for k in range(c0, c1):
            bit = k - c0
            if sweep == 1 and bit < 64 and not (later >> np.uint64(bit)) & np.uint64(1):
                continue
            t = pairs.tri[k]
            a = M.tri[t, 0]
            b = M.tri[t, 1]
            c = M.tri[t, 2]
            qx, qy, qz, wa, wb, wcc, region = closest_point_triangle(
                xi0, xi1, xi2, mx[a, 0], mx[a, 1], mx[a, 2],
                mx[b, 0], mx[b, 1], mx[b, 2], mx[c, 0], mx[c, 1], mx[c, 2])
            ddx = qx - xi0
            ddy = qy - xi1
            ddz = qz - xi2
            if ddx * ddx + ddy * ddy + ddz * ddz >= r2:
                continue
            if (region == FACE) != (sweep == 0):
                if sweep == 0 and bit < 64:
                    later |= np.uint64(1) << np.uint64(bit)
                continue
            kind, fid = feature(t, region, M.tri, M.tri_edge)
            if _duplicate(i, ns, kind, fid, M.tri_wall[t], qx, qy, qz, tol2, M, wc):
                continue
            if ns == MAX_WALL_SLOTS:
                wc.overflow[0] += 1   # benign race: only a flag
                continue
            wc.tri[i, ns] = t
            wc.kind[i, ns] = kind
            wc.feature[i, ns] = fid
            wc.cand[i, ns] = k
            wc.weight[i, ns, 0] = wa
            wc.weight[i, ns, 1] = wb
            wc.weight[i, ns, 2] = wcc
            wc.point[i, ns, 0] = qx
            wc.point[i, ns, 1] = qy
            wc.point[i, ns, 2] = qz
            ns += 1
    # springs of candidates without an accepted contact restart from zero
    for k in range(c0, c1):
        used = False
        for s in range(ns):
            if wc.cand[i, s] == k:
                used = True
        if not used:
            pairs.tri_hist[k, 0] = 0.0
            pairs.tri_hist[k, 1] = 0.0
            pairs.tri_hist[k, 2] = 0.0
    return ns
