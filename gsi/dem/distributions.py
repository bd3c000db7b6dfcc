"""Particle size distributions (radius, m) for insertion.

Each distribution has ``sample(rng, n) -> ndarray`` of radii (m) and ``r_max`` (m).
A plain float is a constant radius (see :func:`as_distribution`).
"""
import numpy as np

from gsi.errors import GsiInputError


class Constant:
    """Every particle has radius ``r`` (m)."""

    def __init__(self, r, *, key="radius"):
        if not r > 0:
            raise GsiInputError(f"{key} = {r}: must be > 0 (m)")
        self.r = float(r)
        self.r_max = self.r

    def sample(self, rng, n):
        return np.full(n, self.r)


class Uniform:
    """Radius uniform in [lo, hi] (m)."""

    def __init__(self, lo, hi, *, key="radius"):
        if not (0 < lo <= hi):
            raise GsiInputError(f"{key} = uniform({lo}, {hi}): need 0 < lo <= hi (m)")
        self.lo, self.hi = float(lo), float(hi)
        self.r_max = self.hi

    def sample(self, rng, n):
        return rng.uniform(self.lo, self.hi, n)


class Normal:
    """Normal radius (mean, std) truncated to [lo, hi] (m) by resampling.

    Defaults: lo = max(mean - 3 std, mean/10), hi = mean + 3 std.
    """

    def __init__(self, mean, std, *, lo=None, hi=None, key="radius"):
        lo = max(mean - 3 * std, 0.1 * mean) if lo is None else lo
        hi = mean + 3 * std if hi is None else hi
        if not (mean > 0 and std >= 0 and 0 < lo <= mean <= hi):
            raise GsiInputError(
                f"{key} = normal(mean={mean}, std={std}, lo={lo}, hi={hi}): "
                "need mean > 0, std >= 0, 0 < lo <= mean <= hi (m)")
        self.mean, self.std, self.lo, self.hi = float(mean), float(std), float(lo), float(hi)
        self.r_max = self.hi

    def sample(self, rng, n):
        out = rng.normal(self.mean, self.std, n)
        bad = (out < self.lo) | (out > self.hi)
        while bad.any():
            out[bad] = rng.normal(self.mean, self.std, int(bad.sum()))
            bad = (out < self.lo) | (out > self.hi)
        return out


class Discrete:
    """Radii from ``values`` (m) with relative ``weights`` (by number)."""

    def __init__(self, values, weights=None, *, key="radius"):
        values = np.asarray(values, float)
        weights = np.ones_like(values) if weights is None else np.asarray(weights, float)
        if values.ndim != 1 or values.size == 0 or (values <= 0).any():
            raise GsiInputError(f"{key}.values = {values.tolist()}: must be a non-empty list of radii > 0 (m)")
        if weights.shape != values.shape or (weights < 0).any() or weights.sum() <= 0:
            raise GsiInputError(f"{key}.weights = {weights.tolist()}: need one weight >= 0 per value, sum > 0")
        self.values, self.p = values, weights / weights.sum()
        self.r_max = float(values.max())

    def sample(self, rng, n):
        return rng.choice(self.values, size=n, p=self.p)


def as_distribution(radius, *, key="radius"):
    """A distribution object from a float (constant radius) or a distribution."""
    if hasattr(radius, "sample"):
        return radius
    return Constant(float(radius), key=key)
