"""GSI_NO_JIT=1 (the kernels as plain Python, for debugging) runs the same engine as the
compiled one: a small case with pairs, a hot plane and a mesh floor agrees to round-off
(kept from the removed engine-factory tests)."""
import json
import os
import pathlib
import subprocess
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[3]

CASE = r"""
import json, sys
import numpy as np
from gsi.dem import Simulation, Material
sim = Simulation({"m": Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.5)}, dt=2e-6,
                 skin=3e-4, domain=((0, 0, 0), (0.012, 0.012, 0.02)), heat="area")
k = np.arange(36)
x = np.column_stack([0.00099 + 0.00199 * (k % 6), 0.00099 + 0.00199 * (k // 6),
                     0.00097 + 0.00002 * (k % 2)])
sim.add_particles(x, 1e-3, material="m", v=np.column_stack([np.zeros(36), np.zeros(36),
                                                            -0.3 * np.ones(36)]),
                  T=np.linspace(0, 50, 36))
sim.add_plane((0, 0, 0), (1, 0, 0), material="m", temperature=80.0)
sim.add_mesh_wall([[0, 0, 0], [0.012, 0, 0], [0, 0.012, 0], [0.012, 0.012, 0]],
                  [[0, 1, 2], [1, 3, 2]], material="m", vertex_temperature=20.0)
sim.step(6)
json.dump({"x": sim.x.tolist(), "v": sim.v.tolist(), "T": sim.T.tolist(),
           "nc": sim.contact_count(), "wall": sim.mesh_walls[0].force.tolist()}, sys.stdout)
"""


def _run_case(no_jit):
    env = dict(os.environ, PYTHONPATH=str(ROOT), GSI_NO_JIT="1" if no_jit else "0")
    r = subprocess.run([sys.executable, "-c", CASE], capture_output=True, text=True,
                       env=env, timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_no_jit_runs_a_small_case_like_the_compiled_engine():
    """36 particles on a mesh floor beside a hot plane, 6 steps: plain Python and the
    compiled engine agree to round-off."""
    py = _run_case(True)
    jit = _run_case(False)
    assert py["nc"] == jit["nc"] > 100
    np.testing.assert_allclose(py["x"], jit["x"], rtol=0, atol=1e-15)
    np.testing.assert_allclose(py["v"], jit["v"], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(py["T"], jit["T"], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(py["wall"], jit["wall"], rtol=1e-10)
    assert abs(jit["wall"][2]) > 0
