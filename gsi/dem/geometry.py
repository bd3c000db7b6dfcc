"""Contact geometry kernels: closest point on a triangle (face, edge or vertex region).

Ericson, *Real-Time Collision Detection* (2005), section 5.1.5.  Region codes:
``FACE = 0``; vertices ``VA, VB, VC = 1, 2, 3``; edges ``EAB, EBC, ECA = 4, 5, 6``.
"""
from gsi.jit import njit

FACE, VA, VB, VC, EAB, EBC, ECA = range(7)


@njit(inline="always")
def triangle_normal(ax, ay, az, bx, by, bz, cx, cy, cz):
    """N = (b - a) x (c - a), the unnormalised normal of triangle (a, b, c) (|N| is twice
    its area; 0 for a degenerate one).  The plane distance of a point p is
    (p - a).N / |N|, a lower bound of its distance to the triangle."""
    ux = bx - ax
    uy = by - ay
    uz = bz - az
    vx = cx - ax
    vy = cy - ay
    vz = cz - az
    return uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx


@njit
def closest_point_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz):
    """Closest point of triangle (a, b, c) to p, its barycentric weights and region.

    Returns
    -------
    qx, qy, qz : float
        The closest point (m).
    wa, wb, wc : float
        Barycentric weights of q in (a, b, c), >= 0, sum 1.
    region : int
        FACE, VA, VB, VC, EAB, EBC or ECA.
    """
    abx = bx - ax
    aby = by - ay
    abz = bz - az
    acx = cx - ax
    acy = cy - ay
    acz = cz - az
    apx = px - ax
    apy = py - ay
    apz = pz - az
    d1 = abx * apx + aby * apy + abz * apz
    d2 = acx * apx + acy * apy + acz * apz
    if d1 <= 0.0 and d2 <= 0.0:
        return ax, ay, az, 1.0, 0.0, 0.0, VA
    bpx = px - bx
    bpy = py - by
    bpz = pz - bz
    d3 = abx * bpx + aby * bpy + abz * bpz
    d4 = acx * bpx + acy * bpy + acz * bpz
    if d3 >= 0.0 and d4 <= d3:
        return bx, by, bz, 0.0, 1.0, 0.0, VB
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        t = d1 / (d1 - d3)
        return ax + t * abx, ay + t * aby, az + t * abz, 1.0 - t, t, 0.0, EAB
    cpx = px - cx
    cpy = py - cy
    cpz = pz - cz
    d5 = abx * cpx + aby * cpy + abz * cpz
    d6 = acx * cpx + acy * cpy + acz * cpz
    if d6 >= 0.0 and d5 <= d6:
        return cx, cy, cz, 0.0, 0.0, 1.0, VC
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        t = d2 / (d2 - d6)
        return ax + t * acx, ay + t * acy, az + t * acz, 1.0 - t, 0.0, t, ECA
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        t = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return (bx + t * (cx - bx), by + t * (cy - by), bz + t * (cz - bz),
                0.0, 1.0 - t, t, EBC)
    denom = 1.0 / (va + vb + vc)
    v = vb * denom
    w = vc * denom
    return (ax + abx * v + acx * w, ay + aby * v + acy * w, az + abz * v + acz * w,
            1.0 - v - w, v, w, FACE)
