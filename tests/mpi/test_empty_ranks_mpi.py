"""Ranks without cells: structures of ONE tetrahedron (a gmsh ``.msh`` file) on 1, 2 and 3
MPI ranks (3 oversubscribed on a 2-core machine), through the runner
(tests/mpi/empty_ranks_case.py), so that one or two ranks own no cell of a structure.

The case: a stream of hot particles onto two one-tetrahedron structures, a P1 one
coupled thermo-mechanically (Newmark, heat, convection) and a P2 static one (mechanical):
assembly, nodal loads, the surface gather, the XDMF output and the checkpoints all run
on ranks with no cell. Checked: the ranks own 1 cell in all; the particles' final
positions, velocities and temperatures, each structure's interface displacement, the
summary numbers and the monitor series agree with the serial run to 1e-9 relative (the
partitioned direct solve's round-off is all that differs); a run rewound to its older
checkpoint and resumed ends bit-identical to the uninterrupted run on every rank.
"""
import importlib.util
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("gsi_tests_mpirun", HERE / "mpirun.py")
mpirun = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(mpirun)

pytestmark = pytest.mark.mpi
RTOL = 1e-9

CASE = """
[case]
name = "one_tet"

[run]
duration = 0.012
dt = 1.5e-5
seed = 7
progress = false
heat_time_scale = 10.0

[dem]
contact = "hertz"
heat = "area"
gravity = [0.0, 0.0, -9.81]
domain_lo = [-0.01, -0.01, -0.01]
domain_hi = [0.07, 0.04, 0.05]

[materials.ore]
E = 5.0e7
nu = 0.25
rho = 3000.0
e = 0.3
mu = 0.5
k = 2.0
cp = 100.0

[[particles]]
name = "stream"
material = "ore"
fill = "stream"
rate = 8000.0
max_count = 60
velocity = [0.0, 0.0, -2.0]
temperature = 600.0
size = { kind = "uniform", min = 1.5e-3, max = 2.0e-3 }
region = { kind = "box", lo = [0.002, 0.002, 0.019], hi = [0.042, 0.012, 0.026] }

[[structures]]
name = "tet"
file = "tet.msh"
tags = { support = "bottom", contact = "top", cooled = "side_x" }
material = "steel"
degree = 1
scheme = "newmark"
supports = ["support"]
thermal = { T_ref = 300.0, convection = [ { tag = "cooled", h = 200.0, T_ambient = 300.0 } ] }
contact = { tags = ["contact"], mode = "both", n_sub = 20 }

[[structures]]
name = "tet2"
file = "tet.msh"
translate = [0.03, 0.0, 0.0]
tags = { support = "bottom", contact = "top" }
material = "steel"
degree = 2
scheme = "static"
supports = ["support"]
contact = { tags = ["contact"], mode = "mechanical", n_sub = 10 }

[[monitors]]
name = "tet"
kind = "structure"
target = "tet"
interval = 0.002

[[monitors]]
name = "tet2"
kind = "structure"
target = "tet2"
interval = 0.002

[[monitors]]
name = "hot"
kind = "temperature"
group = "stream"
interval = 0.002

[output]
interval = 0.004
pictures = false
"""


def one_tetrahedron(path, side=0.02):
    """A .msh of ONE first-order tetrahedron (0,0,0), (s,0,0), (0,s,0), (0,0,s) with the
    physical surfaces bottom (z = 0), side_x (x = 0), side_y (y = 0), top (the slanted
    face) and the volume solid."""
    import gmsh
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("tet")
        geo = gmsh.model.geo
        for i, p in enumerate([(0, 0, 0), (side, 0, 0), (0, side, 0), (0, 0, side)], 1):
            geo.addPoint(*p, meshSize=10 * side, tag=i)
        lines = {}

        def line(a, b):
            key = (min(a, b), max(a, b))
            if key not in lines:
                lines[key] = geo.addLine(*key)
            return lines[key] if a < b else -lines[key]
        faces = {}
        for name, (a, b, c) in dict(bottom=(1, 3, 2), side_y=(1, 2, 4), side_x=(1, 4, 3),
                                    top=(2, 3, 4)).items():
            faces[name] = geo.addPlaneSurface([geo.addCurveLoop([line(a, b), line(b, c),
                                                                 line(c, a)])])
        volume = geo.addVolume([geo.addSurfaceLoop(list(faces.values()))])
        geo.synchronize()
        for name, tag in faces.items():
            gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, [tag]), name)
        gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [volume]), "solid")
        gmsh.option.setNumber("Mesh.MeshSizeMin", 10 * side)
        gmsh.model.mesh.generate(3)
        assert [len(t) for t in gmsh.model.mesh.getElements(3)[1]] == [1]
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("empty_ranks")
    one_tetrahedron(tmp / "tet.msh")
    (tmp / "case.toml").write_text(CASE)
    return {n: mpirun.run_json(HERE / "empty_ranks_case.py", n, tmp / f"r{n}.json",
                               timeout=900, args=(tmp / "case.toml", tmp))
            for n in (1, 2, 3)}


def _close(x, y, key):
    x, y = np.asarray(x, float), np.asarray(y, float)
    assert x.shape == y.shape, key
    scale = np.nanmax(np.abs(x), initial=0.0)
    assert np.allclose(x, y, rtol=0, atol=RTOL * max(scale, 1e-300), equal_nan=True), \
        (key, np.nanmax(np.abs(x - y), initial=0.0), scale)


@pytest.mark.parametrize("n", [2, 3])
def test_ranks_without_cells_give_the_serial_result(results, n):
    serial, r = results[1], results[n]
    assert r["n_ranks"] == n
    for name in ("tet", "tet2"):
        assert sum(r["cells"][name]) == 1 and r["cells"][name].count(0) == n - 1
    assert len(serial["x"]) > 20                        # particles came and hit
    assert serial["summary"]["tet.load_z_min"] < 0 and serial["summary"]["tet2.load_z_min"] < 0
    assert np.abs(serial["u"]["tet"]).max() > 0 and np.abs(serial["u"]["tet2"]).max() > 0
    assert serial["summary"]["tet.T_max"] > 300.0       # heat went in
    for key in ("x", "v", "T"):
        _close(serial[key], r[key], key)
    for name in serial["u"]:
        _close(serial["u"][name], r["u"][name], f"u.{name}")
    assert serial["summary"].keys() == r["summary"].keys()
    for key, value in serial["summary"].items():
        if "balance" not in key:                         # round-off themselves
            _close(value, r["summary"][key], key)
    for name, series in serial["monitors"].items():
        for column, values in series.items():
            _close(values, r["monitors"][name][column], f"{name}.{column}")


@pytest.mark.parametrize("n", [1, 2, 3])
def test_ranks_without_cells_checkpoint_and_resume_bitwise(results, n):
    assert results[n]["resume_bitwise"] == [True] * n
