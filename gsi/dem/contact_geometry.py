"""Contact geometry shared by the contact laws, the heat models and radiation.

One place for the overlap, the unit normal, the lever arms and the contact radius a
(docs/design.md, "Contact geometry"):

- two spheres at centre distance L (overlap delta = R_i + R_j - L):
  a^2 = R_i^2 - ((R_i^2 - R_j^2 + L^2)/(2L))^2 (the intersection circle of the
  spheres);
- a sphere on a plane or a triangle at overlap delta: a^2 = 2 R delta - delta^2.

A heat model takes a^2 (:mod:`gsi.dem.contact.conductance`), so conduction, the force pass and
:func:`heat_conductance_sum <gsi.dem.engine.heat_conductance_sum>` use the same a.
"""
from gsi.jit import njit, sqrt


@njit
def spheres_touch(L2, rs):
    """Two spheres at squared centre distance L2 with radii summing to rs overlap (and do
    not coincide); without a branch (``&``, not ``and``), for the pair loop's first pass."""
    return (L2 < rs * rs) & (L2 != 0.0)


@njit
def sphere_pair(dx, dy, dz, ri, rj):
    """Contact of sphere i with sphere j at centre offset d = x_j - x_i.

    Returns
    -------
    touch : bool
        The spheres overlap (and do not coincide).
    L2 : float
        Squared centre distance (m^2).
    inv_L : float
        1/L (1/m), 0 without contact.
    nx, ny, nz : float
        Unit normal from i to j.
    delta : float
        Overlap R_i + R_j - L (m).
    """
    L2 = dx * dx + dy * dy + dz * dz
    if not spheres_touch(L2, ri + rj):
        return False, L2, 0.0, 0.0, 0.0, 0.0, 0.0
    L2, inv_L, nx, ny, nz, delta = touching_pair(dx, dy, dz, ri, rj)
    return True, L2, inv_L, nx, ny, nz, delta


@njit(inline="always")
def touching_pair(dx, dy, dz, ri, rj):
    """:func:`sphere_pair` of two spheres known to touch, without a branch (the engine's
    vectorized loop of laws): ``(L2, inv_L, nx, ny, nz, delta)``.  Inlined into numba's
    IR (``inline="always"``): a separately compiled copy comes with LLVM's pairs of
    lanes (SLP) already formed, which stop the loop vectorizer."""
    L2 = dx * dx + dy * dy + dz * dz
    L = sqrt(L2)
    inv_L = 1.0 / L
    return L2, inv_L, dx * inv_L, dy * inv_L, dz * inv_L, (ri + rj) - L


@njit(inline="always")
def pair_radius2(ri, rj, L2, inv_L):
    """Squared contact radius a^2 (m^2) of two spheres at squared centre distance L2."""
    s = (ri * ri - rj * rj + L2) * 0.5 * inv_L
    return ri * ri - s * s


@njit
def wall_radius2(ri, delta):
    """Squared contact radius a^2 = 2 R delta - delta^2 (m^2) of a sphere on a wall."""
    return 2.0 * ri * delta - delta * delta


@njit
def plane_distance(xi0, xi1, xi2, px, py, pz, nx, ny, nz):
    """Signed distance (m) of a point from the plane through p with unit normal n."""
    return (xi0 - px) * nx + (xi1 - py) * ny + (xi2 - pz) * nz
