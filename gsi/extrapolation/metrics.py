"""Error measures of the extrapolation: eq. 9 on Voronoi cells (:func:`cell_error`),
eq. 10 (:func:`energy_transfer_error`), the sampling level of eq. 9
(:func:`cell_sampling_level`) and the errors per period (:func:`period_errors`)."""
from __future__ import annotations

import math

import numpy as np

from gsi.errors import GsiInputError


def finite_max(a):
    """Largest finite value of ``a``, NaN if none (a cell level is NaN where no cell
    holds two particles)."""
    a = np.asarray(a, float)
    a = a[np.isfinite(a)]
    return float(a.max()) if a.size else math.nan


def voronoi_seeds(x, count=200, *, seed=0):
    """``count`` seed points of the Voronoi cells of eq. 9: positions of distinct
    particles drawn at random (generator ``seed``) from ``x`` (m), so every cell lies in
    the bed."""
    x = np.asarray(x, float)
    if count > len(x):
        raise GsiInputError(f"voronoi cells = {count}: more than the {len(x)} particles")
    rng = np.random.default_rng(seed)
    return x[rng.choice(len(x), count, replace=False)]


def _cell_index(seeds, x):
    """The Voronoi cell (nearest seed) of each position."""
    from scipy.spatial import cKDTree
    return cKDTree(seeds).query(np.asarray(x, float))[1]


def cell_means(seeds, x, T):
    """Mean of T over the particles of each Voronoi cell (nearest seed); NaN where a
    cell holds none.  Returns (means (v,), counts (v,))."""
    cell = _cell_index(seeds, x)
    v = len(seeds)
    count = np.bincount(cell, minlength=v)
    total = np.bincount(cell, weights=np.asarray(T, float), minlength=v)
    with np.errstate(invalid="ignore", divide="ignore"):
        return total / count, count


def cell_error(seeds, x_dem, T_dem, x_ext, T_ext, *, hot=None):
    """The error of eq. 9 on the Voronoi cells of ``seeds``.

    eps_abs = (1/v) sum_cells |mean T_DEM - mean T_extra| over the v cells that hold
    particles in both fields; eps_rel = eps_abs/|T_hot - T_cold| with T_hot, T_cold the
    DEM means of the particles flagged ``hot`` and the others (if given).

    Returns
    -------
    (eps_abs, eps_rel, cells_used)
    """
    m_dem, c_dem = cell_means(seeds, x_dem, T_dem)
    m_ext, c_ext = cell_means(seeds, x_ext, T_ext)
    both = (c_dem > 0) & (c_ext > 0)
    eps_abs = float(np.abs(m_dem[both] - m_ext[both]).mean())
    eps_rel = np.nan
    if hot is not None:
        hot = np.asarray(hot, bool)
        diff = abs(float(np.mean(T_dem[hot]) - np.mean(T_dem[~hot])))
        eps_rel = eps_abs / diff if diff > 0 else np.inf
    return eps_abs, eps_rel, int(both.sum())


def cell_sampling_level(seeds, x_dem, T_dem, x_ext, T_ext):
    """The eq.-9 error (K) of two fields whose cells hold independent samples of the same
    temperatures: (1/v) sum_cells sqrt(2/pi) sqrt(s_DEM^2/n_DEM + s_extra^2/n_extra),
    over the cells with at least two particles in both fields (NaN if none), where s^2 is
    the variance of the particle temperatures in the cell and n their count.

    sqrt(2/pi) sigma is the mean of |X| for X normal with standard deviation sigma, and
    s^2/n the variance of a mean of n independent draws: an extrapolation that puts the
    right temperatures in each cell, but other particles than the DEM's, has eps_abs near
    this level (within a few per cent on 200 cells), one that also reproduces the
    particles has less, and a biased one more.  The level grows with the spread of the
    temperatures inside a cell (how finely the bed interleaves hot and cold) and falls as
    1/sqrt(particles per cell).
    """
    def moments(x, T):
        cell = _cell_index(seeds, x)
        T = np.asarray(T, float)
        v = len(seeds)
        n = np.bincount(cell, minlength=v).astype(float)
        s1 = np.bincount(cell, weights=T, minlength=v)
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = s1 / n
            dev2 = np.bincount(cell, weights=(T - mean[cell]) ** 2, minlength=v)
            return n, dev2 / (n - 1.0)

    n_d, s2_d = moments(x_dem, T_dem)
    n_e, s2_e = moments(x_ext, T_ext)
    ok = (n_d > 1) & (n_e > 1)
    if not ok.any():
        return math.nan
    return float(np.mean(math.sqrt(2.0 / math.pi)
                         * np.sqrt(s2_d[ok] / n_d[ok] + s2_e[ok] / n_e[ok])))


def energy_transfer_error(T_dem_n, T_dem_next, T_ext_n, T_ext_next):
    """eq. 10: (sum |T_{n+1} - T_n| - sum |T^ext_{n+1} - T^ext_n|)/sum |T_{n+1} - T_n|,
    sums over the particles (by identity); signed (positive: the extrapolation moves
    less heat than the DEM)."""
    dem = float(np.abs(np.asarray(T_dem_next) - T_dem_n).sum())
    ext = float(np.abs(np.asarray(T_ext_next) - T_ext_n).sum())
    return (dem - ext) / dem


def period_errors(log, res, T_dem, x_dem, seeds, hot):
    """The errors at t_2 ... t_{P+1} of a replay ``res`` (:meth:`Replay.run` with
    positions) against the DEM's ``T_dem``, ``x_dem`` (P + 1, N, ...) from t1 (log
    order): eq. 9 (``eps_abs`` K, ``eps_rel``), its sampling level on the same cells
    (``eps_level`` K, :func:`cell_sampling_level`), eq. 10 (``energy_error``), and the
    drift of sum m c_p T of the replay relative to t1 (``energy_drift``, P + 1 values)."""
    eps_abs, eps_rel, eps_e, level = [], [], [], []
    for n in range(1, len(T_dem)):
        ea, er, _ = cell_error(seeds, x_dem[n], T_dem[n], res["x"][n], res["T"][n], hot=hot)
        eps_abs.append(ea)
        eps_rel.append(er)
        level.append(cell_sampling_level(seeds, x_dem[n], T_dem[n], res["x"][n],
                                         res["T"][n]))
        eps_e.append(energy_transfer_error(T_dem[n - 1], T_dem[n], res["T"][n - 1],
                                           res["T"][n]))
    E = res["T"] @ log.heat_capacity
    return dict(eps_abs=np.array(eps_abs), eps_rel=np.array(eps_rel),
                eps_level=np.array(level), energy_error=np.array(eps_e),
                energy_drift=np.abs(E - E[0]) / abs(E[0]))

