"""Benchmark "thesis_drums": seed 001's rotating cavity, cases 6 (smooth) and 7 (L-shaped
flights), at 10, 20 and 30 rpm, with copper and alumina (thesis Table III.1).

The cases are ``demos/graded/case6_drum_smooth.toml`` and ``case7_drum_flights.toml``
(D = 0.1524 m, linear law K = 6000 N/m, e_pp 0.8, e_pw 0.5, no tangential force as in the
thesis's chapter III model; left half hot, right half cold). As the thesis runs 2D discs,
gsi runs a quasi-2D slab one diameter thick between two frictionless planes. The two
materials of Table III.1:

* copper: r = 2 mm, rho 8900 kg/m3, c_p 172 J/(kg K), k 385 W/(m K) -- the cases as
  shipped, 336 spheres;
* alumina: r = 1 mm, rho 3900, c_p 875, k 36 -- the same bed boxes filled with a lattice of
  the smaller spheres (1,450), the slab 2 mm thick, dt = 0.99 t_c / 50 of the linear law
  (t_c = pi sqrt(m*/K), m* = m/2).

For every material, speed and cavity the run lasts ``--turns`` turns and prints Lacey's
index of the two halves (10 x 10 cells, the cases' ``mixing`` monitor) against time, its
mean over the last half turn, and the hot and cold halves' mean temperatures at the end.
The last line holds, per run, ``<material>_<rpm>rpm_<smooth|flights>=<mean index over the
last half turn>`` and ``lead_<material>_<rpm>rpm=<flights - smooth>``.

Usage::

    python benchmarks/thesis_drums.py [--materials copper,alumina] [--rpm 10,20,30]
        [--turns 1] [--threads T] [--csv FILE]
"""
import argparse
import dataclasses
import math
import os
import pathlib
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

GRADED = pathlib.Path(__file__).resolve().parents[1] / "demos" / "graded"
CASES = {"smooth": "case6_drum_smooth.toml", "flights": "case7_drum_flights.toml"}
#: thesis Table III.1
ALUMINA = dict(radius=0.001, rho=3900.0, cp=875.0, k=36.0)


def thesis_case(cavity: str, material: str, rpm: float, turns: float):
    """The case of ``cavity`` ("smooth" or "flights") with ``material`` ("copper" or
    "alumina") turning at ``rpm`` for ``turns`` turns."""
    from gsi.case import load_case
    case = load_case(GRADED / CASES[cavity])
    case.walls = [dataclasses.replace(w, motion=dataclasses.replace(w.motion, rpm=rpm))
                  if w.motion.kind == "rotation" else w for w in case.walls]
    duration = turns * 60.0 / rpm
    if material == "alumina":
        r = ALUMINA["radius"]
        grain = case.materials["copper"]
        case.materials = dict(case.materials, copper=dataclasses.replace(
            grain, rho=ALUMINA["rho"], cp=ALUMINA["cp"], k=ALUMINA["k"]))
        case.particles = [dataclasses.replace(
            p, size=dataclasses.replace(p.size, radius=r),
            region=dataclasses.replace(p.region, hi=(p.region.hi[0], 2 * r, p.region.hi[2])))
            for p in case.particles]
        case.walls = [dataclasses.replace(w, point=(w.point[0], 2 * r, w.point[2]))
                      if w.name == "back" else w for w in case.walls]
        m = ALUMINA["rho"] * 4.0 / 3.0 * math.pi * r ** 3
        t_c = math.pi * math.sqrt(0.5 * m / case.dem.k_n)
        case.run = dataclasses.replace(case.run, dt=float(f"{0.99 * t_c / 50:.2e}"))
    elif material != "copper":
        raise SystemExit(f"--materials: {material!r} is not copper or alumina")
    case.run = dataclasses.replace(case.run, duration=duration)
    case.output = dataclasses.replace(case.output, interval=duration, pictures=False)
    case.quick = None                    # the [quick] form is the cases' own, not this one
    return case


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--materials", default="copper,alumina")
    ap.add_argument("--rpm", default="10,20,30")
    ap.add_argument("--turns", type=float, default=1.0)
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--csv", default=None, help="write time, index per run to this CSV")
    args = ap.parse_args(argv)
    import numba
    import numpy as np
    if args.threads:
        numba.set_num_threads(args.threads)
    from gsi.run import Runner
    kv, series = {}, {}
    with tempfile.TemporaryDirectory() as tmp:
        for material in args.materials.split(","):
            for rpm in (float(s) for s in args.rpm.split(",")):
                tag = f"{material}_{rpm:g}rpm"
                for cavity in CASES:
                    case = thesis_case(cavity, material, rpm, args.turns)
                    t0 = time.perf_counter()
                    res = Runner(case, out=pathlib.Path(tmp) / f"{tag}_{cavity}",
                                 pictures=False, verbose=False).run()
                    wall = time.perf_counter() - t0
                    mon = res.monitors
                    t = np.asarray(mon["mixing"]["time_s"])
                    lacey = np.asarray(mon["mixing"]["lacey"])
                    last_half = t > t[-1] - 30.0 / rpm
                    mean = float(lacey[last_half].mean())
                    series[f"{tag}_{cavity}"] = (t, lacey)
                    kv[f"{tag}_{cavity}"] = mean
                    T_hot = mon["left_T"]["T_mean_K"][-1]
                    T_cold = mon["right_T"]["T_mean_K"][-1]
                    every = max(1, len(t) // 12)
                    print(f"{tag} {cavity:7s}: {res.n_particles} particles, dt "
                          f"{case.run.dt:.3g} s, {wall:.0f} s; Lacey "
                          + " ".join(f"{a:.2f}s:{b:.2f}" for a, b in
                                     zip(t[::every], lacey[::every]))
                          + f"; last half turn mean {mean:.3f}; T hot/cold halves "
                          f"{T_hot:.2f}/{T_cold:.2f} K; lost {res.n_lost}", flush=True)
                kv[f"lead_{tag}"] = kv[f"{tag}_flights"] - kv[f"{tag}_smooth"]
    if args.csv:
        names = list(series)
        n = min(len(series[k][0]) for k in names)
        with open(args.csv, "w") as fh:
            fh.write("run,time_s,lacey\n")
            for k in names:
                for a, b in zip(series[k][0][:n], series[k][1][:n]):
                    fh.write(f"{k},{a:.6g},{b:.6g}\n")
    print(" ".join(f"{k}={v:.4g}" for k, v in kv.items()))
    return kv


if __name__ == "__main__":
    main()
