"""Where an FE structure's body lies, checked before the run (``gsi check``), from its
:class:`gsi.meshes.footprint.Footprint` (the body a builder or a gmsh file will mesh, known
without meshing it):

* a builder's values it would refuse only when meshing (an outlet wider than the top);
* a surface traction above the structure's Young's modulus (a strain over 100 %);
* a body over 100 x the domain (a gmsh file's lengths in mm: "did you give mm?");
* a body wholly outside the domain box (particles never reach it);
* a body cutting through the particles placed at the start: a particle file's rows or a
  lattice fill's sites closer to the solid than (1 - MAX_OVERLAP) x their radius (inside
  it, or cut by it), and the possible centres of a random fill or a stream (the region
  shrunk by the smallest radius, sampled on a grid of :data:`GRID` points per side) that
  close. Particles placed there start inside the solid or cut by its surface: they are
  pushed through it or fly off. With ``dem.force_dt`` it is a warning instead (as for
  placed particles that overlap each other).

The criterion for a random fill is the same as for placed particles, at the smallest
radius of the source: a region that only touches the structure (its centres at least a
radius from the solid) passes; one whose grid of possible centres reaches closer is
refused. The grid may miss a penetration thinner than its spacing (region / GRID)."""
from __future__ import annotations

import warnings

import numpy as np

from gsi.errors import GsiInputError

__all__ = ["check_structures", "possible_centres", "GRID"]

#: points per side of the grid of possible centres of a random fill or a stream
GRID = 24


def check_structures(case) -> None:
    """The checks of the module docstring, one-line errors naming the key."""
    from gsi.case.sizes import structure_footprint
    dlo, dhi = np.asarray(case.dem.domain_lo, float), np.asarray(case.dem.domain_hi, float)
    size = float(np.max(dhi - dlo))
    for k, st in enumerate(case.structures):
        key = f"structures[{k}]"
        try:
            fp = structure_footprint(st, case.base_dir)
        except GsiInputError as exc:     # the builder's own words, the case's key
            raise GsiInputError(str(exc).replace(f"structure.{st.mesh}.",
                                                 f"{key}.geometry.")) from None
        if fp is None:
            continue
        if st.file is not None and fp.extent > 100 * size:
            raise GsiInputError(
                f"{key}.{'geometry' if st.geometry else 'file'}: the structure is "
                f"{fp.extent:.3g} m across, over 100 x the "
                f"domain ({size:.3g} m); did you give mm? lengths are in m")
        if (fp.hi < dlo).any() or (fp.lo > dhi).any():
            raise GsiInputError(
                f"{key}.translate = {list(st.translate)}: the structure "
                f"({np.round(fp.lo, 6).tolist()} to {np.round(fp.hi, 6).tolist()}) lies wholly "
                f"outside dem.domain ({dlo.tolist()} to {dhi.tolist()}); particles never "
                f"touch it: move it (m)")
        _check_loads(st, key)
        if fp.distance is not None:
            _check_particles(case, k, st, fp)


def _check_loads(st, key: str) -> None:
    """A surface traction above the structure's Young's modulus strains it by more than
    100 % in linear elasticity: a unit slip (kPa or MPa typed as Pa the other way)."""
    if not st.loads:
        return
    E = st.structural_material().E
    for j, ld in enumerate(st.loads):
        t = float(np.linalg.norm(ld.traction))
        if t > E:
            raise GsiInputError(
                f"{key}.loads[{j}].traction = {list(ld.traction)}: {t:.3g} Pa, above the "
                f"structure's Young's modulus ({E:.3g} Pa): a strain above 100 % in linear "
                f"elasticity; check the units (Pa)")


def possible_centres(p, r: float) -> np.ndarray:
    """Grid points of the region where a particle of radius ``r`` may be centred."""
    lo, hi = p.region.bounds()
    lo, hi = np.asarray(lo, float) + r, np.asarray(hi, float) - r
    axes = [np.linspace(a, b, GRID) if b > a else np.array([0.5 * (a + b)])
            for a, b in zip(lo, hi)]
    x = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    return x[p.region.contains(x, 0.999 * r)]


def _check_particles(case, k: int, st, fp) -> None:
    from gsi.case.case_checks import placed_particles
    from gsi.case.sources import MAX_OVERLAP
    for i, p in enumerate(case.particles):
        placed = placed_particles(case, i, p, "largest")
        if placed is None:
            r0 = case.source_smallest_radius(i)
            x = possible_centres(p, r0)
            placed = x, np.full(len(x), r0), f"particles[{i}].region", "possible centre"
        x, r, key, what = placed
        near = ((x >= fp.lo - r[:, None]) & (x <= fp.hi + r[:, None])).all(1)
        if not near.any():
            continue
        idx = np.flatnonzero(near)
        d = fp.distance(x[idx], within=(1.0 - MAX_OVERLAP) * float(r[idx].max()))
        bad = d < (1.0 - MAX_OVERLAP) * r[idx]
        if not bad.any():
            continue
        j = idx[bad][int(np.argmin(d[bad] / r[idx][bad]))]
        dj = float(d[np.searchsorted(idx, j)])
        where = "inside it" if dj < 0 else f"{dj:.3g} m from it"
        row = f" {j}" if what != "possible centre" else ""
        msg = (f"{key}: cuts through structures[{k}] ('{st.name}'): the {what}{row} at "
               f"{np.round(x[j], 6).tolist()} is {where}, radius {float(r[j]):g} m; the "
               f"particles would start inside the solid or cut by it: move the particles or "
               f"the structure (structures[{k}].translate)")
        if not case.dem.force_dt:
            raise GsiInputError(msg + " (or dem.force_dt = true to run anyway)")
        warnings.warn(f"dem.force_dt = true: {msg}", stacklevel=3)
