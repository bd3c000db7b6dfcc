"""structures.translate places a body: every node moves by the vector, tags unchanged."""
import numpy as np
from mpi4py import MPI

from gsi.case.structure import Structure
from gsi.config.schema import load
from gsi.fem import compat


def test_translate_shifts_every_node():
    kw = dict(name="bar", mesh="box", geometry={"length_x": 0.2, "length_y": 0.05,
                                                 "length_z": 0.05, "h": 0.05},
              supports=["x0"], contact={"tags": ["x1"]})
    a = load(Structure, kw).load_mesh(comm=MPI.COMM_WORLD)
    b = load(Structure, dict(kw, translate=[1.0, -2.0, 0.5])).load_mesh(comm=MPI.COMM_WORLD)
    xa, xb = compat.geometry_x(a.mesh), compat.geometry_x(b.mesh)
    assert np.allclose(xb - xa, [1.0, -2.0, 0.5], rtol=0, atol=1e-15)
    assert a.tags == b.tags
