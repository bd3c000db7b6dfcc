"""Triangulations of the wall shapes gsi builds (vertices in m, triangles as vertex indices).

Each function returns ``(vertices (nv, 3) float, triangles (nt, 3) int64)`` ready for
:meth:`gsi.dem.Simulation.add_mesh_wall`.  Shapes with an axis (cone, funnel, cylinder,
drum) take a point ``centre`` on the axis at one end, a unit-free ``axis`` direction
(normalised here) and build rings of ``facets`` vertices around it; the number of rings
keeps the triangles roughly equilateral.  Triangles are oriented with their normals
(right-hand rule on the vertex order) pointing INTO the space the particles occupy:
toward the axis for the mantles and into the drum for the end caps.  A drum is closed
(every edge belongs to exactly two triangles, traversed in opposite directions).

The contact detection uses the closest point of each triangle, so orientation does not
change the contact force; it matters for pictures and for checks that a shape is closed.
"""
from __future__ import annotations

import math

import numpy as np

from gsi.errors import GsiInputError

__all__ = ["orthonormal_frame", "cone", "funnel", "cylinder", "drum", "plate", "box",
           "plate_edges", "unit", "closed_and_consistent", "triangle_normals", "enclosed_volume"]


def unit(v, *, key: str = "axis") -> np.ndarray:
    """``v`` normalised; GsiInputError naming ``key`` for a zero or non-3 vector."""
    a = np.asarray(v, float).reshape(-1)
    n = float(np.linalg.norm(a)) if a.shape == (3,) else 0.0
    if not (n > 0 and math.isfinite(n)):
        raise GsiInputError(f"{key} = {list(np.atleast_1d(v))}: must be a nonzero 3-vector")
    return a / n


def orthonormal_frame(axis) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit vectors (e1, e2, a) with a = axis/|axis| and e1 x e2 = a."""
    a = unit(axis)
    ref = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = ref - (ref @ a) * a
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(a, e1), a


def _rings(centre, axis, radii, offsets, facets) -> np.ndarray:
    """Ring k: ``facets`` vertices at radius radii[k], offsets[k] along the axis (m)."""
    e1, e2, a = orthonormal_frame(axis)
    th = 2 * math.pi * np.arange(facets) / facets
    c = np.asarray(centre, float)
    circle = np.cos(th)[:, None] * e1 + np.sin(th)[:, None] * e2
    return np.vstack([c + s * a + r * circle for r, s in zip(radii, offsets)])


def _band(k0: int, k1: int, facets: int) -> np.ndarray:
    """Triangles between ring k0 and ring k1 (ring vertex blocks of ``facets``), normals
    toward the axis when ring k1 lies further along the axis than ring k0.  Each quad
    (a, b on ring k0; a', b' above them) is split along a-b' (the split of the hopper
    driver's cone, so a rebuilt hopper has the same triangles)."""
    i = np.arange(facets)
    a = k0 * facets + i
    b = k0 * facets + (i + 1) % facets
    up = (k1 - k0) * facets
    return np.vstack([np.c_[a, b + up, b], np.c_[a, a + up, b + up]])


def _check_facets(facets: int) -> None:
    if not (isinstance(facets, (int, np.integer)) and facets >= 8):
        raise GsiInputError(f"facets = {facets}: must be an integer >= 8")


def _n_rings(length: float, radius: float, facets: int) -> int:
    return max(1, int(math.ceil(length / (2 * math.pi * radius / facets))))


def cone(*, centre=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0), outlet_radius: float,
         top_radius: float, length: float, facets: int = 48):
    """Open truncated cone (a hopper): radius ``outlet_radius`` (m) at ``centre`` growing
    linearly to ``top_radius`` (m) at ``length`` (m) along ``axis``; ``facets`` vertices per
    ring.  ``outlet_radius = 0`` is allowed (a closed tip)."""
    _check_facets(facets)
    if not (outlet_radius >= 0 and top_radius > 0 and length > 0):
        raise GsiInputError(f"cone: outlet_radius = {outlet_radius}, top_radius = {top_radius}, "
                            f"length = {length}: need outlet_radius >= 0, top_radius > 0, length > 0 (m)")
    n_z = _n_rings(length, max(top_radius, outlet_radius), facets)
    s = np.arange(n_z + 1) / n_z
    V = _rings(centre, axis, outlet_radius + s * (top_radius - outlet_radius), s * length, facets)
    T = np.vstack([_band(k, k + 1, facets) for k in range(n_z)])
    return V, T.astype(np.int64)


def funnel(*, centre=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0), outlet_radius: float,
           top_radius: float, length: float, spout_length: float, facets: int = 48):
    """A cone (see :func:`cone`) with a cylindrical spout of radius ``outlet_radius`` (m)
    reaching ``spout_length`` (m) from ``centre`` against ``axis`` (the outlet end of the
    spout is at centre - spout_length axis)."""
    _check_facets(facets)
    if not (outlet_radius > 0 and spout_length > 0):
        raise GsiInputError(f"funnel: outlet_radius = {outlet_radius}, spout_length = {spout_length}: "
                            "must be > 0 (m)")
    Vc, Tc = cone(centre=centre, axis=axis, outlet_radius=outlet_radius,
                  top_radius=top_radius, length=length, facets=facets)
    n_s = _n_rings(spout_length, outlet_radius, facets)
    s = np.arange(n_s) / n_s          # the spout's rings below the cone's outlet ring
    a = unit(axis)
    Vs = _rings(np.asarray(centre, float) - spout_length * a, axis,
                np.full(n_s, outlet_radius), s * spout_length, facets)
    V = np.vstack([Vs, Vc])
    T = np.vstack([_band(k, k + 1, facets) for k in range(n_s)] + [Tc + n_s * facets])
    return V, T.astype(np.int64)


def cylinder(*, centre=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0), radius: float, length: float,
             facets: int = 48):
    """Open cylinder mantle: radius ``radius`` (m) from ``centre`` along ``axis`` for
    ``length`` (m)."""
    return cone(centre=centre, axis=axis, outlet_radius=radius, top_radius=radius,
                length=length, facets=facets)


def _zip_rings(outer, inner) -> np.ndarray:
    """Triangles between two concentric rings of ``len(outer)`` and ``len(inner)`` vertices
    (index arrays in increasing angle, both starting at angle 0): walk both rings by angle,
    always closing the triangle whose next vertex comes first. Oriented as
    (outer, next outer, inner): counter-clockwise about the axis of :func:`_rings`."""
    no, ni = len(outer), len(inner)
    t_o = np.arange(no + 1) / no            # angles as fractions of a turn, wrapped once
    t_i = np.arange(ni + 1) / ni
    tri = []
    a = b = 0
    while a < no or b < ni:
        if b >= ni or (a < no and t_o[a + 1] <= t_i[b + 1]):
            tri.append((outer[a % no], outer[(a + 1) % no], inner[b % ni]))
            a += 1
        else:
            tri.append((outer[a % no], inner[(b + 1) % ni], inner[b % ni]))
            b += 1
    return np.asarray(tri, np.int64)


def drum(*, centre=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0), radius: float, length: float,
         facets: int = 48):
    """Closed drum: cylinder mantle (see :func:`cylinder`) with flat end caps at both ends;
    normals point into the drum.

    Each cap is a disc of concentric rings whose vertex count falls with the radius (ring k
    of n_r at radius k R/n_r has about ``facets`` k/n_r vertices, at least 6), so the cap's
    triangles stay near-equilateral down to the centre: a particle touching the cap meets a
    few triangles, not the dozens of slivers of a fan or of equal-count rings."""
    V, T = cylinder(centre=centre, axis=axis, radius=radius, length=length, facets=facets)
    n_rings = len(V) // facets
    n_r = max(1, int(round(facets / (2 * math.pi))))           # rings on a cap: ~equilateral
    a = unit(axis)
    c = np.asarray(centre, float)
    tris = [T]
    verts = [V]
    nv = len(V)
    for end, ring0 in ((0.0, 0), (length, (n_rings - 1) * facets)):
        ring_idx = [ring0 + np.arange(facets)]
        block = []
        for k in range(n_r - 1, 0, -1):
            n_k = max(6, int(round(facets * k / n_r)))
            block.append(_rings(c, a, [radius * k / n_r], [end], n_k))
            ring_idx.append(nv + sum(len(v) for v in block[:-1]) + np.arange(n_k))
        block.append((c + end * a)[None, :])
        centre_idx = nv + sum(len(v) for v in block[:-1])
        tri = [_zip_rings(outer, inner) for outer, inner in zip(ring_idx[:-1], ring_idx[1:])]
        last = ring_idx[-1]
        tri.append(np.c_[last, np.roll(last, -1), np.full(len(last), centre_idx)])
        tri = np.vstack(tri)
        # (outer, next, inner) turns counter-clockwise about +axis: normal +axis, into the
        # drum at the bottom cap (end 0); flip at the top cap
        if end > 0:
            tri = tri[:, ::-1]
        tris.append(tri)
        Vi = np.vstack(block)
        verts.append(Vi)
        nv += len(Vi)
    return np.vstack(verts), np.vstack(tris).astype(np.int64)


def plate(*, centre, edge_u, edge_v, n_u: int = 1, n_v: int = 1):
    """Flat parallelogram centred at ``centre`` (m) with full edge vectors ``edge_u`` and
    ``edge_v`` (m), split into ``n_u`` x ``n_v`` cells of two triangles; normal along
    edge_u x edge_v."""
    c = np.asarray(centre, float)
    u, v = np.asarray(edge_u, float), np.asarray(edge_v, float)
    if np.linalg.norm(np.cross(u, v)) == 0:
        raise GsiInputError(f"plate: edge_u = {u.tolist()}, edge_v = {v.tolist()}: must be nonzero "
                            "and not parallel (m)")
    su, sv = np.meshgrid(np.linspace(-0.5, 0.5, n_u + 1), np.linspace(-0.5, 0.5, n_v + 1),
                         indexing="ij")
    V = c + su.reshape(-1, 1) * u + sv.reshape(-1, 1) * v
    idx = np.arange((n_u + 1) * (n_v + 1)).reshape(n_u + 1, n_v + 1)
    a, b = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel()
    cc, d = idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    T = np.vstack([np.c_[a, b, cc], np.c_[a, cc, d]])
    return V, T.astype(np.int64)


def plate_edges(*, normal, size) -> tuple[np.ndarray, np.ndarray]:
    """Edge vectors of a ``size`` = (width, depth) (m) rectangle with unit ``normal``:
    width along the projection of x (of y when the normal is along x), depth completing
    a right-handed frame (edge_u x edge_v along the normal)."""
    e1, e2, n = orthonormal_frame(normal)
    x = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = x - (x @ n) * n
    u /= np.linalg.norm(u)
    return size[0] * u, size[1] * np.cross(n, u)


def box(*, lo, hi, lid: bool = True):
    """Triangulated box between corners ``lo`` and ``hi`` (m), two triangles per face,
    normals inward; ``lid=False`` leaves the top (max z) face open."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    if not (hi > lo).all():
        raise GsiInputError(f"box: hi = {hi.tolist()} must exceed lo = {lo.tolist()} in every component (m)")
    V = np.array([[lo[0], lo[1], lo[2]], [hi[0], lo[1], lo[2]], [hi[0], hi[1], lo[2]],
                  [lo[0], hi[1], lo[2]], [lo[0], lo[1], hi[2]], [hi[0], lo[1], hi[2]],
                  [hi[0], hi[1], hi[2]], [lo[0], hi[1], hi[2]]])
    faces = [(0, 1, 2, 3), (0, 4, 5, 1), (1, 5, 6, 2), (2, 6, 7, 3), (3, 7, 4, 0)]
    if lid:
        faces.append((4, 7, 6, 5))
    T = np.array([t for a, b, c, d in faces for t in ((a, b, c), (a, c, d))], np.int64)
    return V, T


# ----------------------------------------------------------------------------- checks
def triangle_normals(V, T) -> np.ndarray:
    """Unit normals (nt, 3) of triangles by the right-hand rule."""
    V, T = np.asarray(V, float), np.asarray(T)
    n = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])
    return n / np.linalg.norm(n, axis=1)[:, None]


def closed_and_consistent(T) -> tuple[bool, bool]:
    """(closed, consistent): every undirected edge in exactly two triangles; every directed
    edge in at most one triangle (neighbours traverse a shared edge in opposite senses)."""
    T = np.asarray(T)
    directed = np.vstack([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]])
    und = np.sort(directed, axis=1)
    _, counts = np.unique(und, axis=0, return_counts=True)
    _, dcounts = np.unique(directed, axis=0, return_counts=True)
    return bool((counts == 2).all()), bool((dcounts == 1).all())


def enclosed_volume(V, T) -> float:
    """Signed volume (m^3) enclosed by a closed triangulation (divergence theorem);
    negative when the normals point inward."""
    V, T = np.asarray(V, float), np.asarray(T)
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)
