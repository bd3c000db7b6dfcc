"""Element bounds of the heat problem (P1 simplices; see :mod:`gsi.fem.heat`): the largest
eigenvalue of C^-1 K (the theta-scheme's explicit limit) and the boundary factor of the
explicit radiation limit. Each is this rank's part (the caller reduces with MAX)."""
from __future__ import annotations

import math

import numpy as np

from gsi.errors import GsiInputError

from . import compat


def check_options(dt, theta, degree, theta_key: str) -> None:
    """Refuse a step ``dt`` <= 0, ``theta`` outside [0, 1] (named ``theta_key``), a
    ``degree`` other than 1 or 2, and an explicit theta < 1/2 above degree 1 (the bound
    is for P1)."""
    if not (dt is not None and np.isfinite(dt) and dt > 0):
        raise GsiInputError(f"structure.heat.dt = {dt!r}: must be > 0 (s)")
    if not 0.0 <= theta <= 1.0:
        raise GsiInputError(f"{theta_key} = {theta!r}: must be in [0, 1]")
    if degree not in (1, 2):
        raise GsiInputError(f"structure.heat.degree = {degree!r}: must be 1 or 2")
    if theta < 0.5 and degree != 1:
        raise GsiInputError(f"{theta_key} = {theta!r}: below 0.5 (explicit) needs degree 1 "
                            f"(its stability bound is for P1); use degree = 1 or theta >= 0.5")


def stable_dt(theta: float, lam: float) -> float:
    """Largest stable step (s) of the theta-scheme, 2/((1 - 2 theta) lambda) for theta <
    1/2 and a bound ``lam`` > 0 (1/s) of the largest eigenvalue; inf otherwise."""
    if theta >= 0.5 or not lam > 0:
        return math.inf
    return 2.0 / ((1.0 - 2.0 * theta) * lam)


def check_explicit_step(dt: float, theta: float, limit: float, theta_key: str) -> None:
    """Refuse (GsiInputError naming ``theta_key``) a step ``dt`` above the stable
    ``limit`` (s)."""
    if dt > limit:
        raise GsiInputError(
            f"{theta_key} = {theta:g}: the step dt = {dt:.4g} s is above the "
            f"explicit stability limit {limit:.4g} s (2/((1 - 2 theta) lambda_max), P1 "
            f"element bound); lower dt or use theta >= 0.5")


def _facet_areas(mesh, facet_tags, tag_id, x, d) -> dict:
    """Area of each facet of tag ``tag_id``, keyed by its sorted node tuple."""
    facets = compat.meshtag_find(facet_tags, tag_id)
    if len(facets) == 0:
        return {}
    fn = compat.entities_to_geometry(mesh, d - 1, facets)
    E = x[fn][:, 1:, :] - x[fn][:, :1, :]
    A = np.sqrt(np.abs(np.linalg.det(np.einsum("nia,nja->nij", E, E)))) / math.factorial(d - 1)
    return {tuple(sorted(f)): a for f, a in zip(fn.tolist(), A)}


def _cell_volumes(X, d):
    J = np.transpose(X[:, 1:, :] - X[:, :1, :], (0, 2, 1))   # columns: edges from node 0
    JtJ = np.einsum("nai,naj->nij", J, J)
    return J, JtJ, np.sqrt(np.abs(np.linalg.det(JtJ))) / math.factorial(d)


def _add_facet_terms(out, cells, area, d, h, rho, c, V):
    """out[c] (in place) += (d+1)(d+2) h A/(d rho c V_c) over the tagged facets of each
    cell c; with ``out`` None, returns the largest term instead."""
    best = 0.0
    for cell, nodes in enumerate(cells.tolist()):
        for skip in range(d + 1):
            key = tuple(sorted(nodes[:skip] + nodes[skip + 1:]))
            if key in area:
                term = (d + 1) * (d + 2) * h * area[key] / (d * rho * c * V[cell])
                if out is None:
                    best = max(best, term)
                else:
                    out[cell] += term
    return best


def facet_factor(mesh, structure, name, material) -> float:
    """max over the cells at the facets of ``name`` of (d+1)(d+2) A/(d rho c V)
    (1/(s W/(m^2 K)))."""
    x = compat.geometry_x(mesh)
    cells = compat.geometry_dofmap(mesh)
    d = mesh.topology.dim
    area = _facet_areas(mesh, structure.facet_tags, structure.tags[name], x, d)
    if not area:
        return 0.0
    cells = cells[:, :d + 1]
    _, _, V = _cell_volumes(x[cells], d)
    return _add_facet_terms(None, cells, area, d, 1.0, material.rho, material.c, V)


def eigenvalue_bound(mesh, structure, material, h: dict) -> float:
    """Upper bound (1/s) of the largest eigenvalue of C^-1 K on this rank's cells
    (conduction and the convection ``h`` {tag: W/(m^2 K)}; straight P1 simplices)."""
    m = material
    x = compat.geometry_x(mesh)
    cells = compat.geometry_dofmap(mesh)
    d = mesh.topology.dim
    J, JtJ, V = _cell_volumes(x[cells], d)
    Jinv = np.linalg.solve(JtJ, np.transpose(J, (0, 2, 1)))  # rows: gradients of nodes 1..d
    G = np.concatenate([-Jinv.sum(1, keepdims=True), Jinv], axis=1)  # (n, d+1, 3)
    GtG = np.einsum("nia,nib->nab", G, G)
    lam = (d + 1) * (d + 2) * (m.k / (m.rho * m.c)) * np.linalg.eigvalsh(GtG)[:, -1]
    for name, hv in h.items():
        if hv <= 0.0:
            continue
        area = _facet_areas(mesh, structure.facet_tags, structure.tags[name], x, d)
        if area:
            _add_facet_terms(lam, cells, area, d, hv, m.rho, m.c, V)
    return float(lam.max()) if len(lam) else 0.0
