"""Particle insertion: lattice and random fills, and continuous insertion at a rate.

Regions (all with ``volume``, ``bounds()``, ``contains(x, r)`` and ``sample(rng, r)``):
:class:`Box` (lo, hi corners, m), :class:`Cylinder` (any axis: an axis point at one end,
axis direction, radius, length, m) and :class:`Sphere` (centre, radius, m).  Particles are
placed with their whole sphere inside the region.

- :func:`lattice_fill` -- simple-cubic lattice of spheres filling a region (the box
  lattice of its bounding box, clipped to a cylinder or sphere).
- :func:`random_fill` -- random non-overlapping spheres in a region, given a count or a
  volume fraction; raises GsiInputError when it cannot place them (random sequential
  insertion jams near a volume fraction of about 0.3-0.35).
- :class:`Inserter` (``sim.add_inserter``) -- inserts ``rate`` particles/s at random
  spots of a region with an initial velocity, skipping spots that overlap existing
  or just-inserted particles (after 20 tries per particle; skipped ones are counted in
  ``n_skipped`` and not retried), up to ``max_count``.  At the steps when particles are
  due the simulation asks it for spots (``place``) and adds the particles;
  ``ids`` lists the ids it inserted.
"""
import math

import numpy as np

from gsi.errors import GsiInputError
from gsi.dem.distributions import as_distribution


class Box:
    """Axis-aligned box region between corners ``lo`` and ``hi`` (m)."""

    def __init__(self, lo, hi):
        self.lo = np.asarray(lo, float)
        self.hi = np.asarray(hi, float)
        if self.lo.shape != (3,) or self.hi.shape != (3,) or not (self.hi > self.lo).all():
            raise GsiInputError(f"region.box = {lo}, {hi}: need lo < hi, 3 numbers each (m)")

    @property
    def volume(self):
        return float(np.prod(self.hi - self.lo))

    def bounds(self):
        return self.lo, self.hi

    def contains(self, x, r=0.0):
        """Whether spheres at ``x`` (k, 3) of radii ``r`` (m) lie wholly inside."""
        x = np.atleast_2d(np.asarray(x, float))
        r = np.asarray(r, float).reshape(-1, 1) if np.ndim(r) else float(r)
        tol = 1e-12 * (self.hi - self.lo)
        return ((x - r >= self.lo - tol) & (x + r <= self.hi + tol)).all(1)

    def sample(self, rng, r):
        """Random centres (len(r), 3) whose spheres of radii r lie inside."""
        r = np.asarray(r)[:, None]
        if ((self.hi - self.lo) < 2 * r).any():
            raise GsiInputError(f"region.box size {(self.hi - self.lo).tolist()}: smaller than a particle diameter")
        return self.lo + r + rng.random((len(r), 3)) * (self.hi - self.lo - 2 * r)


class Cylinder:
    """Cylinder region with any axis: ``centre`` (m) is the axis point at one end, the
    cylinder reaches ``length`` (m) along ``axis`` (normalised; default +z), of ``radius`` (m).
    """

    def __init__(self, centre, radius, length, *, axis=(0.0, 0.0, 1.0)):
        from gsi.dem.shapes import orthonormal_frame
        self.centre = np.asarray(centre, float).reshape(-1)
        self.radius = float(radius)
        self.length = float(length)
        if self.centre.shape != (3,) or not (self.radius > 0 and self.length > 0):
            raise GsiInputError(f"region.cylinder centre = {list(self.centre)}, radius = {radius}, "
                                f"length = {length}: need a 3-vector centre, radius > 0, length > 0 (m)")
        self.e1, self.e2, self.axis = orthonormal_frame(axis)

    @property
    def volume(self):
        return math.pi * self.radius ** 2 * self.length

    def bounds(self):
        """Tight axis-aligned bounding box (lo, hi) (m)."""
        a = self.axis
        ends = np.array([self.centre, self.centre + self.length * a])
        ext = self.radius * np.sqrt(np.clip(1.0 - a ** 2, 0.0, 1.0))
        return ends.min(0) - ext, ends.max(0) + ext

    def contains(self, x, r=0.0):
        """Whether spheres at ``x`` (k, 3) of radii ``r`` (m) lie wholly inside."""
        d = np.atleast_2d(np.asarray(x, float)) - self.centre
        s = d @ self.axis
        rho = np.linalg.norm(d - s[:, None] * self.axis, axis=1)
        r = np.asarray(r, float)
        return (rho + r <= self.radius * (1 + 1e-12)) & (s - r >= -1e-12 * self.length) & \
            (s + r <= self.length * (1 + 1e-12))

    def sample(self, rng, r):
        """Random centres (len(r), 3) whose spheres of radii r lie inside (uniform)."""
        r = np.asarray(r)
        if (r >= self.radius).any() or (2 * r > self.length).any():
            raise GsiInputError(f"region.radius = {self.radius}, length = {self.length}: "
                                f"smaller than a particle of radius {float(r.max())} (m)")
        rho = (self.radius - r) * np.sqrt(rng.random(len(r)))
        phi = 2 * math.pi * rng.random(len(r))
        s = r + rng.random(len(r)) * (self.length - 2 * r)
        return (self.centre + s[:, None] * self.axis + (rho * np.cos(phi))[:, None] * self.e1
                + (rho * np.sin(phi))[:, None] * self.e2)


class Sphere:
    """Spherical region of ``radius`` (m) about ``centre`` (m)."""

    def __init__(self, centre, radius):
        self.centre = np.asarray(centre, float).reshape(-1)
        self.radius = float(radius)
        if self.centre.shape != (3,) or not self.radius > 0:
            raise GsiInputError(f"region.sphere centre = {list(self.centre)}, radius = {radius}: "
                                "need a 3-vector centre and radius > 0 (m)")

    @property
    def volume(self):
        return 4.0 / 3.0 * math.pi * self.radius ** 3

    def bounds(self):
        return self.centre - self.radius, self.centre + self.radius

    def contains(self, x, r=0.0):
        d = np.linalg.norm(np.atleast_2d(np.asarray(x, float)) - self.centre, axis=1)
        return d + np.asarray(r, float) <= self.radius * (1 + 1e-12)

    def sample(self, rng, r):
        r = np.asarray(r)
        if (r >= self.radius).any():
            raise GsiInputError(f"region.radius = {self.radius}: smaller than a particle of "
                                f"radius {float(r.max())} (m)")
        u = rng.normal(size=(len(r), 3))
        u /= np.linalg.norm(u, axis=1)[:, None]
        rho = (self.radius - r) * np.cbrt(rng.random(len(r)))
        return self.centre + rho[:, None] * u


def lattice_fill(region, radius, *, spacing=None):
    """Centres of a simple-cubic lattice of spheres of ``radius`` (m) filling ``region``.

    ``spacing`` (m) defaults to 2.02 radius; the lattice starts one radius inside the
    region's bounding box and keeps the points whose whole sphere lies in the region
    (a box lattice clipped to a cylinder or sphere).
    """
    spacing = 2.02 * radius if spacing is None else spacing
    if not (radius > 0 and spacing >= 2 * radius):
        raise GsiInputError(f"lattice spacing = {spacing}: must be >= the diameter {2 * radius} (m)")
    lo, hi = region.bounds()
    axes = [np.arange(a + radius, b - radius + 1e-12 * spacing, spacing) for a, b in zip(lo, hi)]
    g = np.meshgrid(*axes, indexing="ij")
    x = np.column_stack([a.ravel() for a in g])
    return x if isinstance(region, Box) else x[region.contains(x, radius)]


def lattice_capacity(region, radius, *, spacing=None):
    """Number of lattice sites of :func:`lattice_fill` (counted without building them for a
    box)."""
    spacing = 2.02 * radius if spacing is None else spacing
    lo, hi = region.bounds()
    n = np.floor((hi - lo - 2 * radius) / spacing + 1e-12) + 1
    total = float(np.prod(np.maximum(n, 0)))
    if isinstance(region, Box) or total > 5e6:
        return int(total) if isinstance(region, Box) else int(total * region.volume / np.prod(hi - lo))
    return len(lattice_fill(region, radius, spacing=spacing))


def _overlaps(xc, rc, x, r):
    if len(x) == 0:
        return False
    d2 = ((x - xc) ** 2).sum(1)
    return bool((d2 < (r + rc) ** 2).any())


def random_fill(region, radius, *, count=None, volume_fraction=None, rng=None,
                existing_x=None, existing_r=None, max_tries=200):
    """Random non-overlapping spheres in a region.

    Parameters
    ----------
    region : Box, Cylinder or Sphere
    radius : float or distribution
        Radii (m).
    count : int, optional
        Number of particles; or
    volume_fraction : float, optional
        Solid volume fraction of the region (-) to fill.
    rng : numpy.random.Generator, optional
    existing_x, existing_r : arrays, optional
        Particles already present that new ones must not overlap.
    max_tries : int
        Tries per particle before giving up.

    Returns
    -------
    x (k, 3), r (k,)
    """
    rng = np.random.default_rng() if rng is None else rng
    dist = as_distribution(radius)
    if (count is None) == (volume_fraction is None):
        raise GsiInputError("random_fill: give exactly one of count or volume_fraction")
    if count is not None:
        if count < 0:
            raise GsiInputError(f"random_fill.count = {count}: must be >= 0")
        r = dist.sample(rng, int(count))
    else:
        if not 0 < volume_fraction < 0.6:
            raise GsiInputError(f"random_fill.volume_fraction = {volume_fraction}: must be in (0, 0.6)")
        target = volume_fraction * region.volume
        chunks, vol = [], 0.0
        while vol < target:
            c = dist.sample(rng, 256)
            cv = np.cumsum(4 / 3 * math.pi * c ** 3)
            take = int(np.searchsorted(cv, target - vol)) + 1
            chunks.append(c[:take])
            vol += cv[min(take, len(c)) - 1]
        r = np.concatenate(chunks)
    r = np.sort(r)[::-1]          # big ones first place more easily
    ex = np.zeros((0, 3)) if existing_x is None else np.asarray(existing_x, float)
    er = np.zeros(0) if existing_r is None else np.asarray(existing_r, float)
    x = np.empty((len(r), 3))
    for k, rk in enumerate(r):
        for _ in range(max_tries):
            xc = region.sample(rng, np.array([rk]))[0]
            if not _overlaps(xc, rk, x[:k], r[:k]) and not _overlaps(xc, rk, ex, er):
                x[k] = xc
                break
        else:
            phi = float((4 / 3 * math.pi * r[:k] ** 3).sum() / region.volume)
            raise GsiInputError(
                f"random_fill: placed {k} of {len(r)} particles (volume fraction {phi:.3f}) "
                f"after {max_tries} tries for the next one; lower count/volume_fraction or "
                "enlarge the region (random insertion jams near 0.3)")
    return x, r


class Inserter:
    """Continuous insertion into a region at ``rate`` particles/s (see module docstring).

    The inserter decides where particles go; it holds no simulation.  The simulation
    asks it at each due step (:func:`gsi.dem.step_loop.run_inserters`): :meth:`place`
    gets the time, the random generator and the particles already there, and returns
    the spots; the simulation adds the particles and hands their ids back through
    :meth:`inserted`.

    Parameters
    ----------
    region : Box, Cylinder or Sphere
    rate : float
        Particles per second (> 0).
    radius : float or distribution
        Radii (m).
    material : str
        The particles' material (checked by the simulation that adds them).
    velocity : (3,) float
        Initial velocity (m/s).
    max_count : int, optional
        Stop after this many attempts (None: no limit).
    T : float, optional
        Initial temperature.
    start : float
        Time (s) from which insertion runs.
    """

    def __init__(self, region, rate, *, radius, material, velocity=(0.0, 0.0, 0.0),
                 max_count=None, T=None, start=0.0):
        if not rate > 0:
            raise GsiInputError(f"inserter.rate = {rate}: must be > 0 (particles/s)")
        if max_count is not None and max_count < 0:
            raise GsiInputError(f"inserter.max_count = {max_count}: must be >= 0")
        self.region, self.rate = region, float(rate)
        self.dist = as_distribution(radius, key="inserter.radius")
        self.material = material
        self.velocity = np.asarray(velocity, float)
        self.max_count = max_count
        self.T = T
        self.start = float(start)
        self.n_attempted = 0
        self.n_inserted = 0
        self.n_skipped = 0
        self._ids = []

    @property
    def ids(self):
        """Ids of the particles this inserter added (int64 array, in insertion order)."""
        return np.concatenate(self._ids) if self._ids else np.zeros(0, np.int64)

    def _due(self, time):
        due = int(math.floor(self.rate * (time - self.start) + 1e-9))
        if self.max_count is not None:
            due = min(due, self.max_count)
        return due

    def steps_to_next(self, time, dt):
        """Steps of ``dt`` (s) from ``time`` (s) until the next particle is due (>= 1;
        large when finished)."""
        if self.max_count is not None and self.n_attempted >= self.max_count:
            return 1 << 40
        t_next = self.start + (self.n_attempted + 1) / self.rate
        return max(1, int(math.ceil((t_next - time) / dt - 1e-9)))

    def place(self, time, rng, x, radius):
        """Spots for the particles due by ``time`` (s): radii drawn and positions
        sampled with ``rng``, each clear of the particles at ``x`` (n, 3) with radii
        ``radius`` (n,) and of those placed before it (20 tries each; a particle without
        a spot is skipped and counted).  Returns (positions (k, 3), radii (k,)), possibly
        empty; the caller adds them and reports their ids to :meth:`inserted`."""
        k = self._due(time) - self.n_attempted
        if k <= 0:
            return np.zeros((0, 3)), np.zeros(0)
        r = self.dist.sample(rng, k)
        lo, hi = self.region.bounds()
        n = len(radius)
        reach = 2 * max(self.dist.r_max, float(radius.max()) if n else 0.0)
        near = ((x > lo - reach) & (x < hi + reach)).all(1) if n else np.zeros(0, bool)
        ex, er = x[near].copy(), radius[near].copy()
        placed_x, placed_r = [], []
        for rk in r:
            for _ in range(20):
                xc = self.region.sample(rng, np.array([rk]))[0]
                if not _overlaps(xc, rk, ex, er):
                    placed_x.append(xc)
                    placed_r.append(rk)
                    ex = np.vstack([ex, xc])
                    er = np.append(er, rk)
                    break
            else:
                self.n_skipped += 1
        self.n_attempted += k
        return np.array(placed_x).reshape(-1, 3), np.array(placed_r)

    def inserted(self, ids):
        """Book the ids (int64) of the particles the simulation added from :meth:`place`."""
        ids = np.asarray(ids, np.int64)
        if len(ids):
            self._ids.append(ids)
        self.n_inserted += len(ids)

    # ------------------------------------------------------------------ checkpoints
    def state(self):
        """Counters, start time (s) and inserted ids as plain arrays (for checkpoints;
        the random generator is the simulation's, saved with it)."""
        return {"counters": np.array([self.n_attempted, self.n_inserted, self.n_skipped],
                                     np.int64),
                "start": np.array(self.start, np.float64), "ids": self.ids.copy()}

    def set_state(self, d):
        """Restore :meth:`state`."""
        self.n_attempted, self.n_inserted, self.n_skipped = (int(v) for v in d["counters"])
        self.start = float(d["start"])
        self._ids = [np.array(d["ids"], np.int64)] if len(d["ids"]) else []
