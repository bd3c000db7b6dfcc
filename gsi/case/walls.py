"""Walls (``[[walls]]``) and their motions.

A :class:`Wall` is one of

``plane``     an infinite plane: ``point``, ``normal`` into the domain;
``box``       the five (``lid = false``) or six faces of the box ``lo``..``hi``, as plane
              walls (``as_planes = true``, the default: exact and cheap, translation
              only) or as one triangulated mesh wall (``as_planes = false``: any motion);
``mesh``      the triangles of any file meshio reads (STL, OBJ, VTU, gmsh ``.msh``),
              ``file`` relative to the case directory, coordinates times ``scale`` then
              shifted by ``translate``;
``cone``      an open truncated cone (a hopper): ``centre`` (axis point at the outlet),
              ``axis``, ``outlet_radius``, ``top_radius``, ``length``;
``funnel``    a cone with a cylindrical spout of ``spout_length`` below its outlet;
``cylinder``  an open cylinder mantle: ``centre`` (axis point at one end), ``axis``,
              ``radius``, ``length``;
``drum``      a cylinder closed by flat end caps (normals inward);
``plate``     a flat rectangle: ``centre`` and full edge vectors ``edge_u``, ``edge_v``, or
              ``normal`` and ``size`` = [width, depth] (width along the projection of x, of y
              when the normal is along x).

Shapes are triangulated by :mod:`gsi.dem.shapes` (``facets`` vertices around an axis).
Every wall has a ``material``, a ``temperature`` (None = adiabatic) and a
:class:`Motion`: ``fixed``, ``translation`` (``velocity``), ``rotation`` about ``axis``
through ``centre`` at ``rpm`` or ``omega`` (rad/s; exactly one), or a ``schedule`` of
:class:`MotionEvent` s, each holding from its ``t`` until the next (before the first
event the wall is fixed); or a motion the DEM drives step by step: ``oscillation``,
``servo`` (holds a stress or force) or ``free`` (moved by the particles), see
:mod:`gsi.case.driven_motion`.  Rotating shapes with an axis (cone, funnel, cylinder, drum)
default the rotation's axis and centre to their own.  A plane cannot rotate.

The torque a mesh wall reports is about its reference point: the rotation centre, else
the shape's ``centre``, else the vertex centroid (mesh files, plates, triangulated
boxes); the point moves with the wall's translation.

Example (the hopper's slide gate)::

    [[walls]]
    name = "gate"
    kind = "plate"
    material = "steel"
    centre = [0.0, 0.0, 0.3]
    edge_u = [0.18, 0.0, 0.0]
    edge_v = [0.0, 0.18, 0.0]
    motion = { kind = "schedule", events = [
        { t = 0.6, velocity = [2.0, 0.0, 0.0] },     # opens sideways at 2 m/s
        { t = 0.71 } ] }                             # cleared the outlet: stops

A runner applies a schedule exactly by stepping to each event time
(:meth:`Motion.next_event`) and calling :meth:`Wall.apply_motion` there.
"""
from __future__ import annotations

import dataclasses
import math
import pathlib
from dataclasses import dataclass
from typing import Optional

import numpy as np

from gsi.case.motion import MOTION_KINDS, RPM, Motion, MotionEvent, next_event  # noqa: F401
from gsi.case.regions import key_prefix
from gsi.config.schema import nonnegative, one_of, param, positive
from gsi.errors import GsiInputError

__all__ = ["Motion", "MotionEvent", "Wall", "WALL_KINDS", "MOTION_KINDS", "RPM", "next_event"]

Vec3 = tuple[float, ...]
WALL_KINDS = ("plane", "box", "mesh", "cone", "funnel", "cylinder", "drum", "plate")
_AXIAL = ("cone", "funnel", "cylinder", "drum")
#: most vertices around the axis of a round wall (its triangles grow as facets^2)
MAX_FACETS = 4096


def _unit(v, key) -> np.ndarray:
    from gsi.dem.shapes import unit
    return unit(v, key=key)


_KEYS = {
    "plane": ("point", "normal"),
    "box": ("lo", "hi", "lid", "as_planes"),
    "mesh": ("file", "scale", "translate"),
    "cone": ("centre", "axis", "outlet_radius", "top_radius", "length", "facets"),
    "funnel": ("centre", "axis", "outlet_radius", "top_radius", "length", "spout_length", "facets"),
    "cylinder": ("centre", "axis", "radius", "length", "facets"),
    "drum": ("centre", "axis", "radius", "length", "facets"),
    "plate": ("centre", "edge_u", "edge_v", "normal", "size"),
}
_NEED = {
    "plane": ("point", "normal"), "box": ("lo", "hi"), "mesh": ("file",),
    "cone": ("centre", "outlet_radius", "top_radius", "length"),
    "funnel": ("centre", "outlet_radius", "top_radius", "length", "spout_length"),
    "cylinder": ("centre", "radius", "length"), "drum": ("centre", "radius", "length"),
    "plate": ("centre",),
}
_SHAPE_KEYS = ("point", "normal", "lo", "hi", "lid", "as_planes", "file", "scale", "translate",
               "centre", "axis", "radius", "length", "outlet_radius", "top_radius",
               "spout_length", "facets", "edge_u", "edge_v", "size")


@dataclass(kw_only=True)
class Wall:
    """A ``[[walls]]`` table: shape, material, temperature and motion (module docstring)."""

    kind: str = param(check=one_of(*WALL_KINDS),
                      doc="plane, box, mesh, cone, funnel, cylinder, drum or plate")
    material: str = param(doc="name of a [materials.X] table")
    name: Optional[str] = param(None, doc="name for monitors and output (default 'walls<i>')")
    temperature: Optional[float] = param(None, unit="K", check=positive(),
                                         doc="wall temperature (none = adiabatic)")
    motion: Motion = param(default_factory=Motion, doc="the motion table (default fixed)")
    point: Optional[Vec3] = param(None, unit="m", length=3, doc="plane: a point of the plane")
    normal: Optional[Vec3] = param(None, unit="-", length=3,
                                   doc="plane: normal into the domain; plate: normal (with size)")
    lo: Optional[Vec3] = param(None, unit="m", length=3, doc="box lower corner")
    hi: Optional[Vec3] = param(None, unit="m", length=3, doc="box upper corner")
    lid: bool = param(False, doc="box: also the top (max z) face")
    as_planes: bool = param(True, doc="box: plane walls (true) or one triangulated mesh wall")
    file: Optional[str] = param(None, doc="mesh: file meshio reads, relative to the case")
    scale: float = param(1.0, unit="-", check=positive(), doc="mesh: coordinate scale (0.001 for mm)")
    translate: Optional[Vec3] = param(None, unit="m", length=3, doc="mesh: shift after scaling")
    centre: Optional[Vec3] = param(None, unit="m", length=3,
                                   doc="axis point at the outlet/one end (cone, funnel, cylinder, "
                                       "drum); plate centre")
    axis: Optional[Vec3] = param(None, unit="-", length=3, doc="shape axis (default [0, 0, 1])")
    radius: Optional[float] = param(None, unit="m", check=positive(), doc="cylinder or drum radius")
    length: Optional[float] = param(None, unit="m", check=positive(),
                                    doc="length along the axis (cone, funnel, cylinder, drum)")
    outlet_radius: Optional[float] = param(None, unit="m", check=nonnegative(),
                                           doc="cone/funnel radius at centre")
    top_radius: Optional[float] = param(None, unit="m", check=positive(),
                                        doc="cone/funnel radius at centre + length axis")
    spout_length: Optional[float] = param(None, unit="m", check=positive(),
                                          doc="funnel: spout length below the outlet")
    facets: int = param(48, check=positive(), doc="vertices around the axis (>= 8)")
    edge_u: Optional[Vec3] = param(None, unit="m", length=3, doc="plate: first full edge vector")
    edge_v: Optional[Vec3] = param(None, unit="m", length=3, doc="plate: second full edge vector")
    size: Optional[tuple[float, ...]] = param(None, unit="m", length=2, check=positive(),
                                             doc="plate: [width, depth] (with normal)")

    def __post_init__(self) -> None:
        self._surface = None       # (V, T) of a triangulated wall, built on first use

    def label(self, index: int) -> str:
        """The wall's name for monitors and output: ``name``, or ``walls<index>``."""
        return self.name if self.name is not None else f"walls{index}"

    # ---- presets
    @classmethod
    def slide_gate(cls, *, material: str, centre, half: float, open_time: float, speed: float,
                   travel: float | None = None, name: str = "gate") -> "Wall":
        """The hopper's slide gate: a square plate of half-width ``half`` (m) centred at
        ``centre`` (m), fixed until ``open_time`` (s), then sliding along +x at ``speed``
        (m/s) for ``travel`` (m; default 2 half, clear of its start) and fixed again."""
        travel = 2.0 * half if travel is None else travel
        w = cls(kind="plate", material=material, name=name, centre=tuple(map(float, centre)),
                edge_u=(2.0 * half, 0.0, 0.0), edge_v=(0.0, 2.0 * half, 0.0),
                motion=Motion.schedule([dict(t=open_time, velocity=(speed, 0.0, 0.0)),
                                        dict(t=open_time + travel / speed)]))
        w.validate("walls")
        return w

    # ---- validation
    def validate(self, path: str = "walls") -> None:
        """Keys match the kind; the motion suits the shape (a plane cannot rotate)."""
        p = key_prefix(path)
        allowed, need = _KEYS[self.kind], _NEED[self.kind]
        defaults = {f.name: f.default for f in dataclasses.fields(self)}
        for key in _SHAPE_KEYS:
            if key not in allowed and getattr(self, key) != defaults[key]:
                raise GsiInputError(f"{p}{key}: not a key of a {self.kind} wall; it takes "
                                    f"{', '.join(allowed)}")
        for key in need:
            if getattr(self, key) is None:
                raise GsiInputError(f"{p}{key}: missing; a {self.kind} wall needs {', '.join(need)}")
        for key in ("normal", "axis"):
            if key in allowed and getattr(self, key) is not None:
                _unit(getattr(self, key), f"{p}{key}")
        if self.kind in _AXIAL and self.facets < 8:
            raise GsiInputError(f"{p}facets = {self.facets}: must be >= 8")
        if self.kind in _AXIAL and self.facets > MAX_FACETS:
            r = self.radius if self.radius is not None else self.top_radius
            rings = max(1.0, self.length / (2 * math.pi * r / self.facets)) \
                if (r and self.length) else 1.0
            raise GsiInputError(f"{p}facets = {self.facets}: above {MAX_FACETS}; the {self.kind} "
                                f"would have about {2 * self.facets * rings:.3g} triangles; "
                                f"48-256 resolve a round wall")
        if self.kind == "box" and any(h <= l for l, h in zip(self.lo, self.hi)):
            raise GsiInputError(f"{p}hi = {list(self.hi)}: must exceed lo = {list(self.lo)} in "
                                "every component (m)")
        if self.kind in ("cone", "funnel") and self.outlet_radius >= self.top_radius:
            raise GsiInputError(f"{p}outlet_radius = {self.outlet_radius}: must be < top_radius = "
                                f"{self.top_radius} (m)")
        if self.kind == "funnel" and self.outlet_radius == 0:
            raise GsiInputError(f"{p}outlet_radius = 0: a funnel needs an open outlet (m)")
        if self.kind == "plate":
            by_edges = self.edge_u is not None or self.edge_v is not None
            by_normal = self.normal is not None or self.size is not None
            if by_edges == by_normal:
                raise GsiInputError(f"{p}edge_u: give edge_u and edge_v, or normal and size "
                                    "(not both)")
            pair = ("edge_u", "edge_v") if by_edges else ("normal", "size")
            for key in pair:
                if getattr(self, key) is None:
                    raise GsiInputError(f"{p}{key}: missing; a plate needs {' and '.join(pair)}")
            if by_edges and np.linalg.norm(np.cross(self.edge_u, self.edge_v)) == 0:
                raise GsiInputError(f"{p}edge_v = {list(self.edge_v)}: must be nonzero and not "
                                    f"parallel to edge_u = {list(self.edge_u)} (m)")
        self.motion.validate(f"{p}motion", has_axis=self.kind in _AXIAL, planes=self._planes,
                             box=self.kind == "box" and self.as_planes)
        if self.motion.rotates and self._planes:
            what = "a plane" if self.kind == "plane" else "a box of planes"
            fix = ("use kind = 'plate' (a mesh)" if self.kind == "plane"
                   else "set as_planes = false (a triangulated box)")
            raise GsiInputError(f"{p}motion.kind = '{self.motion.kind}': {what} cannot rotate; "
                                f"{fix}")
        self._surface = None

    @property
    def _planes(self) -> bool:
        return self.kind == "plane" or (self.kind == "box" and self.as_planes)

    # ---- geometry
    def _axis(self) -> np.ndarray:
        return _unit(self.axis if self.axis is not None else (0.0, 0.0, 1.0), "axis")

    def reference_point(self, *, base_dir=".") -> np.ndarray:
        """The point torques of a mesh wall are taken about before any rotation (m): the
        shape's centre, else the vertex centroid."""
        if self.kind in _AXIAL or self.kind == "plate":
            return np.asarray(self.centre, float)
        if self.kind == "plane":
            return np.asarray(self.point, float)
        return self.vertices(base_dir=base_dir).mean(axis=0)

    def _plane_list(self):
        if self.kind == "plane":
            return [(np.asarray(self.point, float), np.asarray(self.normal, float))]
        lo, hi = np.asarray(self.lo, float), np.asarray(self.hi, float)
        planes = [(lo, (0, 0, 1)), (lo, (1, 0, 0)), (hi, (-1, 0, 0)), (lo, (0, 1, 0)),
                  (hi, (0, -1, 0))] + ([(hi, (0, 0, -1))] if self.lid else [])
        return [(p, np.asarray(n, float)) for p, n in planes]

    def surface(self, *, base_dir=".", domain=None) -> tuple[np.ndarray, np.ndarray]:
        """Triangles of the wall as built, before any motion: (vertices (nv, 3) m,
        triangles (nt, 3)).  A plane is drawn as a square patch through the projection of
        the domain centre, as wide as the domain diagonal (``domain`` = (lo, hi) needed);
        a box of planes as its triangulated box."""
        from gsi.dem import shapes
        if self._surface is not None and self.kind != "plane":
            return self._surface
        k = self.kind
        if k == "plane":
            if domain is None:
                raise GsiInputError("wall.surface of a plane: give domain = (lo, hi) to clip it")
            lo, hi = (np.asarray(d, float) for d in domain)
            n = _unit(self.normal, "normal")
            c = 0.5 * (lo + hi)
            c = c - ((c - np.asarray(self.point, float)) @ n) * n
            u, v = shapes.plate_edges(normal=n, size=(1.0, 1.0))
            d = float(np.linalg.norm(hi - lo))
            return shapes.plate(centre=c, edge_u=d * u, edge_v=d * v)
        if k == "box":
            out = shapes.box(lo=self.lo, hi=self.hi, lid=self.lid)
        elif k == "mesh":
            out = self._read_mesh(pathlib.Path(base_dir), "walls")
        elif k in ("cone", "funnel"):
            kw = dict(centre=self.centre, axis=self._axis(), outlet_radius=self.outlet_radius,
                      top_radius=self.top_radius, length=self.length, facets=self.facets)
            out = shapes.cone(**kw) if k == "cone" else shapes.funnel(
                **kw, spout_length=self.spout_length)
        elif k in ("cylinder", "drum"):
            f = shapes.cylinder if k == "cylinder" else shapes.drum
            out = f(centre=self.centre, axis=self._axis(), radius=self.radius,
                    length=self.length, facets=self.facets)
        else:
            if self.edge_u is not None:
                u, v = self.edge_u, self.edge_v
            else:
                u, v = shapes.plate_edges(normal=self.normal, size=self.size)
            out = shapes.plate(centre=self.centre, edge_u=u, edge_v=v)
        self._surface = out
        return out

    def vertices(self, *, base_dir=".", domain=None) -> np.ndarray:
        """Vertices (nv, 3) (m) of :meth:`surface`."""
        return self.surface(base_dir=base_dir, domain=domain)[0]

    def triangles(self, *, base_dir=".", domain=None) -> np.ndarray:
        """Triangles (nt, 3) of :meth:`surface`."""
        return self.surface(base_dir=base_dir, domain=domain)[1]

    def _read_mesh(self, base_dir: pathlib.Path, path: str):
        from gsi.dem.walls import MeshWall
        p = key_prefix(path)
        f = base_dir / self.file
        if not f.is_file():
            raise GsiInputError(f"{p}file = '{self.file}': no such file (looked in "
                                f"{base_dir.resolve()})")
        try:
            w = MeshWall.from_file(f, material=self.material, scale=self.scale)
        except GsiInputError as exc:
            raise GsiInputError(f"{p}file = '{self.file}': {str(exc).split(': ', 1)[-1]}") from None
        V = w.vertices
        if self.translate is not None:
            V = V + np.asarray(self.translate, float)
        return V, w.triangles

    # ---- building
    def add_to(self, sim, *, base_dir=".", path: str = "walls") -> list:
        """Add the wall to ``sim`` and set its motion at ``sim.time``.

        Returns
        -------
        list of gsi.dem.PlaneWall or gsi.dem.MeshWall
            The handles (one mesh wall, one plane, or the planes of a box); pass them to
            :meth:`apply_motion`.
        """
        self.validate(path)
        kw = dict(material=self.material, temperature=self.temperature)
        if self._planes:
            handles = [sim.add_plane(p, n, **kw) for p, n in self._plane_list()]
        else:
            if self.kind == "mesh":
                V, T = self._read_mesh(pathlib.Path(base_dir), path)
                self._surface = (V, T)
            else:
                V, T = self.surface(base_dir=base_dir)
            nv = len(V)
            w = sim.add_mesh_wall(V, T, material=self.material,
                                  vertex_temperature=None if self.temperature is None
                                  else np.full(nv, float(self.temperature)))
            w.set_motion(centre=self.reference_point(base_dir=base_dir))
            handles = [w]
        self.apply_motion(handles, sim.time)
        if self.motion.driven:                # oscillation, servo, free: a driver per step
            from gsi.case.driven_motion import make_driver
            make_driver(self.motion, handles, sim, key=f"{path}.motion")
        return handles

    def apply_motion(self, handles, t: float) -> None:
        """Set the velocity, angular velocity and rotation centre of ``handles`` (from
        :meth:`add_to`) to the motion's state at time ``t`` (s); a driven motion's
        driver sets them before every step instead."""
        if self.motion.driven:
            return
        axis = self._axis() if self.kind in _AXIAL else None
        centre = self.centre if self.kind in _AXIAL else None
        v, omega, c = self.motion.state_at(t, axis=axis, centre=centre)
        for h in handles:
            if self._planes:
                if np.any(omega):
                    raise GsiInputError(f"walls: {self.kind} wall {self.name or ''} cannot rotate")
                h.set_motion(velocity=v)
            else:
                h.set_motion(velocity=v, omega=omega, centre=c)

    # ---- checks
    def check(self, path: str = "walls", *, domain_lo, domain_hi, duration: float | None = None,
              base_dir=".") -> None:
        """Everything that can be known before a run; one-line GsiInputError naming the key.

        Checks: keys match the kind and the motion (a plane cannot rotate); a mesh file
        exists and parses into triangles; the wall reaches into the domain and is not over
        100 x its size ("did you give mm?"); no schedule event at or after ``duration``.
        """
        self.validate(path)
        p = key_prefix(path)
        self.motion.check(f"{p}motion", duration=duration, has_axis=self.kind in _AXIAL,
                          planes=self._planes, box=self.kind == "box" and self.as_planes)
        dlo, dhi = np.asarray(domain_lo, float), np.asarray(domain_hi, float)
        size = float(np.max(dhi - dlo))
        if self.kind == "plane":
            corners = np.array([[a, b, c] for a in (dlo[0], dhi[0]) for b in (dlo[1], dhi[1])
                                for c in (dlo[2], dhi[2])])
            s = (corners - np.asarray(self.point)) @ _unit(self.normal, "normal")
            if (s < 0).all():
                raise GsiInputError(f"{p}point = {list(self.point)}: the plane leaves the whole "
                                    "domain on its back side; flip normal (it points into the "
                                    "domain) or move the point (m)")
            return
        V = self._read_mesh(pathlib.Path(base_dir), path)[0] if self.kind == "mesh" \
            else self.vertices(base_dir=base_dir)
        lo, hi = V.min(0), V.max(0)
        key = {"mesh": "scale", "box": "hi", "plate": "centre"}.get(self.kind, "radius")
        if self.kind in ("cone", "funnel"):
            key = "top_radius"
        if float(np.max(hi - lo)) > 100 * size:
            fix = "set scale = 0.001 for a file in mm" if self.kind == "mesh" else \
                "lengths are in m"
            raise GsiInputError(f"{p}{key}: the {self.kind} wall is {float(np.max(hi - lo)):g} m "
                                f"across, over 100 x the domain ({size:g} m); did you give mm? {fix}")
        if (hi < dlo).any() or (lo > dhi).any():
            key = "translate" if self.kind == "mesh" else ("lo" if self.kind == "box" else "centre")
            raise GsiInputError(f"{p}{key}: the {self.kind} wall ({np.round(lo, 9).tolist()} to "
                                f"{np.round(hi, 9).tolist()}) lies wholly outside dem.domain "
                                f"({dlo.tolist()} to {dhi.tolist()}); move it or check the units (m)")
