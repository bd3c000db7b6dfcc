"""Benchmark "collision_durations": seed 003's Fig. 9, the distribution of the contact
durations in the rotating drum, from which the seed chose the sampling factor n = 10 ("97 %
of the collisions last more than 10 time steps").

The drum of :mod:`gsi.studies.drum` (default: the quick drum, 640 particles, R = 0.06 m,
Fr 0.048) is filled, settled and turned ``--spin-up`` turns; then one period of
``--period-turns`` turns is logged with n = 1 and no splitting (every contact one row, its
duration in DEM steps of 1e-4 s). Contacts open at t0 or still open at t1 are cut by the
window and left out. Printed: the share of the contacts (particle-particle, and with the
wall) lasting more than 1, 10 and 100 steps, the median and the quartiles; ``--out DIR``
also writes the cumulative distribution (``collision_durations.csv``: duration in steps,
share of contacts lasting at most that) and its plot (``collision_durations.png``).
Last line: key=value pairs.

    python benchmarks/collision_durations.py [--particles 640] [--out DIR]
"""
from __future__ import annotations

import argparse
import pathlib
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def durations(log, steps):
    """Durations (steps) of the contacts that start after t0 and end before t1."""
    out = []
    for start, dur in ((log.pp_start, log.pp_dur), (log.pw_start, log.pw_dur)):
        start, dur = np.asarray(start, np.int64), np.asarray(dur, np.int64)
        whole = (start > 0) & (start + dur < steps)
        out.append(dur[whole])
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--particles", type=int, default=640)
    ap.add_argument("--settle", type=float, default=0.5)
    ap.add_argument("--spin-up", type=float, default=0.25, help="turns before t0")
    ap.add_argument("--period-turns", type=float, default=0.25)
    ap.add_argument("--out", type=pathlib.Path, default=None)
    a = ap.parse_args(argv)
    if a.out is not None:
        a.out.mkdir(parents=True, exist_ok=True)
    from gsi.studies.drum import drum_geometry, prepare
    g = drum_geometry(a.particles)
    t = time.perf_counter()
    sim, _, _ = prepare(g, settle=a.settle, spin_up=a.spin_up)
    steps = int(round(a.period_turns * g.steps_per_turn))
    sim.start_contact_log(every=1, dt_split=None)
    sim.step(steps)
    log = sim.stop_contact_log()
    seconds = time.perf_counter() - t
    pp, pw = durations(log, steps)
    d = np.concatenate([pp, pw])
    res = {"particles": a.particles, "steps": steps, "contacts": int(d.size),
           "pp_contacts": int(pp.size), "pw_contacts": int(pw.size)}
    for k in (1, 10, 100):
        res[f"share_over_{k}_steps"] = round(float((d > k).mean()), 4)
        res[f"pp_share_over_{k}_steps"] = round(float((pp > k).mean()), 4)
    q1, med, q3 = np.percentile(d, [25, 50, 75])
    res.update(median_steps=float(med), q1_steps=float(q1), q3_steps=float(q3),
               seconds=round(seconds, 1))
    print(f"drum of {a.particles} particles, {steps} steps logged with n = 1: {d.size} whole "
          f"contacts ({pp.size} particle-particle, {pw.size} with the wall); lasting more "
          f"than 10 steps: {100 * res['share_over_10_steps']:.1f} % (seed 003 Fig. 9: 97 %); "
          f"median {med:g} steps (quartiles {q1:g}, {q3:g})")
    if a.out is not None:
        v, c = np.unique(d, return_counts=True)
        cdf = np.cumsum(c) / d.size
        np.savetxt(a.out / "collision_durations.csv", np.column_stack([v, cdf]), delimiter=",",
                   header="duration_steps,share_at_most", comments="", fmt=["%d", "%.6g"])
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5, 3.5))
        ax.step(v, cdf, where="post")
        ax.axvline(10, ls="--", c="grey")
        ax.set_xscale("log")
        ax.set_xlabel("contact duration (DEM steps of 1e-4 s)")
        ax.set_ylabel("share of contacts lasting at most")
        ax.set_title(f"drum, {a.particles} particles (seed 003 Fig. 9)")
        fig.tight_layout()
        fig.savefig(a.out / "collision_durations.png", dpi=120)
        plt.close(fig)
    print(" ".join(f"{k}={v}" for k, v in res.items()))
    return res


if __name__ == "__main__":
    main()
