"""The compiled engine is loaded from numba's cache by the next process.

numba refuses, with only a warning, to cache a function that holds a "dynamic global"
(for example a contact sub-model passed on as a value: see docs/design.md, "Compile
time"), and then every later run compiles the engine again, a minute each.  This runs a
small case (Hertz + rolling + heat, a plane, a mesh wall) in two fresh processes that
share the cache of the test session: the second must load every engine entry point it
uses from the cache and compile none."""
import json
import os
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[3]

CASE = r"""
import json, sys
import numpy as np
from gsi.dem import Simulation, Material
from gsi.dem import engine
sim = Simulation({"m": Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.5, mu_r=0.1)},
                 dt=2e-6, skin=3e-4, domain=((0, 0, 0), (0.012, 0.012, 0.02)), heat="area",
                 rolling=True)
sim.add_particles(np.array([[0.006, 0.006, 0.00099], [0.006, 0.006, 0.00297]]), 1e-3,
                  material="m", T=np.array([300.0, 350.0]))
sim.add_plane((0, 0, 0), (0, 0, 1), material="m", temperature=280.0)
sim.add_mesh_wall([[0, 0, 0.02], [0.012, 0, 0.02], [0, 0.012, 0.02]], [[0, 1, 2]],
                  material="m")
sim.step(20)
f = engine.heat_conductance_sum
json.dump({"advance": [sum(engine.advance.stats.cache_hits.values()),
                       sum(engine.advance.stats.cache_misses.values())],
           "heat_sum": [sum(f.stats.cache_hits.values()), sum(f.stats.cache_misses.values())]},
          sys.stdout)
"""


def _run():
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    env.pop("GSI_NO_JIT", None)
    r = subprocess.run([sys.executable, "-W", "ignore", "-c", CASE], capture_output=True,
                       text=True, env=env, timeout=900)
    assert r.returncode == 0, r.stderr[-2000:]
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_a_second_process_loads_the_engine_from_the_cache():
    _run()                      # compiles what the cache does not hold yet
    second = _run()
    for name, (hits, misses) in second.items():
        assert misses == 0 and hits >= 1, (name, second)
