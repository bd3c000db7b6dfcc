"""Particle sources (``[[particles]]``): what particles, where, and how they enter.

A source is a :class:`ParticleSource` with a :class:`Size` distribution and a
:class:`gsi.case.regions.Region`, filled in one of four ways (``fill``):

``random``   random non-overlapping spheres at the start, by ``count`` or by
             ``volume_fraction`` (solid volume / region volume).  Random sequential
             insertion jams near a volume fraction of 0.3: :meth:`ParticleSource.check`
             refuses more than :data:`RANDOM_FILL_LIMIT`.
``lattice``  a simple-cubic lattice (spacing 2.02 x the largest radius) clipped to the
             region, filled from the bottom (smallest z) up; ``count`` or
             ``volume_fraction`` take the lowest sites, neither fills every site.
``stream``   continuous insertion at ``rate`` particles/s from ``start`` s, up to
             ``max_count`` (:class:`gsi.dem.insertion.Inserter`).
``file``     positions and radii read from ``file`` (relative to the case directory):
             CSV with a header naming columns ``x, y, z, radius`` and optionally
             ``vx, vy, vz, T``; or VTU (as written by :class:`gsi.dem.output.ParticleWriter`)
             with point data ``radius`` and optionally ``velocity`` and ``T`` (or
             ``temperature``).  Velocities and temperatures from the file replace
             ``velocity`` and ``temperature``.

Example::

    [[particles]]
    name = "glass"                 # group name for monitors (default "particles<i>")
    material = "glass"
    fill = "random"
    volume_fraction = 0.2
    size = { kind = "uniform", min = 0.0018, max = 0.0022 }
    region = { kind = "box", lo = [0, 0, 0.05], hi = [0.06, 0.06, 0.15] }

In Python, build the same objects and call ``source.add_to(sim, rng=rng)``.
"""
from __future__ import annotations

import math
import pathlib
from dataclasses import dataclass
from typing import Optional

import numpy as np

from gsi.case.regions import Region, key_prefix
from gsi.config.schema import between, nonnegative, one_of, param, positive
from gsi.errors import GsiInputError
from gsi.case.particle_files import read_particle_file


__all__ = ["Size", "ParticleSource", "read_particle_file", "first_overlap", "FILLS",
           "RANDOM_FILL_LIMIT", "MAX_PARTICLES"]

Vec3 = tuple[float, ...]
FILLS = ("random", "lattice", "stream", "file")
#: largest volume fraction a random fill is asked for (random sequential insertion jams
#: near 0.3-0.35; above this, use a lattice fill and let it settle)
RANDOM_FILL_LIMIT = 0.30
#: largest initial overlap of two particles, as a fraction of the smaller radius (file and
#: lattice sources; random fills never overlap)
MAX_OVERLAP = 0.05
#: more particles than this in one source is refused before any allocation
MAX_PARTICLES = 20_000_000
SIZE_KINDS = ("single", "uniform", "normal", "discrete")


@dataclass(kw_only=True)
class Size:
    """Size distribution of the particle radius (m)."""

    kind: str = param("single", check=one_of(*SIZE_KINDS), doc="size distribution of the radius")
    radius: Optional[float] = param(None, unit="m", check=positive(), doc="radius (single)")
    min: Optional[float] = param(None, unit="m", check=positive(),
                                 doc="smallest radius (uniform; normal: truncation)")
    max: Optional[float] = param(None, unit="m", check=positive(),
                                 doc="largest radius (uniform; normal: truncation)")
    mean: Optional[float] = param(None, unit="m", check=positive(), doc="mean radius (normal)")
    std: Optional[float] = param(None, unit="m", check=positive(), doc="std deviation (normal)")
    values: Optional[tuple[float, ...]] = param(None, unit="m", check=positive(),
                                               doc="radii (discrete)")
    weights: Optional[tuple[float, ...]] = param(None, unit="-", check=positive(),
                                                doc="number fractions (discrete)")

    def validate(self, path: str = "size") -> None:
        p = key_prefix(path)
        need = {"single": ("radius",), "uniform": ("min", "max"), "normal": ("mean", "std"),
                "discrete": ("values", "weights")}[self.kind]
        allowed = need + (("min", "max") if self.kind == "normal" else ())
        for key in need:
            if getattr(self, key) is None:
                raise GsiInputError(f"{p}{key}: missing; size kind '{self.kind}' needs "
                                    f"{' and '.join(need)} (m)")
        for key in ("radius", "min", "max", "mean", "std", "values", "weights"):
            if key not in allowed and getattr(self, key) is not None:
                raise GsiInputError(f"{p}{key}: not a key of size kind '{self.kind}'; it takes "
                                    f"{', '.join(allowed)}")
        if self.kind == "uniform" and self.max < self.min:
            raise GsiInputError(f"{p}max = {self.max}: must be >= {p}min = {self.min} (m)")
        if self.kind == "discrete" and len(self.values) != len(self.weights):
            raise GsiInputError(f"{p}weights: must have as many entries as values "
                                f"({len(self.values)})")
        if self.kind == "normal" and not self.smallest <= self.mean <= self.largest:
            raise GsiInputError(f"{p}mean = {self.mean}: must lie in [min, max] = "
                                f"[{self.smallest}, {self.largest}] (m)")

    @property
    def smallest(self) -> float:
        """Smallest radius the distribution gives (m)."""
        if self.kind == "single":
            return self.radius
        if self.kind == "uniform":
            return self.min
        if self.kind == "normal":
            return self.min if self.min is not None else max(self.mean - 3 * self.std, 0.1 * self.mean)
        return min(self.values)

    @property
    def largest(self) -> float:
        """Largest radius the distribution gives (m)."""
        if self.kind == "single":
            return self.radius
        if self.kind == "uniform":
            return self.max
        if self.kind == "normal":
            return self.max if self.max is not None else self.mean + 3 * self.std
        return max(self.values)

    def distribution(self):
        """The :mod:`gsi.dem.distributions` object that samples these radii."""
        from gsi.dem import distributions as d
        if self.kind == "single":
            return d.Constant(self.radius)
        if self.kind == "uniform":
            return d.Uniform(self.min, self.max)
        if self.kind == "normal":
            return d.Normal(self.mean, self.std, lo=self.smallest, hi=self.largest)
        return d.Discrete(np.asarray(self.values), np.asarray(self.weights))

    def mean_volume(self) -> float:
        """Mean particle volume E[4/3 pi r^3] (m^3) (exact; the truncated normal by
        midpoint quadrature on 2000 intervals)."""
        c = 4.0 / 3.0 * math.pi
        if self.kind == "single":
            return c * self.radius ** 3
        if self.kind == "uniform":
            a, b = self.min, self.max
            return c * (b ** 4 - a ** 4) / (4 * (b - a)) if b > a else c * a ** 3
        if self.kind == "discrete":
            w = np.asarray(self.weights, float)
            return c * float((w * np.asarray(self.values) ** 3).sum() / w.sum())
        lo, hi = self.smallest, self.largest
        r = lo + (np.arange(2000) + 0.5) * (hi - lo) / 2000
        pdf = np.exp(-0.5 * ((r - self.mean) / self.std) ** 2)
        return c * float((pdf * r ** 3).sum() / pdf.sum())


@dataclass(kw_only=True)
class ParticleSource:
    """A ``[[particles]]`` table: material, size, region and fill (see module docstring)."""

    material: str = param(doc="name of a [materials.X] table")
    name: Optional[str] = param(None, doc="group name for monitors (default 'particles<i>')")
    fill: str = param("random", check=one_of(*FILLS),
                      doc="random or lattice fill at start, a stream at a rate, or a file")
    size: Optional[Size] = param(None, doc="the size table (not with fill = 'file')")
    region: Optional[Region] = param(None, doc="the region table (not with fill = 'file')")
    count: Optional[int] = param(None, check=positive(), doc="number of particles (random, lattice)")
    volume_fraction: Optional[float] = param(
        None, unit="-", check=between(0.0, 0.74, open_lo=True),
        doc="solid volume / region volume (random, lattice; instead of count)")
    rate: Optional[float] = param(None, unit="1/s", check=positive(), doc="particles per second (stream)")
    start: float = param(0.0, unit="s", check=nonnegative(), doc="time the stream starts")
    max_count: Optional[int] = param(None, check=positive(),
                                     doc="stream: stop after this many particles (default: no limit)")
    file: Optional[str] = param(None, doc="CSV or VTU of positions and radii, relative to the case")
    velocity: Vec3 = param((0.0, 0.0, 0.0), unit="m/s", length=3, doc="initial velocity")
    temperature: float = param(293.15, unit="K", check=positive(), doc="initial temperature")
    fixed: bool = param(False, doc="hold the particles in place (they still feel forces and "
                                   "exchange heat); their overlaps among themselves are allowed")

    def validate(self, path: str = "particles") -> None:
        """Keys match the fill; raise a one-line GsiInputError naming the key."""
        p = key_prefix(path)
        uses = {"random": ("size", "region", "count", "volume_fraction"),
                "lattice": ("size", "region", "count", "volume_fraction"),
                "stream": ("size", "region", "rate", "start", "max_count"),
                "file": ("file",)}[self.fill]
        defaults = {"start": 0.0}
        for key in ("size", "region", "count", "volume_fraction", "rate", "start", "max_count",
                    "file"):
            if key not in uses and getattr(self, key) != defaults.get(key):
                hint = ("; a stream stops after max_count" if key == "count" and self.fill == "stream"
                        else "")
                raise GsiInputError(f"{p}{key}: not used by fill = '{self.fill}' (it takes "
                                    f"{', '.join(uses)}){hint}")
        need = {"random": ("size", "region"), "lattice": ("size", "region"),
                "stream": ("size", "region", "rate"), "file": ("file",)}[self.fill]
        for key in need:
            if getattr(self, key) is None:
                raise GsiInputError(f"{p}{key}: missing; fill = '{self.fill}' needs "
                                    f"{', '.join(need)}")
        if self.fixed and self.fill == "stream":
            raise GsiInputError(f"{p}fixed: a stream's particles cannot be fixed (use fill = "
                                "'file' or 'lattice' for particles held in place)")
        if self.fill == "random" and (self.count is None) == (self.volume_fraction is None):
            raise GsiInputError(f"{p}count: give exactly one of count or volume_fraction for a "
                                "random fill")
        if self.fill == "lattice" and self.count is not None and self.volume_fraction is not None:
            raise GsiInputError(f"{p}volume_fraction: give count or volume_fraction, not both")
        if self.size is not None:
            self.size.validate(f"{p}size")
        if self.region is not None:
            self.region.validate(f"{p}region")

    def group(self, index: int) -> str:
        """The group name monitors use: ``name``, or ``particles<index>``."""
        return self.name if self.name is not None else f"particles{index}"

    # ---- counts
    def planned_count(self, *, duration: float | None = None) -> int:
        """How many particles the source will add (streams: up to ``duration`` s)."""
        if self.fill == "file":
            return -1
        if self.fill == "stream":
            n = math.inf if duration is None else self.rate * max(duration - self.start, 0.0)
            return int(min(n, self.max_count if self.max_count is not None else math.inf))
        if self.count is not None:
            return self.count
        if self.volume_fraction is not None:
            return int(math.ceil(self.volume_fraction * self.region.volume / self.size.mean_volume()))
        from gsi.dem.insertion import lattice_capacity
        return lattice_capacity(self.region.shape, self.size.largest)

    # ---- building
    def add_to(self, sim, *, rng, base_dir=".", path: str = "particles"):
        """Add the particles to ``sim`` (or register a stream).

        Parameters
        ----------
        sim : gsi.dem.Simulation
        rng : numpy.random.Generator
            Random placement and radii.
        base_dir : path
            Directory that ``file`` is relative to.
        path : str
            Key path for error messages (``particles[i]``).

        Returns
        -------
        numpy.ndarray of int64 or gsi.dem.insertion.Inserter
            The new particles' ids; for a stream the Inserter (its ``ids`` grow as it
            inserts).
        """
        from gsi.dem import insertion
        p = key_prefix(path)
        if self.fill == "file":
            data = read_particle_file(pathlib.Path(base_dir) / self.file, key=f"{p}file",
                                      shown=self.file)
            self._refuse_overlap(sim, data["x"], data["radius"], f"{p}file = '{self.file}'")
            v = data["v"] if data["v"] is not None else np.asarray(self.velocity, float)
            T = data["T"] if data["T"] is not None else self.temperature
            ids = sim.add_particles(data["x"], data["radius"], material=self.material, v=v, T=T)
            sim.fix(ids, self.fixed)
            return ids
        dist = self.size.distribution()
        if self.fill == "stream":
            return sim.add_inserter(self.region.shape, self.rate, radius=dist,
                                    material=self.material, velocity=self.velocity,
                                    T=self.temperature, max_count=self.max_count,
                                    start=self.start)
        planned = self.planned_count()
        if planned > MAX_PARTICLES:
            key = ("volume_fraction" if self.volume_fraction is not None else
                   "count" if self.count is not None else "size")
            raise GsiInputError(f"{p}{key}: {planned} particles is more than {MAX_PARTICLES:.0e}; "
                                "lower it or check the radius units (did you give mm? lengths "
                                "are in m)")
        n = planned if (self.count or self.volume_fraction) else None
        if self.fill == "lattice":
            x = self.lattice_sites(path)
            r = dist.sample(rng, len(x))
            self._refuse_overlap(sim, x, r, f"{p}region")
        else:
            try:
                x, r = insertion.random_fill(self.region.shape, dist, count=self.count,
                                             volume_fraction=self.volume_fraction, rng=rng,
                                             existing_x=sim.x, existing_r=sim.radius)
            except GsiInputError as exc:
                raise GsiInputError(f"{p}{'count' if self.count else 'volume_fraction'}: "
                                    f"{exc}") from None
        v = np.broadcast_to(np.asarray(self.velocity, float), (len(x), 3))
        ids = sim.add_particles(x, r, material=self.material, v=v,
                                T=np.full(len(x), self.temperature))
        sim.fix(ids, self.fixed)
        return ids

    def lattice_sites(self, path: str = "particles") -> np.ndarray:
        """Centres (k, 3) (m) of a lattice fill: the lowest ``count`` (or
        ``volume_fraction``) sites, or all (deterministic: no random numbers)."""
        from gsi.dem import insertion
        p = key_prefix(path)
        x = insertion.lattice_fill(self.region.shape, self.size.largest)
        x = x[np.lexsort((x[:, 0], x[:, 1], x[:, 2]))]       # bottom layers first
        n = self.planned_count() if (self.count or self.volume_fraction) else None
        if n is not None:
            if n > len(x):
                raise GsiInputError(
                    f"{p}{'count' if self.count else 'volume_fraction'}: {n} particles do not "
                    f"fit the {len(x)} lattice sites of the region; enlarge the region or "
                    "ask for fewer")
            x = x[:n]
        return x

    @staticmethod
    def _refuse_overlap(sim, x, r, key: str) -> None:
        """New particles (file, lattice) must not overlap those already placed by more than
        MAX_OVERLAP of the smaller radius, unless ``dem.force_dt`` (``sim.force_dt``)."""
        if sim.n == 0 or getattr(sim, "force_dt", False):
            return
        hit = first_overlap(x, r, MAX_OVERLAP, other_x=sim.x, other_r=sim.radius)
        if hit is not None:
            raise GsiInputError(
                f"{key}: its particle {hit[0]} at {np.round(x[hit[0]], 6).tolist()} overlaps an "
                f"earlier source's particle (id {int(sim.ids[hit[1]])}) by {hit[2]:.3g} x the "
                f"smaller radius; they would fly apart: move the region or the particles, or "
                f"list this source first (random fills avoid earlier particles)")

    # ---- pre-run check
    def check(self, path: str = "particles", *, domain_lo, domain_hi, duration: float | None = None,
              base_dir=".") -> None:
        """Everything that can be known before a run; one-line GsiInputError naming the key.

        Checks: the keys match the fill; the region lies in the domain; the largest radius
        fits the region and is below a third of the domain (else: "did you give mm?");
        at most :data:`MAX_PARTICLES`; a random fill below :data:`RANDOM_FILL_LIMIT`, a
        lattice fill within its sites; a stream starts before ``duration``; a file exists,
        parses, and its particles lie in the domain with radii > 0.
        """
        self.validate(path)
        p = key_prefix(path)
        dlo, dhi = np.asarray(domain_lo, float), np.asarray(domain_hi, float)
        if self.fill == "file":
            data = read_particle_file(pathlib.Path(base_dir) / self.file, key=f"{p}file",
                                      shown=self.file)
            out = ((data["x"] - data["radius"][:, None] < dlo) |
                   (data["x"] + data["radius"][:, None] > dhi)).any(1)
            if out.any():
                i = int(np.flatnonzero(out)[0])
                raise GsiInputError(f"{p}file = '{self.file}': {int(out.sum())} particles reach "
                                    f"outside the domain (row {i}: x = {data['x'][i].tolist()}); "
                                    "enlarge dem.domain_lo/domain_hi or check the units (m)")
            self._check_radius(f"{p}file = '{self.file}'", float(data["radius"].max()),
                               None, dlo, dhi)
            return
        self.region.check(f"{p}region", domain_lo=dlo, domain_hi=dhi)
        largest_key = {"single": "radius", "uniform": "max", "normal": "mean",
                       "discrete": "values"}[self.size.kind]
        size_key = f"{p}size.{largest_key}"
        self._check_radius(size_key, self.size.largest, self.region, dlo, dhi)
        if self.fill == "stream":
            if duration is not None and self.start >= duration:
                raise GsiInputError(f"{p}start = {self.start}: the stream starts at or after the "
                                    f"end of the run ({duration} s); start earlier (s)")
            n = self.planned_count(duration=duration)
            if n > MAX_PARTICLES:
                key = "max_count" if self.max_count is not None else "rate"
                raise GsiInputError(f"{p}{key}: the stream would insert {n} particles (more than "
                                    f"{MAX_PARTICLES:.0e}); lower rate or set max_count")
            return
        n = self.planned_count()
        key = ("count" if self.count is not None else
               "volume_fraction" if self.volume_fraction is not None else "size")
        if n > MAX_PARTICLES:
            raise GsiInputError(f"{p}{key}: {n} particles is more than {MAX_PARTICLES:.0e}; "
                                "lower it or check the radius units (did you give mm? lengths are in m)")
        phi = n * self.size.mean_volume() / self.region.volume
        if self.fill == "random" and phi > RANDOM_FILL_LIMIT:
            raise GsiInputError(
                f"{p}{key}: {n} particles fill {phi:.2f} of the region's volume; random insertion "
                f"jams near {RANDOM_FILL_LIMIT}: enlarge the region, ask for fewer, or use "
                "fill = 'lattice'")
        if self.fill == "lattice" and (self.count is not None or self.volume_fraction is not None):
            from gsi.dem.insertion import lattice_capacity
            cap = lattice_capacity(self.region.shape, self.size.largest)
            if n > cap:
                raise GsiInputError(f"{p}{key}: {n} particles do not fit the {cap} lattice sites "
                                    "of the region; enlarge the region or ask for fewer")

    @staticmethod
    def _check_radius(key, r_max, region, dlo, dhi) -> None:
        dom = float(np.min(dhi - dlo))
        if region is not None and 2 * r_max > region.smallest_extent:
            raise GsiInputError(f"{key}: a particle of radius {r_max:g} m does not fit the region "
                                f"({region.smallest_extent:g} m across); did you give mm? "
                                "lengths are in m")
        if r_max > dom / 3:
            raise GsiInputError(f"{key}: radius {r_max:g} m is over a third of the domain "
                                f"({dom:g} m); did you give mm? lengths are in m")


def first_overlap(x, r, frac: float, *, other_x=None, other_r=None):
    """The first pair of spheres that overlap by more than ``frac`` x the smaller radius.

    Parameters
    ----------
    x, r : (k, 3) and (k,) float
        Centres and radii (m).
    frac : float
        Allowed overlap r_a + r_b - |x_a - x_b| as a fraction of min(r_a, r_b).
    other_x, other_r : arrays, optional
        Compare ``x`` with these spheres instead of with each other.

    Returns
    -------
    (int, int, float) or None
        Row in ``x``, row in ``other`` (or in ``x``), overlap / smaller radius.
    """
    from scipy.spatial import cKDTree
    x, r = np.asarray(x, float), np.asarray(r, float)
    if other_x is None:
        if len(x) < 2:
            return None
        ij = cKDTree(x).query_pairs(float(2 * r.max()), output_type="ndarray")
        i, j = (ij[:, 0], ij[:, 1]) if len(ij) else (np.zeros(0, int), np.zeros(0, int))
        ox, orr = x, r
    else:
        ox, orr = np.asarray(other_x, float), np.asarray(other_r, float)
        if len(x) == 0 or len(ox) == 0:
            return None
        m = cKDTree(x).sparse_distance_matrix(cKDTree(ox), float(r.max() + orr.max()),
                                              output_type="ndarray")
        i, j = m["i"].astype(int), m["j"].astype(int)
    if len(i) == 0:
        return None
    d = np.linalg.norm(x[i] - ox[j], axis=1)
    f = (r[i] + orr[j] - d) / np.minimum(r[i], orr[j])
    bad = np.flatnonzero(f > frac)
    if len(bad) == 0:
        return None
    k = bad[np.lexsort((j[bad], i[bad]))[0]]
    return int(i[k]), int(j[k]), float(f[k])
