"""A reference: the extrapolation from one logged period of a DEM compared with the same
DEM run on (:func:`compare_with_dem`)."""
from __future__ import annotations

import time

import numpy as np

from gsi.errors import GsiInputError
from gsi.extrapolation.metrics import (cell_error, cell_sampling_level, period_errors,
                                       voronoi_seeds)
from gsi.extrapolation.replay import Replay


def compare_with_dem(sim, *, period_steps, periods, samplings=((1, None),), hot=None,
                     cells=200, seed=0, log_dir=None, twin=None, twin_periods=None, say=None):
    """Extrapolate from one logged period of ``sim`` and compare with its own full DEM.

    From the state of ``sim`` (t0): for each ``(every, dt_split)`` of ``samplings``, log
    the period t0..t1 (``period_steps`` steps) and replay it for ``periods`` periods;
    the first sampling's run then continues as the reference DEM to t1 + periods tau
    (the others restart from the state at t0: the DEM is deterministic, so their t1 is
    the same, which is checked).

    Errors at each t_{n+1} (n = 1..periods): eq. 9 on ``cells`` Voronoi cells whose seeds
    are the positions at t1 of ``cells`` particles drawn at random (generator ``seed``;
    the extrapolated configuration at every t_n is that of t1, relabelled), absolute and
    relative to |T_hot - T_cold| (DEM means of the particles flagged ``hot``, by id);
    eq. 10 from t_n to t_{n+1}; the drift of sum C T of the replay and of the DEM
    relative to its value at t1.

    ``twin`` (m): also run a second DEM from the state at t1 with every position moved by
    a random amount up to ``twin`` in each coordinate, and give eq. 9 between the two
    DEMs at each t_{n+1} (``dem["twin"]``: ``eps_abs``, ``eps_level``, and the twin's
    ``T``, ``x`` (periods + 1, N, ...) by log order): the error of a
    prediction as good as the DEM itself, which the flow's chaos alone sets (0 for
    ``twin = 0``: the DEM is deterministic).  ``twin_periods`` (default ``periods``): the
    twin runs only that many periods (its arrays hold ``twin_periods + 1`` entries), so
    a comparison over more periods than the twin's (eq. 10 over a longer replay) does not
    pay a second DEM for them.

    Returns
    -------
    dict
        ``dem``: reference (``T``, ``x`` (periods + 1, N, ...) by log order, ``seconds``
        (wall) and ``cpu`` (process CPU time) per period, ``energy_drift``, ``twin``
        if asked); ``runs``:
        per sampling a dict with ``every``,
        ``dt_split``, ``log`` (the :class:`ContactLog`), ``log_seconds`` (the DEM period
        with the log on), ``file_bytes``, ``file_seconds``, ``pairing_seconds``,
        ``replay_setup_seconds`` (once, with the pairing), ``replay_seconds`` (per
        period), CPU times ``log_cpu``, ``setup_cpu``, ``replay_cpu``, ``T``, ``x``,
        ``eps_abs``, ``eps_rel``,
        ``energy_error`` (eq. 10), ``energy_drift``, ``n_substepped``,
        ``max_stability_ratio``, ``same_t1``.
    """
    import pathlib
    say = say or (lambda *a: None)
    tp = periods if twin_periods is None else twin_periods
    if not (isinstance(tp, (int, np.integer)) and 1 <= tp <= periods):
        raise GsiInputError(f"twin_periods = {twin_periods!r}: must be an integer in "
                            f"1..periods ({periods})")
    state0 = sim.state()
    runs = []
    dem = None
    seeds = None
    for k, (every, dt_split) in enumerate(samplings):
        if k:
            sim.set_state(state0)
        t, c = time.perf_counter(), time.process_time()
        sim.start_contact_log(every=every, dt_split=dt_split)
        sim.step(period_steps)
        log = sim.stop_contact_log()
        run = {"every": every, "dt_split": dt_split, "log": log,
               "log_seconds": time.perf_counter() - t, "log_cpu": time.process_time() - c}
        say(f"logged t0..t1 with every = {every}, dt_split = {dt_split}: "
            f"{log.n_collisions} rows in {run['log_seconds']:.1f} s")
        hot_log = None if hot is None else np.asarray(hot)[log.ids]
        if dem is None:
            state1 = sim.state() if twin is not None else None
            t, c = time.perf_counter(), time.process_time()
            T_dem, x_dem = _dem_periods(sim, log.ids, period_steps, periods,
                                        lambda p: say(f"reference DEM: period {p}/{periods}"))
            C = log.heat_capacity
            E = np.array([float(C @ T) for T in T_dem])
            dem = {"T": T_dem, "x": x_dem,
                   "seconds": (time.perf_counter() - t) / periods,
                   "cpu": (time.process_time() - c) / periods,
                   "energy_drift": np.abs(E - E[0]) / abs(E[0]), "T1": log.T1}
            seeds = voronoi_seeds(log.x1, cells, seed=seed)
        run["same_t1"] = bool(np.array_equal(log.T1, dem["T1"]))
        if log_dir is not None:
            path = pathlib.Path(log_dir) / f"contact_log_every{every}.npz"
            path.parent.mkdir(parents=True, exist_ok=True)
            t = time.perf_counter()
            run["file_bytes"] = log.save(path)
            run["file_seconds"] = time.perf_counter() - t
        c = time.process_time()
        rep = Replay(log)
        c_setup = time.process_time() - c
        c = time.process_time()
        res = rep.run(periods, positions=True)
        run["replay_cpu"] = (time.process_time() - c) / periods
        run["setup_cpu"] = c_setup
        run.update(pairing_seconds=rep.pairing_seconds, pairing_info=rep.pairing_info,
                   replay_setup_seconds=rep.setup_seconds,
                   replay_seconds=res["seconds"] / periods,
                   n_substepped=rep.n_substepped, max_stability_ratio=rep.max_stability_ratio,
                   T=res["T"], x=res["x"], n_rows=rep.n_rows)
        run.update(period_errors(log, res, dem["T"], dem["x"], seeds, hot_log))
        runs.append(run)
        say(f"every = {every}: eps_abs max {run['eps_abs'].max():.3g} K, eps_rel max "
            f"{np.nanmax(run['eps_rel']):.3g}, eq. 10 max "
            f"|{np.abs(run['energy_error']).max():.3g}|")
    if twin is not None:
        # a second DEM from t1, every position moved by up to ``twin`` (m): as valid a
        # run as the reference, and as far from it after a period as chaos alone makes it
        sim.set_state(state1)
        rng = np.random.default_rng(seed)
        sim.x[:] += rng.uniform(-twin, twin, sim.x.shape)
        T_tw, x_tw = _dem_periods(sim, log.ids, period_steps, tp,
                                  lambda p: say(f"twin DEM: period {p}/{tp}"))
        dem["twin"] = {
            "amplitude": twin, "T": T_tw, "x": x_tw,
            "eps_abs": np.array([cell_error(seeds, dem["x"][n], dem["T"][n], x_tw[n],
                                            T_tw[n])[0] for n in range(1, tp + 1)]),
            "eps_level": np.array([cell_sampling_level(seeds, dem["x"][n], dem["T"][n],
                                                       x_tw[n], T_tw[n])
                                   for n in range(1, tp + 1)])}
    return {"dem": dem, "runs": runs, "seeds": seeds}


def _dem_periods(sim, ids, period_steps, periods, say):
    """Temperatures and positions of the particles ``ids`` (in that order) now and after
    each of ``periods`` periods of DEM: two arrays (periods + 1, N[, 3])."""
    rows = sim.index(ids)
    T = [sim.T[rows].copy()]
    x = [sim.x[rows].copy()]
    for p in range(periods):
        sim.step(period_steps)
        rows = sim.index(ids)
        T.append(sim.T[rows].copy())
        x.append(sim.x[rows].copy())
        say(p + 1)
    return np.array(T), np.array(x)

