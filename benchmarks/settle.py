"""Benchmark "settle": gsi DEM vs LIGGGHTS on benchmarks/liggghts/settle.liggghts.in.

19,773 spheres (d = 2 mm, rho = 2500 kg/m^3) on a simple-cubic lattice (spacing 2.1 mm,
the lattice points i*2.1 mm inside x, y in [0.001, 0.083], z in [0.001, 0.0283] m, as
LIGGGHTS ``lattice sc 0.0021`` + ``create_atoms``), each displaced uniformly by up to
0.05 mm per axis, settle under gravity in an 84 x 84 mm box with five planes (Hertz +
tangential history, E = 5 MPa, nu = 0.3, e = 0.5, mu = 0.5, dt = 2 us, skin 0.4 mm).
Run 1 settles (--settle-steps, default 50,000), run 2 is timed (--timed-steps, 10,000).
The particle rows are re-ordered at each neighbour build (``sort_particles=True``;
LIGGGHTS sorts its atoms too, ``atom_modify sort``); ``--no-sort`` keeps them in id
order.

Usage::

    python benchmarks/settle.py [--threads N] [--vs-liggghts] [--settle-steps S] [--timed-steps T]

Prints the throughput (particle steps per second), memory per particle, bed height and
kinetic energy; with --vs-liggghts the same from LIGGGHTS (timing from the runner
script benchmarks/liggghts/run_liggghts_settle.sh, unchanged; bed height and KE from a copy of the input with extra thermo output),
and as the last line key=value pairs ending with ``ratio`` = gsi rate / LIGGGHTS rate.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time

#: the LIGGGHTS reference (input + runner), in the repository: benchmarks/liggghts
BENCH = os.environ.get("GSI_BENCH_DIR",
                       os.path.join(os.path.dirname(os.path.abspath(__file__)), "liggghts"))


def lattice_positions(seed=15485863):
    """The LIGGGHTS lattice points of the input (19,773), displaced up to 0.05 mm."""
    import numpy as np
    a = 0.0021
    def axis(lo, hi):
        return a * np.arange(int(np.ceil(lo / a - 1e-9)), int(np.floor(hi / a + 1e-9)) + 1)
    gx, gy, gz = np.meshgrid(axis(0.001, 0.083), axis(0.001, 0.083), axis(0.001, 0.0283),
                             indexing="ij")
    x = np.column_stack([gx.ravel(), gy.ravel(), gz.ravel()])
    rng = np.random.default_rng(seed)
    return x + rng.uniform(-5e-5, 5e-5, x.shape)


def run_gsi(settle_steps, timed_steps, save_state=None, sort=True):
    import numpy as np
    from gsi.dem import Simulation, Material
    glass = Material(E=5e6, nu=0.3, rho=2500.0, e=0.5, mu=0.5)
    sim = Simulation({"glass": glass}, contact="hertz", gravity=(0, 0, -9.81), dt=2e-6,
                     skin=4e-4, domain=((0, 0, 0), (0.084, 0.084, 0.3)),
                     sort_particles=sort)
    x = lattice_positions()
    assert len(x) == 19773, len(x)
    sim.add_particles(x, 0.001, material="glass")
    for point, normal in [((0, 0, 0), (0, 0, 1)), ((0, 0, 0), (1, 0, 0)),
                          ((0.084, 0, 0), (-1, 0, 0)), ((0, 0, 0), (0, 1, 0)),
                          ((0, 0.084, 0), (0, -1, 0))]:
        sim.add_plane(point, normal, material="glass")
    t0 = time.perf_counter()
    sim.step(1)                       # JIT (or cache load) and first build
    t_first = time.perf_counter() - t0
    t0 = time.perf_counter()
    sim.step(max(settle_steps - 1, 0))
    t_settle = time.perf_counter() - t0
    rb0 = sim.n_rebuilds
    t0 = time.perf_counter()
    sim.step(timed_steps)
    t_timed = time.perf_counter() - t0
    if save_state:
        np.savez(save_state, x=sim.x, v=sim.v, omega=sim.omega)
    return dict(
        gsi_particle_steps_per_s=sim.n * timed_steps / t_timed,
        gsi_seconds=t_timed, gsi_settle_seconds=t_settle, gsi_first_step_seconds=t_first,
        gsi_rebuilds_timed=sim.n_rebuilds - rb0,
        gsi_bytes_per_particle=sim.memory_bytes() / sim.n,
        gsi_n=sim.n, gsi_lost=sim.n_lost,
        gsi_bed_top=float((sim.x[:, 2] + sim.radius).max()),
        gsi_mean_z=float(sim.x[:, 2].mean()),
        gsi_ke=sim.kinetic_energy(rotational=False),
        gsi_ke_rot=sim.kinetic_energy() - sim.kinetic_energy(rotational=False))


def run_liggghts(ranks, settle_steps, timed_steps):
    out = {}
    r = subprocess.run(["bash", f"{BENCH}/run_liggghts_settle.sh", str(ranks)],
                       capture_output=True, text=True, check=True)
    line = r.stdout.strip().splitlines()[-1]
    vals = dict(kv.split("=") for kv in line.split())
    out["liggghts_particle_steps_per_s"] = float(vals["particle_steps_per_s"])
    out["liggghts_seconds"] = float(vals["seconds"])
    # a modified copy for the final state (KE, bed height); not timed
    src = open(f"{BENCH}/settle.liggghts.in").read()
    src = src.replace("thermo_style custom step atoms ke cpu",
                      "compute zmax all reduce max z\ncompute zave all reduce ave z\n"
                      "thermo_style custom step atoms ke c_zmax c_zave cpu")
    src = re.sub(r"^run 50000$", f"run {settle_steps}", src, flags=re.M)
    src = re.sub(r"^run 10000$", f"run {timed_steps}", src, flags=re.M)
    with tempfile.TemporaryDirectory() as d:
        open(os.path.join(d, "in.settle"), "w").write(src)
        cmd = ["liggghts", "-in", "in.settle", "-log", "none"]
        if ranks > 1:
            cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + cmd
        r = subprocess.run(cmd, cwd=d, capture_output=True, text=True, check=True)
    rows = [ln.split() for ln in r.stdout.splitlines()
            if re.match(r"^\s*\d+\s+\d+\s+\S+\s+\S+\s+\S+\s+\S+\s*$", ln)]
    last = rows[-1]
    out["liggghts_ke"] = float(last[2])
    out["liggghts_bed_top"] = float(last[3]) + 0.001
    out["liggghts_mean_z"] = float(last[4])
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", type=int, default=None, help="numba threads (default: all)")
    ap.add_argument("--vs-liggghts", action="store_true", help="also run LIGGGHTS (N ranks = threads)")
    ap.add_argument("--settle-steps", type=int, default=50000)
    ap.add_argument("--timed-steps", type=int, default=10000)
    ap.add_argument("--no-sort", action="store_true",
                    help="keep the particle rows in id order (default: sorted at each "
                         "neighbour build, as LIGGGHTS sorts its atoms)")
    ap.add_argument("--save-state", default=None,
                    help="write the final x, v, omega to this .npz (for benchmarks/settle_scale.py)")
    args = ap.parse_args(argv)
    import numba
    threads = args.threads or numba.config.NUMBA_NUM_THREADS
    numba.set_num_threads(threads)
    res = {"gsi_threads": threads}
    res.update(run_gsi(args.settle_steps, args.timed_steps, args.save_state,
                       not args.no_sort))
    for k, v in res.items():
        print(f"{k} = {v}")
    if args.vs_liggghts:
        lig = run_liggghts(threads, args.settle_steps, args.timed_steps)
        for k, v in lig.items():
            print(f"{k} = {v}")
        res.update(lig)
        res["ratio"] = res["gsi_particle_steps_per_s"] / lig["liggghts_particle_steps_per_s"]
    res["particle_steps_per_s"] = res["gsi_particle_steps_per_s"]   # the key name
    keys = ["gsi_threads", "particle_steps_per_s", "gsi_bytes_per_particle", "gsi_bed_top",
            "gsi_mean_z", "gsi_ke", "gsi_lost"]
    if args.vs_liggghts:
        keys += ["liggghts_particle_steps_per_s", "liggghts_bed_top", "liggghts_mean_z",
                 "liggghts_ke", "ratio"]
    print(" ".join(f"{k}={res[k]:.6g}" if isinstance(res[k], float) else f"{k}={res[k]}"
                   for k in keys))
    return 0


if __name__ == "__main__":
    sys.exit(main())
