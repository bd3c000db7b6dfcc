"""Regions of space: where particle sources put their particles.

A :class:`Region` is a box, a cylinder with any axis, or a sphere (lengths in m)::

    region = { kind = "box", lo = [0, 0, 0.05], hi = [0.06, 0.06, 0.15] }
    region = { kind = "cylinder", centre = [0, 0, 0.3], axis = [0, 1, 0], radius = 0.05, length = 0.04 }
    region = { kind = "sphere", centre = [0, 0, 0.1], radius = 0.02 }

The cylinder's ``centre`` is the point of its axis at one end; it reaches ``length``
along ``axis`` (default +z).  In Python: ``Region.box(lo, hi)``,
``Region.cylinder(centre, radius, length, axis=...)``, ``Region.sphere(centre, radius)``
or ``Region(kind=..., ...)`` (then ``validate`` checks the keys).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from gsi.config.schema import one_of, param, positive
from gsi.errors import GsiInputError

__all__ = ["Region", "REGION_KINDS"]

Vec3 = tuple[float, ...]
REGION_KINDS = ("box", "cylinder", "sphere")
_NEED = {"box": ("lo", "hi"), "cylinder": ("centre", "radius", "length"),
         "sphere": ("centre", "radius")}
_OPTIONAL = {"box": (), "cylinder": ("axis",), "sphere": ()}


def key_prefix(path: str) -> str:
    return f"{path}." if path else ""


@dataclass(kw_only=True)
class Region:
    """A box, a cylinder (any axis) or a sphere (m); see the module docstring."""

    kind: str = param("box", check=one_of(*REGION_KINDS), doc="box, cylinder or sphere")
    lo: Optional[Vec3] = param(None, unit="m", length=3, doc="box lower corner")
    hi: Optional[Vec3] = param(None, unit="m", length=3, doc="box upper corner")
    centre: Optional[Vec3] = param(None, unit="m", length=3,
                                   doc="sphere centre, or the cylinder's axis point at one end")
    axis: Optional[Vec3] = param(None, unit="-", length=3,
                                 doc="cylinder axis direction (default [0, 0, 1])")
    radius: Optional[float] = param(None, unit="m", check=positive(), doc="cylinder or sphere radius")
    length: Optional[float] = param(None, unit="m", check=positive(),
                                    doc="cylinder length along its axis")

    def __post_init__(self) -> None:
        self._shape = None        # the gsi.dem.insertion region, built on first use

    # ---- construction
    @classmethod
    def box(cls, lo, hi) -> "Region":
        r = cls(kind="box", lo=tuple(map(float, lo)), hi=tuple(map(float, hi)))
        r.validate("region")
        return r

    @classmethod
    def cylinder(cls, centre, radius: float, length: float, *, axis=(0.0, 0.0, 1.0)) -> "Region":
        r = cls(kind="cylinder", centre=tuple(map(float, centre)), radius=float(radius),
                length=float(length), axis=tuple(map(float, axis)))
        r.validate("region")
        return r

    @classmethod
    def sphere(cls, centre, radius: float) -> "Region":
        r = cls(kind="sphere", centre=tuple(map(float, centre)), radius=float(radius))
        r.validate("region")
        return r

    def validate(self, path: str = "region") -> None:
        """Keys match the kind; raise a one-line GsiInputError naming the key."""
        p = key_prefix(path)
        if self.kind not in REGION_KINDS:
            raise GsiInputError(f"{p}kind = {self.kind!r}: must be one of "
                                + ", ".join(repr(k) for k in REGION_KINDS))
        need = _NEED[self.kind]
        for key in need:
            if getattr(self, key) is None:
                raise GsiInputError(f"{p}{key}: missing; a {self.kind} region needs "
                                    f"{', '.join(need)} (m)")
        for key in ("lo", "hi", "centre", "axis", "radius", "length"):
            if key not in need + _OPTIONAL[self.kind] and getattr(self, key) is not None:
                raise GsiInputError(f"{p}{key}: not a key of a {self.kind} region; it takes "
                                    f"{', '.join(need + _OPTIONAL[self.kind])}")
        if self.kind == "box" and any(h <= l for l, h in zip(self.lo, self.hi)):
            raise GsiInputError(f"{p}hi = {list(self.hi)}: must exceed lo = {list(self.lo)} "
                                f"in every component (m)")
        if self.kind == "cylinder" and self.axis is not None and not np.any(self.axis):
            raise GsiInputError(f"{p}axis = {list(self.axis)}: must be a nonzero vector")
        self._shape = None

    # ---- geometry (delegated to gsi.dem.insertion)
    @property
    def shape(self):
        """The :mod:`gsi.dem.insertion` region (Box, Cylinder or Sphere)."""
        if self._shape is None:
            from gsi.dem import insertion
            if self.kind == "box":
                self._shape = insertion.Box(self.lo, self.hi)
            elif self.kind == "cylinder":
                self._shape = insertion.Cylinder(self.centre, self.radius, self.length,
                                                 axis=self.axis or (0.0, 0.0, 1.0))
            else:
                self._shape = insertion.Sphere(self.centre, self.radius)
        return self._shape

    @property
    def volume(self) -> float:
        """Volume (m^3)."""
        return self.shape.volume

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Tight axis-aligned bounding box (lo, hi) (m)."""
        return self.shape.bounds()

    def sample(self, rng, r) -> np.ndarray:
        """Uniform random centres (len(r), 3) whose spheres of radii ``r`` (m) fit inside."""
        return self.shape.sample(rng, np.asarray(r, float))

    def contains(self, x, r=0.0) -> np.ndarray:
        """Whether spheres at ``x`` (k, 3) of radii ``r`` (m) lie wholly inside (bool (k,))."""
        return self.shape.contains(x, r)

    @property
    def smallest_extent(self) -> float:
        """Smallest width of the region (m): box edge, cylinder diameter or length, sphere
        diameter."""
        if self.kind == "box":
            return float(min(h - l for l, h in zip(self.lo, self.hi)))
        if self.kind == "cylinder":
            return min(2 * self.radius, self.length)
        return 2 * self.radius

    # ---- pre-run check
    def check(self, path: str = "region", *, domain_lo, domain_hi) -> None:
        """The region lies inside the domain box; raise GsiInputError naming the key."""
        self.validate(path)
        p = key_prefix(path)
        dlo, dhi = np.asarray(domain_lo, float), np.asarray(domain_hi, float)
        lo, hi = self.bounds()
        size = float(np.max(dhi - dlo))
        key = {"box": "hi", "cylinder": "centre", "sphere": "centre"}[self.kind]
        if float(np.max(hi - lo)) > 100 * size:
            raise GsiInputError(
                f"{p}{'radius' if self.kind != 'box' else key}: the {self.kind} region "
                f"({float(np.max(hi - lo)):g} m across) is over 100 x the domain ({size:g} m); "
                "did you give mm? lengths are in m")
        tol = 1e-9 * size
        if (lo < dlo - tol).any() or (hi > dhi + tol).any():
            bad = "lo" if self.kind == "box" and (lo < dlo - tol).any() else key
            raise GsiInputError(
                f"{p}{bad} = {list(getattr(self, bad))}: the {self.kind} region spans "
                f"{np.round(lo, 9).tolist()} to {np.round(hi, 9).tolist()}, outside "
                f"dem.domain_lo = {dlo.tolist()} .. dem.domain_hi = {dhi.tolist()}; "
                "move it or enlarge the domain (m)")
