"""The generated engines: the template is not an engine, an engine is rewritten when a
source it is built from changes, and GSI_NO_JIT=1 runs the same kernels as Python."""
import json
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

from gsi.dem import engine_factory as ef

ROOT = pathlib.Path(__file__).resolve().parents[3]


def test_template_is_not_an_engine():
    with pytest.raises(ImportError, match="get_engine"):
        import gsi.dem.engine  # noqa: F401


def test_engine_holds_only_law_calling_kernels(tmp_path, monkeypatch):
    monkeypatch.setenv("GSI_ENGINE_DIR", str(tmp_path))
    monkeypatch.setattr(ef, "_ENGINES", {})
    eng = ef.get_engine("linear", False, None)
    src = pathlib.Path(eng.__file__).read_text()
    assert "from gsi.dem.contact.linear import linear as LAW" in src
    for shared in ("def move_walls", "def plane_sums", "def mesh_scatter", "def scan(",
                   "def integrate_rows", "def select_triangle_contacts"):
        assert shared not in src
    assert eng.move_walls.__module__ == "gsi.dem.wall_kernels"


def test_engine_is_rewritten_when_a_source_changes(tmp_path, monkeypatch):
    """A copy of a source file stands in for the real one; editing it must change the
    digest and rewrite the engine module, and an unchanged source must not."""
    monkeypatch.setenv("GSI_ENGINE_DIR", str(tmp_path / "engines"))
    copy = tmp_path / "heat.py"
    copy.write_text((ROOT / "gsi" / "dem" / "heat.py").read_text())
    real = ef.engine_sources

    def sources():
        return [copy if f.name == "heat.py" else f for f in real()]
    monkeypatch.setattr(ef, "engine_sources", sources)
    monkeypatch.setattr(ef, "_ENGINES", {})
    eng = ef.get_engine("hertz", False, "area")
    path = pathlib.Path(eng.__file__)
    first = path.read_text()
    digest = ef.sources_digest()
    assert f"# kernel sources: {digest}" in first
    mtime = path.stat().st_mtime_ns

    monkeypatch.setattr(ef, "_ENGINES", {})
    ef.get_engine("hertz", False, "area")              # nothing changed: kept as is
    assert path.stat().st_mtime_ns == mtime

    copy.write_text(copy.read_text() + "\n# an edit\n")
    assert ef.sources_digest() != digest
    monkeypatch.setattr(ef, "_ENGINES", {})
    eng2 = ef.get_engine("hertz", False, "area")
    second = pathlib.Path(eng2.__file__).read_text()
    assert second != first and f"# kernel sources: {ef.sources_digest()}" in second


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


def _run_case(no_jit, tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT), GSI_NO_JIT="1" if no_jit else "0",
               GSI_ENGINE_DIR=os.environ.get("GSI_ENGINE_DIR", str(tmp_path)))
    r = subprocess.run([sys.executable, "-c", CASE], capture_output=True, text=True,
                       env=env, timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_no_jit_runs_a_small_case_like_the_compiled_engine(tmp_path):
    """36 particles on a mesh floor beside a hot plane, 6 steps: plain Python
    (GSI_NO_JIT=1) and the compiled engine agree to round-off."""
    py = _run_case(True, tmp_path)
    jit = _run_case(False, tmp_path)
    assert py["nc"] == jit["nc"] > 100
    np.testing.assert_allclose(py["x"], jit["x"], rtol=0, atol=1e-15)
    np.testing.assert_allclose(py["v"], jit["v"], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(py["T"], jit["T"], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(py["wall"], jit["wall"], rtol=1e-10)
    assert abs(jit["wall"][2]) > 0
