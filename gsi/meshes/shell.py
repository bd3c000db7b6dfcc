"""Silo shell with a structured wall: a cylinder on a conical hopper, revolved from its profile.

Made for large structures (benchmarks/fe_scale.py): unlike :mod:`gsi.meshes.silo` (gmsh's
unstructured Delaunay mesh of the solid), the wall here is a structured mesh with exactly
``n_thickness`` element layers through the thickness whatever the in-plane size ``h``,
so one parameter takes the P2 problem from 10^4 to 10^6 dofs with the same wall
resolution. The profile (the wall section in the (r, z) half-plane) is meshed as
transfinite quadrilateral patches split into triangles and revolved about the z axis in
four quarter turns with ``n_theta / 4`` layers each; gmsh splits each revolved prism into
three tetrahedra.

Geometry (axis z, as :mod:`gsi.meshes.silo` with ``bottom = "conical"``): the inner cylinder
of radius ``radius`` from z = 0 to z = ``height`` (open top), on a hopper from the inner
radius at z = 0 down to the outlet of inner radius ``outlet_radius`` at
z = -``hopper_height``; normal wall thickness ``thickness``. The outlet rim and the top
rim are horizontal annuli.

Tags: "contact" (inner surfaces), "support" (the outlet rim annulus, z = -hopper_height),
"outer" (outer surfaces), "top" (top rim annulus), "volume".

The gmsh model exists on rank ``root`` only; dolfinx distributes it (``finish``).
:func:`estimate_dofs` gives the size of a mesh before it is built and :func:`h_for_dofs`
the ``h`` of a wanted size.
"""
from __future__ import annotations

import math

import numpy as np
from mpi4py import MPI

from gsi.errors import GsiInputError

from ._common import VOLUME_TAG, GmshSession, check_less, check_positive, finish, near

NAMES = ["contact", "support", "outer", "top"]


def _profile(radius, height, thickness, hopper_height, outlet_radius):
    """Inner and outer profile points (r, z), bottom to top, and the outer kink height."""
    R, t, hc, r0 = radius, thickness, hopper_height, outlet_radius
    tan_t = (R - r0) / hc
    d = t * math.sqrt(1.0 + tan_t**2)          # horizontal wall width of the cone
    z_j = (t - d) / tan_t                       # outer cone meets the outer cylinder (< 0)
    inner = [(r0, -hc), (R, 0.0), (R, height)]
    outer = [(r0 + d, -hc), (R + t, z_j), (R + t, height)]
    return inner, outer, tan_t, d, z_j


def _divisions(radius, height, hopper_height, outlet_radius, h):
    """(elements along the hopper and the cylinder generators, elements around)."""
    slant = math.hypot(radius - outlet_radius, hopper_height)
    n_along = [max(1, math.ceil(slant / h)), max(1, math.ceil(height / h))]
    n_theta = 4 * max(2, math.ceil(2.0 * math.pi * radius / (4.0 * h)))
    return n_along, n_theta


def estimate_dofs(*, radius: float = 0.5, height: float = 1.0, hopper_height: float = 0.4,
                  outlet_radius: float = 0.1, h: float = 0.05, n_thickness: int = 2,
                  degree: int = 2, components: int = 3) -> int:
    """Global dofs of the Lagrange space of ``degree`` on the mesh :func:`build` makes
    (exact for degree 1, within ~1 % for degree 2: nodes = vertices + edges, the edges
    counted by Euler's formula for a solid ring)."""
    n_along, n_theta = _divisions(radius, height, hopper_height, outlet_radius, h)
    na = sum(n_along)
    V = (n_thickness + 1) * (na + 1) * n_theta
    if degree == 1:
        return components * V
    T = 3 * 2 * n_thickness * na * n_theta                  # 2 triangles per quad, 3 tets per prism
    Fb = 2 * 2 * na * n_theta + 2 * 2 * n_thickness * n_theta   # boundary triangles
    E = V + T + Fb // 2                                     # V - E + F - T = 0, 2F = 4T + Fb
    return components * (V + E)


def h_for_dofs(n_dofs: float, **geometry) -> float:
    """The element size ``h`` (m) whose mesh has about ``n_dofs`` dofs (P2 vectors unless
    ``degree``/``components`` given): bisection on :func:`estimate_dofs`."""
    lo, hi = 1e-4, 1.0
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        if estimate_dofs(h=mid, **geometry) > n_dofs:
            lo = mid
        else:
            hi = mid
    return hi


def build(*, radius: float = 0.5, height: float = 1.0, thickness: float = 0.01,
          hopper_height: float = 0.4, outlet_radius: float = 0.1, h: float = 0.05,
          n_thickness: int = 2, comm: MPI.Comm = MPI.COMM_WORLD,
          root: int = 0):
    """Build the silo shell.

    Parameters
    ----------
    radius : float
        Inner radius of the cylinder (m).
    height : float
        Height of the cylinder above z = 0 (m).
    thickness : float
        Normal wall thickness (m).
    hopper_height, outlet_radius : float
        Vertical depth of the hopper (m) and inner radius of its outlet (m).
    h : float
        In-plane element size (m), along the generators and around.
    n_thickness : int
        Element layers through the thickness (>= 1; default 2).
    comm, root : MPI communicator and the rank that runs gmsh.

    Returns
    -------
    StructureMesh
    """
    check_positive("shell", radius=radius, height=height, thickness=thickness,
                   hopper_height=hopper_height, outlet_radius=outlet_radius, h=h)
    check_less("shell", "outlet_radius", outlet_radius, "radius", radius)
    if isinstance(n_thickness, bool) or int(n_thickness) != n_thickness or n_thickness < 1:
        raise GsiInputError(f"structure.shell.n_thickness = {n_thickness!r}: must be an integer >= 1")
    n_thickness = int(n_thickness)
    params = dict(radius=radius, height=height, thickness=thickness, hopper_height=hopper_height,
                  outlet_radius=outlet_radius, h=h, n_thickness=n_thickness)
    inner, outer, tan_t, d, z_j = _profile(radius, height, thickness, hopper_height, outlet_radius)
    n_along, n_theta = _divisions(radius, height, hopper_height, outlet_radius, h)
    tags = None
    with GmshSession(comm, root, "shell") as gmsh:
        if gmsh is not None:
            tags = _make(gmsh, inner, outer, n_along, n_theta, n_thickness,
                         radius=radius, height=height, thickness=thickness,
                         hopper_height=hopper_height, outlet_radius=outlet_radius,
                         tan_t=tan_t, d=d, z_j=z_j)
        return finish(gmsh, comm, root, tags, params)


def _make(gmsh, inner, outer, n_along, n_theta, n_thickness, *, radius, height, thickness,
          hopper_height, outlet_radius, tan_t, d, z_j) -> dict[str, int]:
    """The revolved, tagged and meshed model on the gmsh rank; name -> group number."""
    geo = gmsh.model.geo
    p_in = [geo.addPoint(r, 0.0, z) for r, z in inner]
    p_out = [geo.addPoint(r, 0.0, z) for r, z in outer]
    across = [geo.addLine(a, b) for a, b in zip(p_in, p_out)]
    for c in across:
        geo.mesh.setTransfiniteCurve(c, n_thickness + 1)
    profile = []
    for i, n in enumerate(n_along):
        li = geo.addLine(p_in[i], p_in[i + 1])
        lo = geo.addLine(p_out[i], p_out[i + 1])
        geo.mesh.setTransfiniteCurve(li, n + 1)
        geo.mesh.setTransfiniteCurve(lo, n + 1)
        s = geo.addPlaneSurface([geo.addCurveLoop([li, across[i + 1], -lo, -across[i]])])
        geo.mesh.setTransfiniteSurface(s)
        profile.append((2, s))
    src, vols = profile, []
    for _ in range(4):                          # gmsh's revolve needs angles < pi
        out = geo.revolve(src, 0, 0, 0, 0, 0, 1, 0.5 * math.pi, numElements=[n_theta // 4])
        src = [out[k] for k in range(len(out) - 1) if out[k][0] == 2 and out[k + 1][0] == 3]
        vols += [e[1] for e in out if e[0] == 3]
    geo.removeAllDuplicates()                   # the last quarter's end face is the first's start
    geo.synchronize()
    vols = [tag for _, tag in gmsh.model.getEntities(3)]
    H, hc, r0, R, t = height, hopper_height, outlet_radius, radius, thickness
    tol = 1e-3 * t
    groups: dict[str, list[int]] = {n: [] for n in NAMES}
    for dim, tag in gmsh.model.getBoundary([(3, v) for v in vols], oriented=False,
                                           combined=True):
        bbox = gmsh.model.getBoundingBox(dim, tag)
        if near(bbox[2], bbox[5], tol):
            groups["top" if near(bbox[5], H, tol) else "support"].append(tag)
            continue
        lo, hi = gmsh.model.getParametrizationBounds(2, tag)
        p = np.asarray(gmsh.model.getValue(2, tag, list(0.5 * (np.asarray(lo) + np.asarray(hi)))))
        r, z = float(np.hypot(p[0], p[1])), float(p[2])
        r_inner = R if z >= 0.0 else r0 + (z + hc) * tan_t
        r_outer = R + t if z >= z_j else r0 + d + (z + hc) * tan_t
        groups["contact" if abs(r - r_inner) < abs(r - r_outer) else "outer"].append(tag)
    tags: dict[str, int] = {}
    for i, n in enumerate(NAMES, start=1):
        if not groups[n]:
            raise RuntimeError(f"shell: no surface classified as {n!r}")
        gmsh.model.addPhysicalGroup(2, groups[n], i)
        gmsh.model.setPhysicalName(2, i, n)
        tags[n] = i
    gmsh.model.addPhysicalGroup(3, vols, VOLUME_TAG)
    gmsh.model.setPhysicalName(3, VOLUME_TAG, "volume")
    tags["volume"] = VOLUME_TAG
    gmsh.model.mesh.generate(3)
    return tags
