"""The shipped user-style gmsh script meshes/belt.geo, loaded through Structure.

* DefineConstant overrides from the case (``geometry = {length = 0.4, ...}``) reach the
  script: the mesh has the requested size.
* The belt clamped at its ends by its own physical group ("belt_ends", mapped to
  gsi's "support") under a uniform pressure p on "belt_top" deflects like the same plate
  built independently (dolfinx's structured box, faces tagged by coordinates, P2): the
  maxima agree within 2 % (measured 0.8 %). Both lie between the clamped-clamped beam,
  w = p L^4 / (384 E I / b), and cylindrical bending (E / (1 - nu^2)), plus the shear
  deflection p L^2 / (8 kappa G t) of a Timoshenko beam (kappa = 5/6).
"""
import pytest
from mpi4py import MPI

from gsi import meshes
from gsi.case.structure import Structure
from gsi.config.schema import load
from gsi.fem import compat
from gsi.fem.elasticity import Elasticity

L, W, T, H = 0.4, 0.1, 0.01, 0.02
P = 1.0e4          # Pa, pressure on the top face (downward)
STEEL = dict(E=210e9, nu=0.3, rho=7850.0)


def _belt():
    table = dict(name="belt", file="belt.geo",
                 geometry=dict(length=L, width=W, thickness=T, h=H, layers=2),
                 tags=dict(support="belt_ends", contact="belt_top"), material="steel",
                 degree=2, scheme="static", supports=["support"],
                 loads=[dict(tag="contact", traction=[0.0, 0.0, -P])], contact=dict(n_sub=1))
    st = load(Structure, table, "structures[0]")
    st.check(base_dir=meshes.DIR)
    return st.build(comm=MPI.COMM_WORLD, dt_dem=1e-5, base_dir=meshes.DIR)


def _max_deflection(el):
    el.solve()
    return el.max_displacement()


def test_geo_overrides_reach_the_script():
    cs = _belt()
    x = compat.geometry_x(cs.mesh.mesh)
    lo = MPI.COMM_WORLD.allreduce(x.min(axis=0), op=MPI.MIN)
    hi = MPI.COMM_WORLD.allreduce(x.max(axis=0), op=MPI.MAX)
    assert hi - lo == pytest.approx([L, W, T], rel=1e-12)
    assert cs.mesh.params["Parameters/length"] == L
    assert set(cs.mesh.tags) >= {"belt_top", "belt_ends", "belt_bottom", "belt_sides",
                                 "support", "contact", "volume"}
    assert cs.mesh.tags["support"] == cs.mesh.tags["belt_ends"]


def test_clamped_belt_deflects_like_an_independent_plate_solve():
    cs = _belt()
    w_geo = _max_deflection(cs.elasticity)
    box = meshes.build("box", length_x=L, length_y=W, length_z=T, n=(40, 10, 2))
    ref = Elasticity(box, STEEL, degree=2)
    ref.clamp("x0")
    ref.clamp("x1")
    ref.set_traction("z1", (0.0, 0.0, -P))
    w_box = _max_deflection(ref)
    assert w_geo == pytest.approx(w_box, rel=0.02)
    E, nu = STEEL["E"], STEEL["nu"]
    I_b = T**3 / 12.0
    shear = P * L**2 / (8 * (5 / 6) * E / (2 * (1 + nu)) * T)
    w_beam = P * L**4 / (384 * E * I_b) + shear
    w_cyl = P * L**4 * (1 - nu**2) / (384 * E * I_b) + shear
    for w in (w_geo, w_box):
        assert w_cyl * 0.97 <= w <= w_beam * 1.03
    # the support carries the load: reaction = p L W upward
    assert cs.elasticity.reaction("support")[2] == pytest.approx(P * L * W, rel=1e-9)
