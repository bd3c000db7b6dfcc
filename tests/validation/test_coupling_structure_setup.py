"""Structure.build is the one structure set-up (gsi/case/structure.py).

* The hopper-membrane structure of demos/hopper_membrane.toml (rubber membrane, circle
  r = 0.3 m, 15 mm thick, h = 60 mm, P2, generalized-alpha rho_inf = 0.3, damping ratio
  0.05, dt_DEM = 0.2 x the Rayleigh time of softwood r = 10 mm) built from its TOML table
  reproduces the set-up the hopper driver wrote by hand, step by step, here: the same
  T_1 bit for bit, n_sub = 34, the same a0 = 2 zeta omega_1 and dt_FE.
* The built problems are the ones the set-up names: a dynamic generalized-alpha
  elasticity with the damping, P2, the interface of the contact face.
"""
import math

import pytest
from mpi4py import MPI

import meshes
from gsi.case.structure import Structure
from gsi.config.schema import load
from gsi.coupling.staggered import choose_n_sub, lowest_period
from gsi.dem import Material
from gsi.dem.materials import rayleigh_time
from gsi.fem.elasticity import Elasticity

SOFTWOOD = Material(E=5.0e5, nu=0.45, rho=400.0, e=0.5, mu=0.8, mu_r=0.2)
TABLE = dict(name="membrane", mesh="membrane",
             geometry=dict(shape="circle", radius=0.3, thickness=0.015, h=0.06, n_thickness=1),
             material="rubber", degree=2, scheme="generalized_alpha", rho_inf=0.3,
             damping_ratio=0.05, supports=["support"],
             contact=dict(tags=["contact"], wall_material="rubber", steps_per_period=20))


@pytest.fixture(scope="module")
def built():
    dt_dem = 0.2 * rayleigh_time(0.01, SOFTWOOD)
    st = load(Structure, TABLE, "structures[0]")
    return st, st.build(comm=MPI.COMM_WORLD, dt_dem=dt_dem, gravity=(0.0, 0.0, -9.81)), dt_dem


def test_build_reproduces_the_hopper_membrane_set_up(built):
    st, cs, dt_dem = built
    # the hand-written set-up of the hopper driver (before the runner)
    sm = meshes.build("membrane", **TABLE["geometry"])
    static = Elasticity(sm, "rubber", degree=2)
    static.clamp("support")
    T_1 = lowest_period(static)
    n_sub = choose_n_sub(dt_dem, T_1, steps_per_period=20)
    assert n_sub == 34
    assert cs.T_1 == T_1
    assert cs.n_sub == n_sub
    assert cs.dt == n_sub * dt_dem
    assert cs.a0 == 2.0 * 0.05 * 2.0 * math.pi / T_1


def test_built_problems_are_the_named_ones(built):
    st, cs, dt_dem = built
    el = cs.elasticity
    assert el.scheme == "generalized_alpha" and el.degree == 2 and el.dt == cs.dt
    assert el.rayleigh == (cs.a0, 0.0)
    assert el.params["alpha_f"] == pytest.approx(0.3 / 1.3, rel=1e-15)
    assert el.supports == ("support",)
    assert cs.heat is None and cs.mode == "mechanical"
    assert cs.interface.n_midpoints > 0                       # P2 wall split at midpoints
    assert cs.interface.surface.area() == pytest.approx(math.pi * 0.3**2, rel=0.01)
    assert cs.wall_material == "rubber"
