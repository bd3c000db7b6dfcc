"""Benchmark "engine compile": the cold compile time of the DEM engine, all variants.

The engine is compiled once for every contact model (gsi.dem.contact.model); this runs,
in a fresh numba cache, the variants the demos, tests and benchmarks use -- Hertz, then
linear + rolling + area heat (adds the conductance sum of the heat check), then a contact
log -- and times each first use, then the same again in a second process (warm cache).

Usage::

    python benchmarks/engine_compile.py

Last line: ``cold_total_s=... cold_cpu_s=... warm_total_s=...`` and each step's seconds
(``cold_cpu_s``: the cold process's CPU time, user + system, which a busy host inflates
less than the wall time; the compiler is single-threaded, so on an idle host the two
agree to within the process start).
"""
import os
import resource
import subprocess
import sys
import tempfile
import time

CHILD = r"""
import time, sys
t0 = time.perf_counter()
import numpy as np
from gsi.dem import Simulation, Material
t_import = time.perf_counter() - t0
m = Material(E=1e7, nu=0.3, rho=2500.0, e=0.5, mu=0.5, mu_r=0.1)
out = {"import": t_import}
def case(name, log=False, **kw):
    t = time.perf_counter()
    sim = Simulation({"g": m}, gravity=(0, 0, -9.81), dt=1e-7, skin=2e-4,
                     domain=((0, 0, 0), (0.01, 0.01, 0.02)), **kw)
    sim.add_particles(np.array([[0.005, 0.005, 0.00099], [0.005, 0.005, 0.00297]]), 0.001,
                      material="g")
    sim.add_plane((0, 0, 0), (0, 0, 1), material="g", temperature=300.0)
    sim.add_mesh_wall(np.array([[0, 0, 0.02], [0.01, 0, 0.02], [0, 0.01, 0.02]]),
                      np.array([[0, 1, 2]]), material="g")
    if log:
        sim.start_contact_log(every=1)
    sim.step(20)
    out[name] = time.perf_counter() - t
case("hertz")
case("linear_rolling_heat", contact="linear", k_n=1e4, rolling=True, heat="area")
case("hertz_log", log=True)
print(" ".join(f"{k}={v:.2f}" for k, v in out.items()))
"""


def run(cache):
    """(wall s, CPU s of the child, its per-case seconds)."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    t = time.perf_counter()
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run([sys.executable, "-c", CHILD], env=env, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode:
        sys.exit(p.stderr[-2000:])
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return time.perf_counter() - t, cpu, dict(kv.split("=") for kv in p.stdout.split()[-4:])


def main():
    with tempfile.TemporaryDirectory() as cache:
        cold, cold_cpu, parts = run(cache)
        warm, _, wparts = run(cache)
    for k, v in parts.items():
        print(f"cold {k:22s} {float(v):7.2f} s   warm {float(wparts[k]):6.2f} s")
    print(f"cold_total_s={cold:.1f} cold_cpu_s={cold_cpu:.1f} warm_total_s={warm:.1f} "
          + " ".join(f"cold_{k}_s={v}" for k, v in parts.items()))


if __name__ == "__main__":
    main()
