"""The body a structure's mesh will occupy, known before it is meshed (``gsi check``): its
bounding box, surface area, volume, a signed distance to it (negative inside), and the
estimated size of its mesh (vertices, FE dofs).

* A shipped builder (:data:`gsi.meshes.BUILDERS`): exact analytic solids. The box and the
  membrane's rectangle are boxes; the other bodies are solids of revolution, described by
  their wall section in the (distance from the axis, position along the axis) half-plane
  (the same polygons the builders cut with OpenCASCADE). Area and volume by Pappus' rules.
* A gmsh file (``.geo`` / ``.msh``): a coarse tetrahedral mesh of the body (a ``.geo`` is
  meshed at 1/:data:`COARSE` of its diagonal, finer only along curved surfaces (24
  segments per turn), the file's own sizes ignored, so the probe is cheap whatever its h;
  a ``.msh`` is read as it is). Its boundary triangles give the
  area, the distance and the inside (ray parity); the mesh size h of a ``.geo`` is the
  mean segment length of a 1D mesh of its curves at the file's own sizes. A ``.msh`` is
  counted as it is (its vertices; its edges by Euler's formula).

Mesh size estimates (calibrated on the builders' gmsh meshes, 2026-12-04: membrane,
hopper, flat and conical silo, drum, h from 1/5 to 1/40 of the body): an unstructured
tetrahedral mesh of size h has about 1.25 S/h^2 + 0.5 V/h^3 vertices (S the surface area,
V the volume; the surface term dominates thin walls); an extruded membrane (n layers)
(n + 1)(1.15 A/h^2 + P/h) (A its area, P its perimeter). A tetrahedral mesh has about 5
edges per vertex (counted: 4.6 to 5.5), so P2 has about 6 nodes per vertex. Against the
counted P2 dofs the estimates are 0.97 to 1.21 (the finer meshes the higher); the box
and shell builders' structured meshes are counted exactly (the shell's edges by Euler's
formula). A ``.geo`` counts the surface term only: it may extrude its body in a few
layers, as ``meshes/belt.geo`` does (4.6e5 estimated P2 dofs at h = 5 mm, 4.1e5
counted); a bulky body meshed freely through its thickness has more.
"""
from __future__ import annotations

import functools
import inspect
import math
import pathlib
from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["Footprint", "of_builder", "of_file", "point_triangle_distance", "COARSE"]

#: the coarse probe mesh of a gmsh file: its size is at least the diagonal / COARSE
COARSE = 30.0
#: a .msh of more tetrahedra than this is measured from its counts only (no surface)
MAX_PROBE_TETS = 3_000_000


@dataclass
class Footprint:
    """What a structure's mesh occupies (m, after ``translate``) and its estimated size.

    ``distance(points)`` (n, 3) -> (n,) signed distance to the solid (negative inside;
    None when unknown); ``vertices`` (and for structured meshes ``edges``) estimated;
    ``how`` says in words where the estimate comes from."""

    lo: np.ndarray
    hi: np.ndarray
    area: float
    volume: float
    vertices: float
    how: str
    distance: Callable | None = None
    edges: float | None = None

    @property
    def extent(self) -> float:
        return float(np.max(self.hi - self.lo))

    def dofs(self, degree: int = 2, components: int = 3) -> float:
        """FE dofs of a Lagrange space of ``degree`` with ``components`` per node."""
        if degree == 1:
            return components * self.vertices
        edges = self.edges if self.edges is not None else 5.0 * self.vertices
        return components * (self.vertices + edges)


def _tet_vertices(area: float, volume: float, h: float) -> float:
    return 1.25 * area / h ** 2 + 0.5 * volume / h ** 3


# ---------------------------------------------------------------- signed distances
def _box_distance(lo, hi) -> Callable:
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)

    def distance(x, within=None):
        x = np.atleast_2d(np.asarray(x, float))
        q = np.maximum(lo - x, x - hi)                  # > 0 outside along that axis
        outside = np.linalg.norm(np.maximum(q, 0.0), axis=1)
        inside = np.minimum(q.max(axis=1), 0.0)
        return outside + inside
    return distance


def _section_distance(poly, axis: int, shift) -> Callable:
    """Signed distance to the solid of revolution about coordinate ``axis`` (through the
    origin, then shifted by ``shift``) whose wall section is the polygon ``poly`` of
    (distance from the axis, position along it) points."""
    P = np.asarray(poly, float)
    A, B = P, np.roll(P, -1, axis=0)
    shift = np.asarray(shift, float)
    others = [k for k in range(3) if k != axis]

    def distance(x, within=None):
        x = np.atleast_2d(np.asarray(x, float)) - shift
        q = np.column_stack([np.hypot(x[:, others[0]], x[:, others[1]]), x[:, axis]])
        ab = B - A
        t = np.clip(((q[:, None, :] - A[None]) * ab[None]).sum(2)
                    / np.maximum((ab * ab).sum(1), 1e-300)[None], 0.0, 1.0)
        d = np.linalg.norm(q[:, None, :] - (A[None] + t[..., None] * ab[None]), axis=2).min(1)
        # crossing number: horizontal ray from q towards +rho
        ya, yb = A[:, 1][None], B[:, 1][None]
        straddle = (ya > q[:, 1:2]) != (yb > q[:, 1:2])
        xc = A[:, 0][None] + (q[:, 1:2] - ya) / np.where(yb - ya == 0, 1e-300, yb - ya) \
            * (B[:, 0] - A[:, 0])[None]
        inside = (straddle & (q[:, 0:1] < xc)).sum(1) % 2 == 1
        return np.where(inside, -d, d)
    return distance


def _revolved(poly, axis: int, shift, vertices=None, edges=None, h=None, how="") -> Footprint:
    """Footprint of a solid of revolution (Pappus: area 2 pi sum rho_mid L, volume
    2 pi x first moment of the section)."""
    P = np.asarray(poly, float)
    A, B = P, np.roll(P, -1, axis=0)
    seg = np.linalg.norm(B - A, axis=1)
    area = float(2 * math.pi * (0.5 * (A[:, 0] + B[:, 0]) * seg).sum())
    cross = A[:, 0] * B[:, 1] - B[:, 0] * A[:, 1]
    sec = 0.5 * cross.sum()
    moment = ((A[:, 0] + B[:, 0]) * cross).sum() / 6.0            # int rho dA (signed)
    volume = float(2 * math.pi * abs(moment)) if sec else 0.0
    r_max = float(P[:, 0].max())
    lo, hi = np.full(3, -r_max), np.full(3, r_max)
    lo[axis], hi[axis] = P[:, 1].min(), P[:, 1].max()
    shift = np.asarray(shift, float)
    if vertices is None:
        vertices = _tet_vertices(area, volume, h)
    return Footprint(lo=lo + shift, hi=hi + shift, area=area, volume=volume,
                     vertices=float(vertices), edges=edges, how=how,
                     distance=_section_distance(P, axis, shift))


def _boxed(size, shift, vertices, edges=None, how="") -> Footprint:
    size = np.asarray(size, float)
    shift = np.asarray(shift, float)
    area = 2.0 * float(size[0] * size[1] + size[1] * size[2] + size[2] * size[0])
    return Footprint(lo=shift.copy(), hi=shift + size, area=area, volume=float(np.prod(size)),
                     vertices=float(vertices), edges=edges, how=how,
                     distance=_box_distance(shift, shift + size))


# ---------------------------------------------------------------- builders
def _params(name: str, geometry: dict) -> dict:
    from gsi.meshes import BUILDERS
    p = {k: v.default for k, v in inspect.signature(BUILDERS[name]).parameters.items()
         if k not in ("comm", "root")}
    p.update(geometry)
    return p


def _cone_wall(r0, R, height, t):
    """(normal-thickness horizontal width d, tan of the half-angle) of a conical wall."""
    tan_t = (R - r0) / height
    return t * math.sqrt(1.0 + tan_t ** 2), tan_t


def of_builder(name: str, geometry: dict, translate=(0.0, 0.0, 0.0)) -> Footprint | None:
    """The body the builder ``name`` makes from ``geometry`` (validated values, m).
    Raises the builder's own one-line GsiInputError (``structure.<name>.<key>``) for
    values it would refuse when meshing (shape names, an outlet wider than the top,
    a layer count that is not a whole number)."""
    from gsi.errors import GsiInputError
    from gsi.meshes._common import check_less
    p = _params(name, geometry)
    h = p.get("h")
    if name == "membrane" and p["shape"] not in ("rectangle", "circle"):
        raise GsiInputError(f"structure.membrane.shape = {p['shape']!r}: must be 'rectangle' "
                            "or 'circle'")
    if name == "silo" and p["bottom"] not in ("flat", "conical"):
        raise GsiInputError(f"structure.silo.bottom = {p['bottom']!r}: must be 'flat' or "
                            "'conical'")
    if name == "hopper":
        check_less("hopper", "outlet_radius", p["outlet_radius"], "top_radius", p["top_radius"])
    if name == "shell" or (name == "silo" and p["bottom"] == "conical"):
        check_less(name, "outlet_radius", p["outlet_radius"], "radius", p["radius"])
    words = f"the '{name}' builder's body, h = {h:g} m" if h is not None else ""
    if name == "box":
        L = np.array([p["length_x"], p["length_y"], p["length_z"]], float)
        n = (np.maximum(1, np.ceil(L / h - 1e-9)) if h is not None
             else np.asarray(p["n"], float))
        nx, ny, nz = n
        vertices = (nx + 1) * (ny + 1) * (nz + 1)
        edges = (nx * (ny + 1) * (nz + 1) + (nx + 1) * ny * (nz + 1) + (nx + 1) * (ny + 1) * nz
                 + nx * ny * (nz + 1) + nx * (ny + 1) * nz + (nx + 1) * ny * nz + nx * ny * nz)
        return _boxed(L, translate, vertices, edges,
                      f"the 'box' builder's {int(nx)} x {int(ny)} x {int(nz)} cells")
    if name == "membrane":
        t, layers = p["thickness"], p["n_thickness"]
        if p["shape"] == "rectangle":
            a, b = p["length_x"], p["length_y"]
            plane = 1.15 * a * b / h ** 2 + 2 * (a + b) / h
            return _boxed((a, b, t), translate, (layers + 1) * plane, how=words)
        R = p["radius"]
        plane = 1.15 * math.pi * R * R / h ** 2 + 2 * math.pi * R / h
        return _revolved([(0.0, 0.0), (R, 0.0), (R, t), (0.0, t)], 2, translate,
                         vertices=(layers + 1) * plane, how=words)
    if name == "hopper":
        r0, R, H, t = p["outlet_radius"], p["top_radius"], p["height"], p["thickness"]
        d, _ = _cone_wall(r0, R, H, t)
        return _revolved([(r0, 0.0), (r0 + d, 0.0), (R + d, H), (R, H)], 2, translate,
                         h=h, how=words)
    if name == "drum":
        R, L, t = p["radius"], p["length"], p["thickness"]
        return _revolved([(R, 0.0), (R + t, 0.0), (R + t, L), (R, L)], 0, translate,
                         h=h, how=words)
    if name == "silo" and p["bottom"] == "flat":
        R, H, t = p["radius"], p["height"], p["thickness"]
        return _revolved([(0.0, -t), (R + t, -t), (R + t, H), (R, H), (R, 0.0), (0.0, 0.0)], 2,
                         translate, h=h, how=words)
    if name in ("silo", "shell"):
        R, H, t = p["radius"], p["height"], p["thickness"]
        hc, r0 = p["hopper_height"], p["outlet_radius"]
        d, tan_t = _cone_wall(r0, R, hc, t)
        z_j = (t - d) / tan_t
        poly = [(r0, -hc), (r0 + d, -hc), (R + t, z_j), (R + t, H), (R, H), (R, 0.0)]
        if name == "silo":
            return _revolved(poly, 2, translate, h=h, how=words)
        from gsi.meshes.shell import estimate_dofs
        keys = ("radius", "height", "hopper_height", "outlet_radius", "h", "n_thickness")
        vertices = estimate_dofs(**{k: p[k] for k in keys}, degree=1, components=1)
        nodes = estimate_dofs(**{k: p[k] for k in keys}, degree=2, components=1)
        return _revolved(poly, 2, translate, vertices=vertices, edges=nodes - vertices,
                         how="the 'shell' builder's structured mesh")
    return None           # a builder without a footprint here: no estimate, no check


# ---------------------------------------------------------------- gmsh files
def point_triangle_distance(P: np.ndarray, A, B, C) -> np.ndarray:
    """Distance (n, m) of points P (n, 3) to triangles (A, B, C) (m, 3 each): to the plane
    when the projection falls inside, else to the nearest edge. Every quantity is a dot
    product of a point with a triangle's vectors, so the (n, m) arrays come from matrix
    products: |d|^2, d.e0, d.e1 and d.n with d = P - A, e0 = B - A, e1 = C - A."""
    P = np.asarray(P, float)
    e0, e1 = B - A, C - A
    n = np.cross(e0, e1)
    nn = np.linalg.norm(n, axis=1)
    n = n / np.maximum(nn, 1e-300)[:, None]
    a, b, c = (e0 * e0).sum(1), (e0 * e1).sum(1), (e1 * e1).sum(1)
    dd = (P * P).sum(1)[:, None] - 2.0 * P @ A.T + (A * A).sum(1)[None]
    d0 = P @ e0.T - (A * e0).sum(1)[None]
    d1 = P @ e1.T - (A * e1).sum(1)[None]
    dn = P @ n.T - (A * n).sum(1)[None]
    det = np.maximum(a * c - b * b, 1e-300)
    s = (c * d0 - b * d1) / det
    t = (a * d1 - b * d0) / det
    inside = (s >= 0) & (t >= 0) & (s + t <= 1) & (nn > 0)[None]

    def seg(dq, proj, length2):       # squared distance to a segment from its start
        u = np.clip(proj / np.maximum(length2, 1e-300), 0.0, 1.0)
        return dq - 2.0 * u * proj + u * u * length2
    e2 = a + c - 2.0 * b
    edge = np.minimum(np.minimum(seg(dd, d0, a), seg(dd, d1, c)),
                      seg(dd - 2.0 * d0 + a, d1 - d0 - b + a, e2))
    return np.where(inside, np.abs(dn), np.sqrt(np.maximum(edge, 0.0)))


#: the parity ray: nearly +z, tilted so that it hits no edge of an axis-aligned mesh
_RAY = np.array([0.0137, 0.0071, 1.0]) / np.linalg.norm([0.0137, 0.0071, 1.0])
#: points per chunk of the distance computation
_CHUNK = 256


def _surface_distance(V, T) -> Callable:
    """Signed distance to the closed triangulated surface (V, T): the nearest triangle,
    negative where the ray :data:`_RAY` from the point crosses the surface an odd number of
    times. ``within``: distances beyond it are returned as ``within`` (only the triangles
    that near are looked at; the sign is exact)."""
    A, B, C = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    t_lo, t_hi = np.minimum(np.minimum(A, B), C), np.maximum(np.maximum(A, B), C)
    z_top = float(V[:, 2].max())
    e1, e2 = B - A, C - A
    # Moeller-Trumbore with s = P - A: u = s.(R x e2)/det, v = s.(e1 x R)/det,
    # t = s.(e1 x e2)/det, det = e1.(R x e2): each a matrix product
    w_u, w_v, w_t = np.cross(_RAY, e2), np.cross(e1, _RAY), np.cross(e1, e2)
    det = (e1 * w_u).sum(1)
    ok = np.abs(det) > 1e-300
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)

    def parity(P, sel):
        def coord(wv):
            return (P @ wv[sel].T - (A[sel] * wv[sel]).sum(1)[None]) * inv[sel][None]
        u, v, t = coord(w_u), coord(w_v), coord(w_t)
        hits = ok[sel][None] & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        return hits.sum(1) % 2 == 1

    def distance(x, within=None):
        x = np.atleast_2d(np.asarray(x, float))
        w = np.inf if within is None else float(within)
        out = np.empty(len(x))
        for k in range(0, len(x), _CHUNK):
            P = x[k:k + _CHUNK]
            lo, hi = P.min(0), P.max(0)
            sel = np.flatnonzero(((t_hi >= lo - w) & (t_lo <= hi + w)).all(1))
            d = (point_triangle_distance(P, A[sel], B[sel], C[sel]).min(1) if len(sel)
                 else np.full(len(P), w))
            d = np.minimum(d, w)
            reach = _RAY[:2] / _RAY[2] * max(0.0, z_top - float(lo[2]))
            col = np.flatnonzero((t_hi[:, 2] >= lo[2])
                                 & (t_hi[:, :2] >= lo[:2]).all(1)
                                 & (t_lo[:, :2] <= hi[:2] + np.maximum(reach, 0)).all(1))
            inside = parity(P, col) if len(col) else np.zeros(len(P), bool)
            out[k:k + _CHUNK] = np.where(inside, -d, d)
        return out
    return distance


def of_file(path, params: dict | None = None, translate=(0.0, 0.0, 0.0)) -> Footprint | None:
    """The body of a gmsh ``.geo`` (with its ``DefineConstant`` overrides ``params``) or
    ``.msh`` file; None when gmsh cannot probe it (the build reports why)."""
    path = pathlib.Path(path)
    try:
        stamp = path.stat().st_mtime_ns
    except OSError:
        return None
    items = tuple(sorted((k, v) for k, v in (params or {}).items()
                         if isinstance(v, (int, float)) and not isinstance(v, bool)))
    got = _probe(str(path), stamp, items)
    if got is None:
        return None
    V, T, volume, h, vertices, edges, words = got
    shift = np.asarray(translate, float)
    V = V + shift
    if T is None:
        return Footprint(lo=V.min(0), hi=V.max(0), area=0.0, volume=volume, vertices=vertices,
                         edges=edges, how=words)
    A, B, C = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    area = float(0.5 * np.linalg.norm(np.cross(B - A, C - A), axis=1).sum())
    if vertices is None:      # the surface term only: a .geo may extrude in few layers
        vertices = _tet_vertices(area, 0.0, h)
    return Footprint(lo=V.min(0), hi=V.max(0), area=area, volume=volume, vertices=vertices,
                     edges=edges, how=words, distance=_surface_distance(V, T))


def _boundary(nodes: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, float]:
    """(boundary triangles as rows of node indices, volume) of a tetrahedral mesh."""
    faces = np.concatenate([tets[:, [0, 1, 2]], tets[:, [0, 1, 3]], tets[:, [0, 2, 3]],
                            tets[:, [1, 2, 3]]])
    key = np.sort(faces, axis=1)
    _, first, count = np.unique(key, axis=0, return_index=True, return_counts=True)
    a, b, c, d = (nodes[tets[:, k]] for k in range(4))
    volume = float(np.abs(np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a)).sum() / 6.0)
    return faces[first[count == 1]], volume


@functools.lru_cache(maxsize=16)
def _probe(path: str, stamp: int, params: tuple):
    """(vertices, boundary triangles, volume, h, mesh vertices or None, edges or None,
    words) of a gmsh file (module docstring), or None. Cached per file version."""
    import gmsh
    from gsi.errors import GsiInputError
    from gsi.meshes.file import check_readable
    path = pathlib.Path(path)
    try:
        check_readable(path, "structure")   # a binary file would harm gmsh's parser
    except GsiInputError:
        return None
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        # no "very large mesh: do you really want to continue?" prompt on stdout (it
        # waits for an answer in a terminal)
        gmsh.option.setNumber("General.ExpertMode", 1)
        gmsh.onelab.clear()
        if path.suffix.lower() == ".geo" and params:
            gmsh.open(str(path))
            names = [n for n in gmsh.onelab.getNames() if not n.startswith(("Gmsh/", "ONELAB/"))]
            for k, v in params:
                full = [n for n in names if n == k or n.rsplit("/", 1)[-1] == k]
                if len(full) == 1:
                    gmsh.onelab.setNumber(full[0], [float(v)])
            gmsh.clear()
        gmsh.open(str(path))
        x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(-1, -1)
        diag = math.dist((x0, y0, z0), (x1, y1, z1))
        if path.suffix.lower() == ".msh":
            return _probe_msh(gmsh, path.name)
        if not (diag > 0 and math.isfinite(diag)):
            return None
        h = _curve_size(gmsh, diag)
        if h is None:
            return None
        gmsh.model.mesh.clear()
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 24)
        gmsh.option.setNumber("Mesh.MeshSizeMin", diag / (10 * COARSE))
        gmsh.option.setNumber("Mesh.MeshSizeMax", diag / COARSE)
        gmsh.model.mesh.generate(3)
        nodes, tets = _tets(gmsh)
        if tets is None:
            return None
        T, volume = _boundary(nodes, tets)
        return nodes, T, volume, h, None, None, f"mesh size h = {h:.3g} m ({path.name})"
    except Exception:     # a file gmsh cannot probe: the build reports it
        return None
    finally:
        gmsh.finalize()


def _curve_size(gmsh, diag: float) -> float | None:
    """Mean segment length of a 1D mesh of the model's curves at its own sizes (floored at
    1/5000 of the diagonal so the probe stays cheap)."""
    gmsh.option.setNumber("Mesh.MeshSizeMin", diag / 5000.0)
    gmsh.model.mesh.generate(1)
    length, segments = 0.0, 0
    for dim, tag in gmsh.model.getEntities(1):
        _, elems, _ = gmsh.model.mesh.getElements(dim, tag)
        k = sum(len(e) for e in elems)
        if k:
            a, b = gmsh.model.getParametrizationBounds(dim, tag)
            x = gmsh.model.getValue(dim, tag, [a[0] + (b[0] - a[0]) * t / 64.0
                                               for t in range(65)])
            pts = [x[3 * i:3 * i + 3] for i in range(65)]
            length += sum(math.dist(pts[i], pts[i + 1]) for i in range(64))
            segments += k
    return length / segments if segments else None


def _tets(gmsh):
    """(node coordinates (n, 3), linear tetrahedra as rows of indices into them) or
    (nodes, None) without tetrahedra."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    nodes = np.asarray(coords, float).reshape(-1, 3)
    index = np.zeros(int(tags.max()) + 1 if len(tags) else 1, dtype=np.int64)
    index[np.asarray(tags, np.int64)] = np.arange(len(tags))
    rows = []
    for etype, _, enodes in zip(*gmsh.model.mesh.getElements(3)):
        name, _, _, n_nodes, _, _ = gmsh.model.mesh.getElementProperties(etype)
        if name.lower().startswith("tetrahedron"):
            rows.append(np.asarray(enodes, np.int64).reshape(-1, n_nodes)[:, :4])
    if not rows:
        return nodes, None
    return nodes, index[np.concatenate(rows)]


def _probe_msh(gmsh, shown: str):
    """The ``.msh`` as it is: its vertex count, its edges by Euler's formula (V - E + F - T
    = 1, 2F = 4T + F_boundary), h the mean edge of its tetrahedra."""
    nodes, tets = _tets(gmsh)
    if tets is None:
        return None
    used = np.unique(tets)
    n_t = len(tets)
    sample = tets[:: max(1, n_t // 20000)]
    h = float(np.mean([np.linalg.norm(nodes[sample[:, a]] - nodes[sample[:, b]], axis=1).mean()
                       for a, b in ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3))]))
    if n_t > MAX_PROBE_TETS:      # counts only: no surface, no distance
        return nodes[used], None, 0.0, h, float(len(used)), float(len(used) + 1.5 * n_t), \
            f"{n_t} tetrahedra in {shown}"
    T, volume = _boundary(nodes, tets)
    edges = len(used) + n_t + len(T) / 2.0 - 1.0
    return nodes, T, volume, h, float(len(used)), float(edges), \
        f"{len(used)} vertices, {n_t} tetrahedra in {shown}"
