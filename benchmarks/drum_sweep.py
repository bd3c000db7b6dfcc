"""Benchmark "drum_sweep": seed 003's sampling sweep (its Fig. 10: eq. 10 for the sampling
factor n and the longest row Delta t_c^max; its Table 8: the collision file per period
length) on an ensemble of small drums, beside the DEM's own chaos (the twin DEM).

The quick drum of :mod:`gsi.studies.drum` (default 640 particles, R = 0.06 m, Fr 0.048,
cascading) as the quick-drum validation test sets it up (tests/validation/
test_drum_extrapolation.py): filled, settled 0.5 s, halves hot/cold at the end of the
settling; then for each member k of the ensemble (k = 0..M-1) every position is moved by
up to k x 0.5 nm per coordinate (generator k, as tests/validation/conftest.py), the drum
turns a quarter turn to t0, and for each period length (``--periods-turns``, in turns:
0.25 quarter, 0.5 half) one period t0..t1 is logged with every sampling of
``--samplings`` (n:steps, Delta t_c^max in DEM steps), replayed for ``--periods``
periods and compared with the same DEM run on, and with a twin DEM from t1 moved by 1 nm.

Printed per period length and sampling: eq. 10 at every t_n (signed, mean +- SE over the
members), the mean of |eq. 10| over the periods, eps_abs(extrapolation)/eps_abs(twin)
(ratio of the ensemble means per t_n), and the collision file (MB, rows, bytes per
collision) and its MB per turn of drum.  Last line: key=value pairs, for each period
``q`` (quarter) or ``h`` (half) and sampling ``n<n>m<steps>``: ``eq10_<p>_<s>`` (ensemble
mean of the members' mean |eq. 10| over the periods), ``eq10se_<p>_<s>``,
``ratio2_<p>_<s>`` (eps ratio at t2), ``ratio_<p>_<s>`` (largest ratio over t3..),
``mb_<p>_<s>`` (file MB of one period).

    python benchmarks/drum_sweep.py [--members 4] [--periods 3] [--periods-turns 0.25,0.5]
        [--samplings 1:10,1:100,10:10,10:100] [--dt-scale 1] [--particles 640]
        [--reference-period 5] [--twin-periods P] [--workers W]

``--reference-period 15`` runs the seed's rolling regime (its Figs. 11a and 12: the
80,000-particle drum at 15 s per turn, Fr = 0.0054) on the drum family's small drum
(:func:`gsi.studies.drum.drum_geometry`; 640 particles: 6.708 s per turn); its record is
kept as ``drum_rolling`` (``benchmarks/record.py drum_rolling -- ...``).  Printed besides,
per period length and sampling: the excess eps_abs(extrapolation) - 1.5 eps_abs(twin)
per t_n (mean +- SE; the issue's bound is excess <= 0 at mean + 3 SE) and the relative
error of the hot/cold gap (the seed's Figs. 7 and 12 plot the hot and cold means);
last-line keys ``excess_<p>_<s>`` (largest mean + 3 SE of the excess over the t_n, K) and
``gap_<p>_<s>`` (largest mean of |gap_extra - gap_DEM|/gap_DEM).

``--dt-scale`` multiplies the DEM step (1.000000000001: the round-off check of the
ensemble, another set of trajectories).  A member costs, per period length, one spin-up,
one DEM period per sampling, and 2 x ``--periods`` periods of reference and twin.

The members run side by side as the tests' do (:func:`gsi.studies.ensemble.run_ensemble`:
spawned workers, one numba thread each, ``--workers`` at a time, default
``NUMBA_NUM_THREADS``, ``GSI_ENSEMBLE_WORKERS`` or the cores); the settling is shared,
passed to every member as a state. A member gives bitwise the result it gave when the
members ran one after the other in this process (the same perturbation, and
:func:`gsi.studies.drum.restore` continues a state bitwise), so the records before and
after the change are comparable. ``--threads`` is the settling's numba threads.
Last-line keys besides: ``seconds`` (wall, all), ``workers``.
"""
from __future__ import annotations

import argparse
import pathlib
import sys
import tempfile
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def _member(k, g, start, hot, dt, steps, periods, twin_periods, samplings):
    # samplings: (n, Delta t_c^max in s)
    """Member ``k`` of one period length (``steps`` DEM steps), run in a worker
    (:func:`gsi.studies.ensemble.run_ensemble`): the shared settled ``start`` moved by
    member ``k``'s perturbation (up to k x 0.5 nm per coordinate, as the tests'), a
    quarter turn of spin-up to t0, then :func:`gsi.extrapolation.compare_with_dem` for
    every sampling; only the numbers the report needs are returned (picklable)."""
    from gsi.extrapolation import compare_with_dem, energy_transfer_error
    from gsi.studies.drum import restore
    from gsi.studies.ensemble import perturb
    t = time.perf_counter()
    sim, _ = restore(g, start, settle=0.5, dt=dt)
    perturb(sim.x, k)
    sim.step(g.steps_per_turn // 4)                             # spin-up to t0
    with tempfile.TemporaryDirectory() as tmp:
        r = compare_with_dem(sim, period_steps=steps, periods=periods, hot=hot, twin=1e-9,
                             twin_periods=twin_periods,
                             samplings=samplings, log_dir=tmp)
    D, W = r["dem"]["T"], r["dem"]["twin"]["T"]
    rows = []
    for run in r["runs"]:
        assert run["same_t1"]
        h = hot[run["log"].ids]
        gd = D[:, h].mean(1) - D[:, ~h].mean(1)
        ge = run["T"][:, h].mean(1) - run["T"][:, ~h].mean(1)
        rows.append(dict(eq10=run["energy_error"], ext=run["eps_abs"][:len(W) - 1],
                         mb=run["file_bytes"] / 1e6, n=run["log"].n_collisions,
                         bpc=run["log"].bytes_per_collision(),
                         gap=np.abs(ge - gd)[1:] / gd[1:],
                         moved_ext=np.abs(np.diff(run["T"], axis=0)).sum(1)))
    # eq. 10 of the twin DEM against the DEM: the DEM's own chaos in the heat moved; and
    # the heat the DEM moves per period, sum |T_n+1 - T_n| (K): eq. 10's denominator
    return dict(rows=rows, twin=r["dem"]["twin"]["eps_abs"],
                twin_eq10=[energy_transfer_error(D[n - 1], D[n], W[n - 1], W[n])
                           for n in range(1, len(W))],
                moved=np.abs(np.diff(D, axis=0)).sum(1), seconds=time.perf_counter() - t)


def stat(v):
    """Mean and standard error over axis 0."""
    v = np.asarray(v, float)
    se = v.std(0, ddof=1) / np.sqrt(len(v)) if len(v) > 1 else np.zeros(v.shape[1:])
    return v.mean(0), se


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--particles", type=int, default=640)
    ap.add_argument("--members", type=int, default=4)
    ap.add_argument("--periods", type=int, default=3, help="extrapolated periods")
    ap.add_argument("--periods-turns", default="0.25,0.5",
                    help="period lengths in turns (default quarter and half)")
    ap.add_argument("--samplings", default="1:10,1:100,10:10,10:100",
                    help="n:Delta t_c^max in DEM steps, comma separated")
    ap.add_argument("--dt-scale", type=float, default=1.0)
    ap.add_argument("--twin-periods", type=int, default=None,
                    help="periods of the twin DEM (default all; fewer: the eps ratios and the "
                         "excess only at its t_n)")
    ap.add_argument("--reference-period", type=float, default=None,
                    help="the 80,000-particle drum's seconds per turn (default the seed's 5, "
                         "cascading; 15 is its rolling regime, Fig. 12)")
    ap.add_argument("--threads", type=int, default=None,
                    help="numba threads of the shared settling (the members run on one each)")
    ap.add_argument("--workers", type=int, default=None,
                    help="members run at a time (default: NUMBA_NUM_THREADS, "
                         "GSI_ENSEMBLE_WORKERS or the cores; 1: in this process)")
    args = ap.parse_args(argv)
    import numba
    if args.threads:
        numba.set_num_threads(args.threads)
    from gsi.studies.drum import DT, drum_geometry, prepare
    from gsi.studies.ensemble import default_workers, run_ensemble
    n_workers = max(1, min(args.members, args.workers or default_workers()))
    g = drum_geometry(args.particles, args.reference_period)
    dt = DT * args.dt_scale
    samplings = [tuple(int(a) for a in s.split(":")) for s in args.samplings.split(",")]
    turns = [float(t) for t in args.periods_turns.split(",")]
    print(f"drum: {g.particles} particles, R = {g.radius:.4g} m, {g.period:.4g} s per turn, "
          f"Fr = {g.froude:.4g} ({g.regime}); dt = {dt!r}; M = {args.members}; samplings "
          f"(n, Delta t_c^max steps) {samplings}; periods {turns} turns; threads "
          f"{numba.get_num_threads()} (settling), {n_workers} members at a time",
          flush=True)
    t_all = time.perf_counter()
    sim, hot, _ = prepare(g, settle=0.5, spin_up=0.0, dt=dt)
    start = sim.state()
    res = {}
    out = {"particles": g.particles, "members": args.members, "dt_scale": args.dt_scale,
           "s_per_turn": g.period, "froude": g.froude, "regime": g.regime}
    for f in turns:
        steps = int(round(f * g.steps_per_turn))
        pname = {0.25: "q", 0.5: "h", 1.0: "f"}.get(f, f"t{f:g}")
        t = time.perf_counter()
        members = run_ensemble(_member, args.members, workers=args.workers,
                               args=(g, start, hot, dt, steps, args.periods,
                                     args.twin_periods,
                                     [(n, m * DT * args.dt_scale) for n, m in samplings]))
        rows = {s: {key: [m["rows"][i][key] for m in members] for key in members[0]["rows"][0]}
                for i, s in enumerate(samplings)}
        twin = [m["twin"] for m in members]
        twin_eq10 = [m["twin_eq10"] for m in members]
        moved = [m["moved"] for m in members]
        for k, m in enumerate(members):
            print(f"  {f:g} turn, member {k}: {m['seconds']:.0f} s; eq. 10 "
                  + "; ".join(f"n{n}m{s} " + " ".join(f"{100 * e:+.1f}" for e in
                                                       rows[(n, s)]["eq10"][k])
                              for n, s in samplings) + " %", flush=True)
        print(f"  {f:g} turn: {args.members} members in {time.perf_counter() - t:.0f} s wall "
              f"({n_workers} at a time)", flush=True)
        tw_mean = np.mean(twin, 0)
        te = np.array(twin_eq10)
        tm, ts = stat(np.abs(te.mean(1)))
        print(f"  twin DEM's eq. 10 (its heat moved against the DEM's, the chaos floor) per "
              f"member: " + "; ".join(" ".join(f"{100 * e:+.2f}" for e in row) for row in te)
              + f" %; |mean over the periods| {100 * tm:.2f} +- {100 * ts:.2f} %; DEM heat "
              f"moved per period sum |dT| (K) per member: "
              + "; ".join(" ".join(f"{v:.0f}" for v in row) for row in moved), flush=True)
        out[f"eq10twin_{pname}"] = float(tm)
        out[f"eq10twinse_{pname}"] = float(ts)
        print(f"period {f:g} turn ({steps} steps): twin eps_abs "
              + ", ".join(f"{a:.3f}" for a in tw_mean) + " K at t2..", flush=True)
        for n, m in samplings:
            d = rows[(n, m)]
            e = np.array(d["eq10"])
            em, es = stat(e)
            am, ase = stat(np.abs(e.mean(1)))
            ratio = np.mean(d["ext"], 0) / tw_mean
            mb = float(np.mean(d["mb"]))
            # eq. 10 pooled over the replay: (sum_n dem_n - sum_n ext_n)/sum_n dem_n, the
            # periods weighted by the heat the DEM moves in them
            dm, de = np.array(moved), np.array(d["moved_ext"])
            pooled = (dm.sum(1) - de.sum(1)) / dm.sum(1)
            pm, ps = stat(np.abs(pooled))
            print(f"    eq. 10 per member (t2..): " + "; ".join(
                " ".join(f"{100 * v:+.2f}" for v in row) for row in e) + " %; pooled over "
                f"the periods (heat-weighted) per member " + " ".join(
                f"{100 * v:+.2f}" for v in pooled) + f" %: |pooled| {100 * pm:.2f} +- "
                f"{100 * ps:.2f} %", flush=True)
            xm, xs = stat(np.array(d["ext"]) - 1.5 * np.array(twin))
            gm, gs = stat(d["gap"])
            print(f"    excess eps_abs - 1.5 twin " + ", ".join(
                f"{a:+.3f} +- {b:.3f}" for a, b in zip(xm, xs)) + " K; |gap error| "
                + ", ".join(f"{100 * a:.2f} +- {100 * b:.2f}" for a, b in zip(gm, gs))
                + " % at t2..", flush=True)
            print(f"  n = {n}, Delta t_c^max = {m} steps ({m * DT:g} s): eq. 10 per period "
                  + ", ".join(f"{100 * a:+.2f} +- {100 * b:.2f}" for a, b in zip(em, es))
                  + f" %; |mean over the periods| {100 * am:.2f} +- {100 * ase:.2f} %; "
                  f"eps_abs/twin " + ", ".join(f"{x:.2f}" for x in ratio)
                  + f"; file {mb:.2f} MB ({np.mean(d['n']):.0f} rows, "
                  f"{np.mean(d['bpc']):.1f} bytes/collision), {mb / f:.2f} MB per turn",
                  flush=True)
            key = f"{pname}_n{n}m{m}"
            out.update({f"eq10_{key}": float(am), f"eq10se_{key}": float(ase),
                        f"ratio2_{key}": float(ratio[0]),
                        f"ratio_{key}": float(ratio[1:].max()) if len(ratio) > 1 else
                        float("nan"), f"mb_{key}": mb,
                        f"excess_{key}": float((xm + 3 * xs).max()),
                        f"gap_{key}": float(gm.max()), f"eq10pooled_{key}": float(pm),
                        f"eq10pooledse_{key}": float(ps)})
            res[(f, n, m)] = dict(eq10=e, ratio=ratio, mb=mb)
    out["seconds"] = time.perf_counter() - t_all
    out["workers"] = n_workers
    out["dt_scale"] = repr(args.dt_scale)         # all digits: 1.000000000001
    print(" ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                   for k, v in out.items()))
    return res


if __name__ == "__main__":
    main()
