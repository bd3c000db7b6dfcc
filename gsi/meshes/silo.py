"""Cylindrical silo / bin with a flat or conical bottom and a wall of finite thickness.

Axis z. The inner cylinder has radius ``radius`` from z = 0 to z = ``height`` (open top).
* ``bottom = "flat"``: a floor plate of thickness ``thickness`` below z = 0.
* ``bottom = "conical"``: a hopper from the inner radius at z = 0 down to the outlet of
  radius ``outlet_radius`` at z = -``hopper_height`` (normal wall thickness ``thickness``).

Tags: "contact" (all inner, bulk-solid-facing surfaces), "support" (flat: the underside of
the floor, z = -thickness; conical: the outlet rim annulus at z = -hopper_height),
"outer" (outer lateral surfaces), "top" (top rim annulus), "volume".
"""
from __future__ import annotations

import math

import numpy as np
from mpi4py import MPI

from gsi.errors import GsiInputError

from ._common import (GmshSession, StructureMesh, check_less, check_positive, finish, near,
                      tag_and_mesh)

NAMES = ["contact", "support", "outer", "top"]


def build(*, radius: float = 0.5, height: float = 1.0, thickness: float = 0.01,
          bottom: str = "flat", hopper_height: float = 0.4, outlet_radius: float = 0.1,
          h: float = 0.08, comm: MPI.Comm = MPI.COMM_WORLD,
          root: int = 0) -> StructureMesh:
    """Build a silo wall.

    Parameters
    ----------
    radius : float
        Inner radius of the cylinder (m).
    height : float
        Height of the cylindrical part above z = 0 (m).
    thickness : float
        Wall (and floor) thickness (m).
    bottom : {"flat", "conical"}
        Bottom type.
    hopper_height, outlet_radius : float
        Conical bottom only: vertical depth of the hopper (m), inner outlet radius (m).
    h : float
        Element size (m).
    comm, root : MPI communicator and the rank that runs gmsh.
    """
    if bottom not in ("flat", "conical"):
        raise GsiInputError(f"structure.silo.bottom = {bottom!r}: must be 'flat' or 'conical'")
    check_positive("silo", radius=radius, height=height, thickness=thickness, h=h)
    if bottom == "conical":
        check_positive("silo", hopper_height=hopper_height, outlet_radius=outlet_radius)
        check_less("silo", "outlet_radius", outlet_radius, "radius", radius)
    params = dict(radius=radius, height=height, thickness=thickness, bottom=bottom,
                  hopper_height=hopper_height, outlet_radius=outlet_radius, h=h)
    R, t, H = radius, thickness, height
    tags = None
    with GmshSession(comm, root, "silo") as gmsh:
        if gmsh is not None:
            occ = gmsh.model.occ
            tol = max(1e-3 * t, 1e-7)
            if bottom == "flat":
                outer = occ.addCylinder(0, 0, -t, 0, 0, H + t, R + t)
                inner = occ.addCylinder(0, 0, 0, 0, 0, H + t, R)
                occ.cut([(3, outer)], [(3, inner)])

                def classify(tag, p, bbox):
                    if near(bbox[2], bbox[5], tol):
                        z = bbox[5]
                        if near(z, H, tol):
                            return "top"
                        return "contact" if near(z, 0.0, tol) else "support"
                    r = float(np.hypot(p[0], p[1]))
                    return "contact" if abs(r - R) < 0.5 * t else "outer"
            else:
                hc, r0 = hopper_height, outlet_radius
                tan_t = (R - r0) / hc
                d = t * math.sqrt(1.0 + tan_t**2)
                z_j = (t - d) / tan_t  # where the outer cone meets the outer cylinder (< 0)
                o_cone = occ.addCone(0, 0, -hc, 0, 0, hc + z_j, r0 + d, R + t)
                o_cyl = occ.addCylinder(0, 0, z_j, 0, 0, H - z_j, R + t)
                outer, _ = occ.fuse([(3, o_cone)], [(3, o_cyl)])
                i_cone = occ.addCone(0, 0, -hc, 0, 0, hc, r0, R)
                i_cyl = occ.addCylinder(0, 0, 0, 0, 0, H + t, R)
                i_out = occ.addCylinder(0, 0, -hc - 2 * t, 0, 0, 2 * t, r0)
                inner, _ = occ.fuse([(3, i_cone)], [(3, i_cyl), (3, i_out)])
                occ.cut(outer, inner)

                def classify(tag, p, bbox):
                    if near(bbox[2], bbox[5], tol):
                        return "top" if near(bbox[5], H, tol) else "support"
                    r, z = float(np.hypot(p[0], p[1])), float(p[2])
                    r_inner = R if z >= 0.0 else r0 + (z + hc) * tan_t
                    r_outer = R + t if z >= z_j else r0 + d + (z + hc) * tan_t
                    return "contact" if abs(r - r_inner) < abs(r - r_outer) else "outer"

            tags = tag_and_mesh(gmsh, classify=classify, names=NAMES, h=h,
                                builder="silo")
        return finish(gmsh, comm, root, tags, params)
