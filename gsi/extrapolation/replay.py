"""The replay of a contact log (Haydar, Martin & Bonnefoy 2023, Algorithm 3, eqs. 7-8):
:class:`Replay`."""
from __future__ import annotations

import time

import numpy as np

from gsi.errors import GsiInputError
from gsi.jit import njit
from gsi.extrapolation.pairing import pair_particles


@njit(inline="always")
def particle_row(T, ka, kb, wr, Twr, inv_C):
    """One row of the replay: eqs. 7-8 between particles ka and kb (kb >= 0), or particle
    ka against a fixed-temperature wall at ``Twr`` (kb < 0)."""
    if kb >= 0:
        q = wr * (T[ka] - T[kb])
        T[ka] -= q * inv_C[ka]
        T[kb] += q * inv_C[kb]
    else:
        T[ka] += wr * (Twr - T[ka]) * inv_C[ka]


@njit
def _replay_rows(T, a, b, w, Tw, inv_C):
    """Apply the rows in order to T (the particles' temperatures in the log's frame:
    T[a] belongs to the particle playing logged particle a): eqs. 7-8 for b >= 0, a
    fixed-temperature wall ``Tw`` for b < 0."""
    for r in range(a.shape[0]):
        particle_row(T, a[r], b[r], w[r], Tw[r], inv_C)


class Replay:
    """The heat extrapolation (Algorithm 3, eqs. 7-8) of a :class:`ContactLog`.

    Parameters
    ----------
    log : gsi.dem.contact_log.ContactLog
    sigma : (N,) int, optional
        The pairing (:func:`pair_particles`); default computed from ``log.x0``,
        ``log.x1`` (its time in :attr:`pairing_seconds`).
    on_unstable : {"substep", "error"}
        What a row breaking the stability bound m < C/H does (module docstring).
    pairing : str
        ``method`` of :func:`pair_particles`.
    fe_wall : int, optional
        Index (in the log) of a wall that is an FE heat structure: its rows are kept with
        b = -2 and their triangle for :class:`FEWallReplay` (plain :meth:`run` does not
        know them).

    Attributes
    ----------
    sigma : (N,) int64
    n_rows : int
        Rows replayed per period (after sub-steps; adiabatic wall rows dropped).
    n_substepped : int
        Log rows split into sub-steps by the stability bound.
    max_stability_ratio : float
        max over rows of m H/C (the bound is < 1).
    pairing_seconds, setup_seconds : float
    pairing_info : dict
        The sparse pairing's ``rounds``, ``edges``, ``gap_bound`` (:func:`pair_particles`;
        empty for the dense one or a given sigma).
    """

    def __init__(self, log, *, sigma=None, on_unstable="substep", pairing="auto",
                 fe_wall=None):
        if on_unstable not in ("substep", "error"):
            raise GsiInputError(f"on_unstable = {on_unstable!r}: must be 'substep' or 'error'")
        self.log = log
        t = time.perf_counter()
        self.pairing_info = {}
        self.sigma = (pair_particles(log.x0, log.x1, method=pairing, info=self.pairing_info)
                      if sigma is None else np.asarray(sigma, np.int64))
        self.pairing_seconds = time.perf_counter() - t
        n = log.n_particles
        if self.sigma.shape != (n,) or not np.array_equal(np.sort(self.sigma), np.arange(n)):
            raise GsiInputError(f"sigma: must be a permutation of 0..{n - 1}")
        t = time.perf_counter()
        C = np.asarray(log.heat_capacity, float)
        typ = log.type
        # particle-particle rows and the wall rows that exchange heat, in log order
        w_pp = (log.pp_dur * log.dt) * log.coef[typ[log.pp_i], typ[log.pp_j]] \
            * log.pp_size.astype(float)
        fe = (log.pw_wall == fe_wall) if fe_wall is not None else np.zeros(len(log.pw_wall),
                                                                            bool)
        keep = (log.wall_has_T[log.pw_wall] | fe) if len(log.pw_wall) else np.zeros(0, bool)
        pw_i, pw_wall = log.pw_i[keep], log.pw_wall[keep]
        w_pw = (log.pw_dur[keep] * log.dt) * log.coef[typ[pw_i], log.wall_type[pw_wall]] \
            * log.pw_size[keep].astype(float)
        start = np.concatenate([log.pp_start, log.pw_start[keep]])
        m = np.concatenate([log.pp_dur, log.pw_dur[keep]]) * log.dt
        a = np.concatenate([log.pp_i, pw_i]).astype(np.int32)
        b = np.concatenate([log.pp_j, np.where(fe[keep], -2, -1).astype(np.int32)]
                           ).astype(np.int32)
        w = np.concatenate([w_pp, w_pw])
        Tw = np.concatenate([np.zeros(len(w_pp)), log.wall_T[pw_wall]])
        tri = np.concatenate([np.full(len(w_pp), -1, np.int32),
                              log.pw_tri[keep].astype(np.int32)])
        order = np.argsort(start, kind="stable")      # pp rows are already in log order
        a, b, w, Tw, m = a[order], b[order], w[order], Tw[order], m[order]
        start, tri = start[order], tri[order]
        C_min = np.where(b >= 0, np.minimum(C[a], C[np.maximum(b, 0)]), C[a])
        ratio = w / C_min                              # m H/C: stable below 1
        self.max_stability_ratio = float(ratio.max()) if len(ratio) else 0.0
        bad = ratio >= 1.0
        self.n_substepped = int(bad.sum())
        if self.n_substepped and on_unstable == "error":
            r = int(np.argmax(ratio))
            m_max = float(np.min(m[ratio > 0] / ratio[ratio > 0]))
            raise GsiInputError(
                f"on_unstable = 'error': {self.n_substepped} rows of the contact log break "
                f"the stability bound m < C/H of the explicit replay (worst: row {r}, "
                f"m H/C = {ratio[r]:.3g}); log with dt_split < {m_max:.3g} s or replay "
                "with on_unstable = 'substep'")
        if self.n_substepped:
            s = np.where(bad, np.floor(ratio) + 1, 1).astype(np.int64)
            a, b, Tw = np.repeat(a, s), np.repeat(b, s), np.repeat(Tw, s)
            start, tri = np.repeat(start, s), np.repeat(tri, s)
            w = np.repeat(w / s, s)
        self._a, self._b, self._w, self._Tw = a, b, w, Tw
        self._start, self._tri = start, tri
        self.n_rows = len(a)
        # load (or compile) the kernel now, so that run() times the replay alone
        _replay_rows(np.zeros(1), a[:0], b[:0], w[:0], Tw[:0], np.ones(1))
        self.setup_seconds = time.perf_counter() - t

    def run(self, periods, *, T=None, positions=False):
        """Extrapolate ``periods`` periods from t1.

        Parameters
        ----------
        periods : int
        T : (N,) float, optional
            Temperatures at t1 (log order), default ``log.T1``.
        positions : bool
            Also return the extrapolated positions at each t_n.

        Returns
        -------
        dict
            ``T`` (periods + 1, N): temperatures of the logged particles (log order, by
            particle identity) at t1, t2, ...; ``time`` (periods + 1,) s; with
            ``positions``, ``x`` (periods + 1, N, 3) m; ``seconds``: replay wall time.
        """
        log = self.log
        n = log.n_particles
        T_real = np.array(log.T1 if T is None else T, float)
        if T_real.shape != (n,):
            raise GsiInputError(f"T: must have {n} temperatures (log order)")
        inv_C_real = 1.0 / np.asarray(log.heat_capacity, float)
        out_T = np.empty((periods + 1, n))
        out_T[0] = T_real
        out_x = np.empty((periods + 1, n, 3)) if positions else None
        if positions:
            out_x[0] = log.x1
        role = np.arange(n)              # role[a]: the particle playing a at the last t_n
        t = time.perf_counter()
        for p in range(1, periods + 1):
            role = role[self.sigma]      # sigma^p
            Tt = T_real[role]
            _replay_rows(Tt, self._a, self._b, self._w, self._Tw, inv_C_real[role])
            T_real[role] = Tt
            out_T[p] = T_real
            if positions:
                out_x[p][role] = log.x1
        seconds = time.perf_counter() - t
        res = {"T": out_T, "time": log.t1 + log.period * np.arange(periods + 1),
               "seconds": seconds}
        if positions:
            res["x"] = out_x
        return res

    def positions(self, periods):
        """Extrapolated positions (periods + 1, N, 3) (m) at t1, t2, ... (log order)."""
        n = self.log.n_particles
        out = np.empty((periods + 1, n, 3))
        out[0] = self.log.x1
        role = np.arange(n)
        for p in range(1, periods + 1):
            role = role[self.sigma]
            out[p][role] = self.log.x1
        return out


