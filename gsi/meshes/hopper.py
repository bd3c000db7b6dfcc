"""Conical hopper shell with an outlet (axis z, outlet at the bottom).

The inner (contact) surface is the truncated cone from radius ``outlet_radius`` at z = 0
to ``top_radius`` at z = ``height``; the wall has normal thickness ``thickness`` (the outer
cone is the inner one shifted outwards horizontally by thickness / cos(half-angle)).

Tags: "contact" (inner conical surface), "support" (top rim annulus, z = height: the hopper
hangs from its top ring), "outer" (outer conical surface), "outlet" (bottom rim annulus,
z = 0), "volume".
"""
from __future__ import annotations

import math

import numpy as np
from mpi4py import MPI

from ._common import (GmshSession, StructureMesh, check_less, check_positive, finish, near,
                      tag_and_mesh)

NAMES = ["contact", "support", "outer", "outlet"]


def build(*, top_radius: float = 0.5, outlet_radius: float = 0.1, height: float = 0.6,
          thickness: float = 0.005, h: float = 0.05,
          comm: MPI.Comm = MPI.COMM_WORLD, root: int = 0) -> StructureMesh:
    """Build a conical hopper shell.

    Parameters
    ----------
    top_radius : float
        Inner radius at the top rim, z = height (m).
    outlet_radius : float
        Inner radius of the outlet, z = 0 (m); must be < top_radius.
    height : float
        Vertical height of the cone (m).
    thickness : float
        Wall thickness normal to the cone (m).
    h : float
        Element size (m).
    comm, root : MPI communicator and the rank that runs gmsh.
    """
    check_positive("hopper", top_radius=top_radius, outlet_radius=outlet_radius,
                   height=height, thickness=thickness, h=h)
    check_less("hopper", "outlet_radius", outlet_radius, "top_radius", top_radius)
    params = dict(top_radius=top_radius, outlet_radius=outlet_radius, height=height,
                  thickness=thickness, h=h)
    tan_t = (top_radius - outlet_radius) / height
    d = thickness * math.sqrt(1.0 + tan_t**2)  # = thickness / cos(half-angle)
    tags = None
    with GmshSession(comm, root, "hopper") as gmsh:
        if gmsh is not None:
            occ = gmsh.model.occ
            outer = occ.addCone(0, 0, 0, 0, 0, height, outlet_radius + d, top_radius + d)
            inner = occ.addCone(0, 0, 0, 0, 0, height, outlet_radius, top_radius)
            occ.cut([(3, outer)], [(3, inner)])
            tol = max(1e-3 * thickness, 1e-7)

            def classify(tag, p, bbox):
                if near(bbox[2], bbox[5], tol):
                    return "support" if near(bbox[5], height, tol) else "outlet"
                r = float(np.hypot(p[0], p[1]))
                r_in = outlet_radius + p[2] * tan_t
                return "contact" if abs(r - r_in) < 0.5 * d else "outer"

            tags = tag_and_mesh(gmsh, classify=classify, names=NAMES, h=h,
                                builder="hopper")
        return finish(gmsh, comm, root, tags, params)
