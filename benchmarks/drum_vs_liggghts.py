"""Benchmark "drum_vs_liggghts": the seed-003 heated drum, gsi against LIGGGHTS-PUBLIC 3.8,
both from the same initial particles, in one command.

    python benchmarks/drum_vs_liggghts.py [--particles 5000] [--duration 2.0]
                                          [--threads 1,2] [--state PATH]

The drum (:mod:`gsi.studies.drum`, Haydar, Martin & Bonnefoy 2023, Tables 3-4): spheres of
r = 5 mm, E = 1e7 Pa, nu = 0.3, rho = 2500 kg/m^3, e = 0.2, mu_pp = 0.3, mu_pw = 0.5,
CDT rolling resistance mu_r = 0.002, k = 100 W/(m K), c_p = 840 J/(kg K), Hertz-Mindlin
contacts and the ``area`` conductance H = 4 k_i k_j/(k_i + k_j) sqrt(A) with A the
geometric overlap area (LIGGGHTS ``heat/gran/conduction``, ``contact_area overlap``). The
drum is a closed triangle mesh (cylinder and end caps), adiabatic; the 5,000-sphere drum of
the family has R = 0.1191 m, L = 0.2382 m and turns once per 3.1498 s (Fr = 0.0483).

1. gsi fills the drum on a lattice and lets the bed settle (``--settle`` s, drum at rest;
   the settled bed is kept in ``--state`` so a second call skips it).
2. The settled positions, with the left half (x < 0) at 30 K and the right half at 10 K,
   at rest and without contact history, start both codes: a particle file for gsi, a
   LIGGGHTS data file (``read_data``) and the same drum triangles as an STL
   (``mesh/surface/stress``, turned by ``move/mesh rotate``). Both run ``--duration`` s at
   dt = 1e-4 s with the drum turning from t = 0 and sample every 100 steps: the bed's
   centre of mass, the mean temperatures of the initially hot and cold halves, and the
   bed's torque on the drum about its axis.
3. Per thread count N, gsi on N numba threads and LIGGGHTS on N MPI ranks run the same
   case; the speed is particle-steps per second of the whole run (gsi: the wall time of
   its steps, the engine compiled beforehand on a copy; LIGGGHTS: its "Loop time").
   gsi re-orders its particle rows at each neighbour build (``sort_particles``), as
   LIGGGHTS sorts its atoms (``atom_modify sort``, on by default) and as
   ``benchmarks/settle.py`` does.

The physics check compares the two runs' second halves: the centre of mass (x and z, as
a fraction of the drum radius), the mean drive torque, and the temperature changes of the
hot and cold halves. The default 2 s put that window in the cascading regime: the bed
turns with the drum as a block until its surface reaches the angle of repose (about
0.4 s), the first avalanche relaxes it by about 1 s, and from then on the tilt, and with
it the torque, fluctuates about a steady mean. (A 0.5 s run compares the block's rise
and the first avalanche, whose timing is chaotic: measured 2026-12-04, the torque there
differed by 6 %; over 1-2 s by 2 %.) The tolerances (2 % of R for the centre of mass,
5 % for the torque and the temperature changes) are for one realisation of a chaotic
flow in each code: the sub-models differ in details (gsi's CDT torque is capped so that
it cannot reverse the relative rotation within one step; LIGGGHTS' acts on the
tangential part of omega_rel only). The torque's standard error is printed beside it
(``torque_se``: 10 block means of the window).

Each code is also checked against an exact reference, the moment balance about the axis:
the bed's torque on the drum is M g x_com - dL/dt (gravity's moment about the axis, less
the rate of change of the bed's angular momentum), and over a window in the steady
regime dL/dt averages out, so the mean torque equals M g times the mean x of the centre
of mass (``balance_gsi``, ``balance_liggghts``: the relative difference, within 3 %).

The LIGGGHTS input is generated from ``benchmarks/liggghts/drum.liggghts.in`` (a
template with the case's numbers filled in; the run directory keeps the filled input).

The last line: ``particles= duration= threads= gsi_particle_steps_per_s=
liggghts_particle_steps_per_s= ratio= ...`` for each thread count (suffix ``_<N>t``) and the
physics differences (``--json PATH`` keeps every sample of both codes). Record a run with
``python benchmarks/record.py drum_vs_liggghts -- .venv/bin/python
benchmarks/drum_vs_liggghts.py``.
"""
import argparse
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

SAMPLE = 100                 # steps between samples (both codes)
TEMPLATE = HERE / "liggghts" / "drum.liggghts.in"
RHO = 2500.0                 # grain density, kg/m^3 (the drum's, Table 3 of the seed)


def settled_bed(geometry, settle, state):
    """Positions (N, 3) and radii of the bed settled in the drum at rest (gsi)."""
    from gsi.studies import drum
    sim, hot, _ = drum.prepare(geometry, settle=settle, spin_up=0.0, state=state)
    order = np.argsort(sim.ids)
    return sim.x[order].copy(), sim.radius[order].copy()


def write_particles(path, x, r, T):
    with open(path, "w") as fh:
        fh.write("x,y,z,radius,T\n")
        for p, rad, t in zip(x, r, T):
            fh.write(f"{p[0]!r},{p[1]!r},{p[2]!r},{rad!r},{t!r}\n")


def gsi_case(geometry, particle_file, duration):
    """The drum case of :func:`gsi.studies.drum.drum_case` with the particles of a file and
    the drum turning from t = 0."""
    import dataclasses
    from gsi.case import ParticleSource
    from gsi.case.walls import Motion
    from gsi.studies import drum
    case = drum.drum_case(geometry, settle=0.0, duration=duration, heat="area")
    wall = case.walls[0]
    turning = Motion(kind="rotation", axis=(0.0, 1.0, 0.0), centre=(0.0, 0.0, 0.0),
                     rpm=round(geometry.rpm, 6))
    # force_dt: the settled bed is a DEM state, whose soft contacts may overlap a little
    # more than check's 5 % limit for hand-placed particles (a 5,000-sphere bed: 5.2 %);
    # the step is the seed's fixed 1e-4 s in both codes
    case = dataclasses.replace(
        case, particles=[ParticleSource(name="grains", material="grain", fill="file",
                                        file=str(particle_file))],
        walls=[dataclasses.replace(wall, motion=turning)],
        dem=dataclasses.replace(case.dem, force_dt=True))
    return case


def run_gsi(case, threads, steps, hot):
    """Samples (list of dicts) and wall seconds of ``steps`` steps on ``threads`` threads."""
    import numba
    from gsi.case.build_dem import build_simulation
    numba.set_num_threads(threads)
    dt = case.check()

    def build():
        sim, handles, _ = build_simulation(case, dt=dt)
        case.walls[0].apply_motion(handles["drum"], 0.0)
        # rows re-ordered at each list build into the force pass's visiting order, as in
        # benchmarks/settle.py: LIGGGHTS sorts its atoms too (atom_modify sort, on by
        # default); measured on the spun-up 5,000-sphere drum, 1 thread, 6 interleaved
        # pairs: CPU per step 1.13x faster sorted (median; min 1.03, max 1.24)
        sim.sort_particles = True
        return sim, handles["drum"][0]

    warm, _ = build()           # compiles the engine (cached on disk after the first call)
    warm.step(SAMPLE)
    sim, wall = build()
    rows = [sample_gsi(sim, wall, hot)]
    seconds = 0.0
    for _ in range(steps // SAMPLE):
        t = time.perf_counter()
        sim.step(SAMPLE)
        seconds += time.perf_counter() - t
        rows.append(sample_gsi(sim, wall, hot))
    return rows, seconds, sim.n


def sample_gsi(sim, wall, hot):
    order = np.argsort(sim.ids)
    x, T, m = sim.x[order], sim.T[order], sim.mass[order]
    com = (m[:, None] * x).sum(0) / m.sum()
    return {"step": sim.step_count, "com_x": com[0], "com_z": com[2],
            "T_hot": float(T[hot].mean()), "T_cold": float(T[~hot].mean()),
            "torque_y": float(wall.torque[1])}


def write_stl(path, vertices, triangles):
    with open(path, "w") as fh:
        fh.write("solid drum\n")
        for a, b, c in triangles:
            p, q, s = vertices[a], vertices[b], vertices[c]
            n = np.cross(q - p, s - p)
            n /= np.linalg.norm(n)
            fh.write(f" facet normal {n[0]:.9e} {n[1]:.9e} {n[2]:.9e}\n  outer loop\n")
            for v in (p, q, s):
                fh.write(f"   vertex {v[0]:.12e} {v[1]:.12e} {v[2]:.12e}\n")
            fh.write("  endloop\n endfacet\n")
        fh.write("endsolid drum\n")


def write_data(path, x, r, lo, hi, rho):
    with open(path, "w") as fh:
        fh.write(f"LIGGGHTS data: the settled drum bed\n\n{len(x)} atoms\n2 atom types\n\n")
        for k, ax in enumerate("xyz"):
            fh.write(f"{lo[k]!r} {hi[k]!r} {ax}lo {ax}hi\n")
        fh.write("\nAtoms\n\n")
        for i, (p, rad) in enumerate(zip(x, r)):
            fh.write(f"{i + 1} 1 {2 * rad!r} {rho!r} {p[0]!r} {p[1]!r} {p[2]!r}\n")


def run_liggghts(work, ranks, values):
    """Samples and loop seconds of LIGGGHTS on ``ranks`` MPI ranks in ``work``."""
    text = TEMPLATE.read_text()
    for k, v in values.items():
        text = text.replace("{" + k + "}", str(v))
    missing = re.findall(r"\{[a-z_]+\}", text)
    assert not missing, missing
    (work / "in.drum").write_text(text)
    cmd = ["liggghts", "-in", "in.drum", "-log", "log.drum"]
    if ranks > 1:
        cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + cmd
    # this process has MPI up (mpi4py, through gsi): a child mpirun must not inherit its
    # singleton's OpenMPI/PMIx variables, or it exits with rc 1 and no output
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("OMPI_", "PMIX_", "OPAL_", "PMI_"))}
    out = subprocess.run(cmd, cwd=work, capture_output=True, text=True, env=env)
    if out.returncode != 0:
        raise SystemExit(f"error: LIGGGHTS failed (rc {out.returncode}), see {work}/log.drum:\n"
                         + out.stdout[-2000:] + out.stderr[-2000:])
    loop = [line for line in out.stdout.splitlines() if line.startswith("Loop time")][-1]
    seconds = float(loop.split()[3])
    rows, head = [], None
    for line in out.stdout.splitlines():
        parts = line.split()
        if parts[:2] == ["Step", "Atoms"] and len(parts) == 7:
            head = parts
            continue
        if head and len(parts) == len(head) and parts[0].isdigit():
            # thermo_style's columns: step atoms c_com[1] c_com[3] c_thot c_tcold f_cad[5]
            step, atoms, cx, cz, th, tc, my = map(float, parts)
            rows.append({"step": int(step), "com_x": cx, "com_z": cz, "T_hot": th,
                         "T_cold": tc, "torque_y": my, "atoms": int(atoms)})
        elif head and (not parts or parts[0] == "Loop"):
            head = None
    return rows, seconds


BLOCKS = 10                  # block means for the torque's standard error


def compare(a, b, radius, weight):
    """Second-half means of the two runs' samples, their differences, the torque's
    standard error (block means) and each code's moment balance about the axis (mean
    torque against ``weight`` = M g times the mean x of the centre of mass)."""
    def second_half(rows, key):
        vals = np.array([r[key] for r in rows])
        return vals[len(vals) // 2:]

    def half(rows, key):
        return float(second_half(rows, key).mean())

    def block_se(rows, key):
        blocks = [v.mean() for v in np.array_split(second_half(rows, key), BLOCKS) if len(v)]
        return float(np.std(blocks, ddof=1) / np.sqrt(len(blocks))) if len(blocks) > 1 else 0.0
    out = {}
    for key in ("com_x", "com_z"):
        ga, lb = half(a, key), half(b, key)
        out[f"gsi_{key}"], out[f"liggghts_{key}"] = ga, lb
        out[f"d_{key}_over_R"] = abs(ga - lb) / radius
    ga, lb = half(a, "torque_y"), half(b, "torque_y")
    out.update(gsi_torque_y=ga, liggghts_torque_y=lb, d_torque_rel=abs(ga - lb) / abs(lb),
               gsi_torque_se=block_se(a, "torque_y"), liggghts_torque_se=block_se(b, "torque_y"))
    for name, rows in (("gsi", a), ("liggghts", b)):
        tq = half(rows, "torque_y")
        out[f"balance_{name}"] = abs(tq - weight * half(rows, "com_x")) / abs(tq)
    for key in ("T_hot", "T_cold"):
        ga, lb = a[-1][key] - a[0][key], b[-1][key] - b[0][key]
        out[f"gsi_d{key}"], out[f"liggghts_d{key}"] = ga, lb
        out[f"d_{key}_rel"] = abs(ga - lb) / abs(lb)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--particles", type=int, default=5000)
    ap.add_argument("--duration", type=float, default=2.0,
                    help="s of turning (both codes); the second half is compared")
    ap.add_argument("--settle", type=float, default=0.8, help="s of settling (gsi, once)")
    ap.add_argument("--threads", default="1,2", help="thread counts = LIGGGHTS ranks")
    ap.add_argument("--state", default=None, help="settled-bed file (default: in /tmp)")
    ap.add_argument("--keep", action="store_true", help="keep the LIGGGHTS run directories")
    ap.add_argument("--json", default=None, help="write every sample of both codes here")
    args = ap.parse_args(argv)
    if shutil.which("liggghts") is None:
        raise SystemExit("error: liggghts not found: apt-get install liggghts")
    from gsi.studies import drum
    geometry = drum.drum_geometry(args.particles)
    steps = int(round(args.duration / drum.DT / SAMPLE)) * SAMPLE
    state = args.state or os.path.join(tempfile.gettempdir(),
                                       f"gsi_drum_settled_{args.particles}.npz")
    x, r = settled_bed(geometry, args.settle, state)
    # M g of the bed (the moment balance of compare): the drum's grain density, g = 9.81
    weight = float(np.sum(RHO * 4.0 / 3.0 * np.pi * r ** 3)) * 9.81
    hot = x[:, 0] < 0.0
    T = np.where(hot, drum.T_HOT, drum.T_COLD)
    work = pathlib.Path(tempfile.mkdtemp(prefix="drum_vs_liggghts_"))
    write_particles(work / "particles.csv", x, r, T)
    case = gsi_case(geometry, work / "particles.csv", steps * drum.DT)
    from gsi.case.build_dem import build_simulation
    sim, handles, _ = build_simulation(case, dt=case.check())
    wall = handles["drum"][0]
    write_stl(work / "drum.stl", wall.vertices, wall.triangles)
    lo, hi = case.dem.domain_lo, case.dem.domain_hi
    write_data(work / "bed.data", x, r, lo, hi, RHO)
    values = dict(dt=drum.DT, steps=steps, sample=SAMPLE, period=repr(geometry.period),
                  skin=repr(sim.skin), T_hot=drum.T_HOT, T_cold=drum.T_COLD)
    res = {"particles": int(len(x)), "duration": steps * drum.DT, "steps": steps,
           "radius": geometry.radius, "period": geometry.period}
    summary = {}
    for n in [int(t) for t in args.threads.split(",")]:
        rows_g, sec_g, n_g = run_gsi(case, n, steps, hot)
        d = work / f"liggghts_{n}"
        d.mkdir()
        for f in ("drum.stl", "bed.data"):
            shutil.copy(work / f, d / f)
        rows_l, sec_l = run_liggghts(d, n, values)
        rate_g = n_g * steps / sec_g
        rate_l = rows_l[-1]["atoms"] * steps / sec_l
        phys = compare(rows_g, rows_l, geometry.radius, weight)
        res[f"threads_{n}"] = dict(gsi_seconds=sec_g, liggghts_seconds=sec_l,
                                   gsi_particle_steps_per_s=rate_g,
                                   liggghts_particle_steps_per_s=rate_l, ratio=rate_g / rate_l,
                                   gsi_particles_end=n_g, liggghts_particles_end=rows_l[-1]["atoms"],
                                   physics=phys, gsi_samples=rows_g, liggghts_samples=rows_l)
        print(f"{n} thread(s)/rank(s): gsi {rate_g:.3g} particle-steps/s ({sec_g:.1f} s), "
              f"LIGGGHTS {rate_l:.3g} ({sec_l:.1f} s), ratio {rate_g / rate_l:.2f}", flush=True)
        print("  " + " ".join(f"{k}={v:.4g}" for k, v in phys.items()), flush=True)
        summary.update({f"gsi_particle_steps_per_s_{n}t": f"{rate_g:.3g}",
                        f"liggghts_particle_steps_per_s_{n}t": f"{rate_l:.3g}",
                        f"ratio_{n}t": f"{rate_g / rate_l:.2f}"})
        ok = (phys["d_com_x_over_R"] < 0.02 and phys["d_com_z_over_R"] < 0.02
              and phys["d_torque_rel"] < 0.05 and phys["d_T_hot_rel"] < 0.05
              and phys["d_T_cold_rel"] < 0.05
              and phys["balance_gsi"] < 0.03 and phys["balance_liggghts"] < 0.03)
        summary[f"physics_{n}t"] = "agree" if ok else "DIFFER"
        res[f"threads_{n}"]["physics_agree"] = bool(ok)
        summary.update({f"d_torque_{n}t": f"{phys['d_torque_rel']:.3f}",
                        f"d_com_x_{n}t": f"{phys['d_com_x_over_R']:.4f}",
                        f"torque_se_{n}t": f"{phys['gsi_torque_se'] / abs(phys['gsi_torque_y']):.3f}",
                        f"balance_gsi_{n}t": f"{phys['balance_gsi']:.3f}",
                        f"balance_liggghts_{n}t": f"{phys['balance_liggghts']:.3f}",
                        f"d_T_hot_{n}t": f"{phys['d_T_hot_rel']:.3f}",
                        f"d_T_cold_{n}t": f"{phys['d_T_cold_rel']:.3f}"})
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    else:
        print(f"run directories kept in {work}")
    res["date"] = time.strftime("%Y-%m-%d %H:%M")
    res["host_cores"] = os.cpu_count()
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(res, indent=1) + "\n")
    print(f"particles={len(x)} duration={steps * drum.DT:g} "
          + " ".join(f"{k}={v}" for k, v in summary.items()))
    return res


if __name__ == "__main__":
    main()
