"""Structure.build is the one structure set-up (gsi/case/structure.py).

* The hopper-membrane structure of demos/hopper_membrane.toml (rubber membrane, circle
  r = 0.3 m, 15 mm thick, h = 60 mm, P2, generalized-alpha rho_inf = 0.3, damping ratio
  0.05, dt_DEM = 0.2 x the Rayleigh time of softwood r = 10 mm) built from its TOML table
  reproduces the set-up the hopper driver wrote by hand, step by step, here: the same
  T_1 bit for bit, n_sub = 34, the same a0 = 2 zeta omega_1 and dt_FE.
* The built problems are the ones the set-up names: a dynamic generalized-alpha
  elasticity with the damping, P2, the interface of the contact face.
* Coupled through ``attach``/``step``, the built membrane (four falling spheres) and the
  built thermal silo (thermo-mechanical, heat-capacity scale 200, three hot particles)
  run bit for bit like the set-ups the two drivers wrote by hand.
"""
import dataclasses
import math

import numpy as np

import pytest
from mpi4py import MPI

from gsi import meshes
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


def _silo_dem(wall_name, wall, s):
    from gsi.coupling.thermal import scale_heat_capacity
    from gsi.dem import Simulation
    clinker = {"clinker": Material(E=5.0e7, nu=0.25, rho=3150.0, e=0.3, mu=0.6, k=1.6,
                                   cp=1000.0)}
    sim = Simulation({**scale_heat_capacity(clinker, s), wall_name: wall}, heat="area",
                     gravity=(0, 0, -9.81), dt=3.0e-5, skin=0.0014,
                     domain=((-0.07, -0.07, -0.02), (0.07, 0.07, 0.14)))
    x = [[0.02 * i - 0.02, 0.0, 0.0041] for i in range(3)]
    sim.add_particles(x, 0.004, material="clinker", T=800.0)
    return sim


def test_build_reproduces_the_thermal_silo_set_up():
    """The thermal-silo structure (demos/thermal_silo.toml: steel silo, P1, quasi-static,
    n_sub 50, convection on "outer", heat-capacity scale 200), built by Structure.build
    and coupled by attach, runs bit for bit like the set-up the silo driver wrote by hand
    (Heat with c / 200, Elasticity with T_ref, StaggeredCoupling + ThermalCoupling)."""
    from gsi.coupling.staggered import StaggeredCoupling
    from gsi.coupling.thermal import ThermalCoupling
    from gsi.fem.heat import Heat
    from gsi.fem.materials import MATERIALS
    geometry = dict(radius=0.05, height=0.08, thickness=0.003, bottom="flat", h=0.016)
    s, n_sub, T_ref = 200.0, 50, 293.15
    steel_dem = Material(E=210.0e9, nu=0.3, rho=7850.0, e=0.3, mu=0.6, k=53.3, cp=440.0)
    # by hand (the silo driver before the runner)
    sm = meshes.build("silo", **geometry)
    mat = MATERIALS["steel"]
    heat = Heat(sm, dataclasses.replace(mat, c=mat.c / s), dt=n_sub * 3.0e-5, theta=1.0,
                T_initial=T_ref)
    heat.set_convection("outer", 25.0, T_ref)
    el = Elasticity(sm, mat, degree=1, scheme="static", T_ref=T_ref)
    el.clamp("support")
    el.set_temperature(T_ref)
    sim_a = _silo_dem("steel", steel_dem, s)
    mech = StaggeredCoupling(sim_a, el, wall_material="steel", n_sub=n_sub)
    tc = ThermalCoupling(sim_a, heat, mechanics=mech, T_ref=T_ref, time_scale=s)
    # by Structure
    st = load(Structure, dict(
        name="silo", mesh="silo", geometry=geometry, material="steel", degree=1,
        scheme="static", supports=["support"],
        thermal=dict(T_ref=T_ref, T_initial=T_ref,
                     convection=[dict(tag="outer", h=25.0, T_ambient=T_ref)]),
        contact=dict(tags=["contact"], mode="both", wall_material="steel", n_sub=n_sub)),
        "structures[0]")
    cs = st.build(comm=MPI.COMM_WORLD, dt_dem=3.0e-5, heat_scale=s)
    name, wall = st.dem_wall_material({"steel": steel_dem})
    sim_b = _silo_dem(name, wall, s)
    cs.attach(sim_b)
    for _ in range(6):
        ra = tc.step()
        rb = cs.step(sim_b)
        da, db = dataclasses.asdict(ra), dataclasses.asdict(rb.thermal)
        assert da == db
    assert tc.records[-1].Q_particles > 0
    assert np.array_equal(el.u.x.array, cs.elasticity.u.x.array)
    assert np.array_equal(heat.T.x.array, cs.heat.T.x.array)
    assert np.array_equal(sim_a.T, sim_b.T)


def test_built_membrane_couples_like_the_hand_set_up(built):
    """The hopper-membrane structure coupled through attach/step runs bit for bit like
    the hand-written set-up (dynamic generalized-alpha Elasticity with a0, clamped rim,
    StaggeredCoupling with the "rubber" wall) under four falling softwood spheres."""
    from gsi.coupling.staggered import StaggeredCoupling
    from gsi.dem import Simulation
    st, _, dt_dem = built
    rubber = Material(E=2.0e6, nu=0.45, rho=930.0, e=0.5, mu=0.8, mu_r=0.2)

    def dem():
        sim = Simulation({"softwood": SOFTWOOD, "rubber": rubber}, rolling=True, dt=dt_dem,
                         skin=0.004, domain=((-0.45, -0.45, -0.3), (0.45, 0.45, 1.0)))
        sim.add_particles([[0.05 * i, 0.03, 0.015 + 0.012 + 0.004 * i] for i in range(4)],
                          0.01, material="softwood")
        return sim

    cs = st.build(comm=MPI.COMM_WORLD, dt_dem=dt_dem)
    sm = meshes.build("membrane", **TABLE["geometry"])
    el = Elasticity(sm, "rubber", degree=2, scheme="generalized_alpha", dt=cs.dt,
                    rho_inf=0.3, rayleigh=(2.0 * 0.05 * 2.0 * math.pi / cs.T_1, 0.0))
    el.clamp("support")
    sim_a, sim_b = dem(), dem()
    cp = StaggeredCoupling(sim_a, el, wall_material="rubber", n_sub=cs.n_sub)
    cs.attach(sim_b)
    skip = ("wall_dem", "wall_fe", "wall_transfer")
    for _ in range(12):
        ra, rb = cp.step(), cs.step(sim_b).mechanical
        da, db = dataclasses.asdict(ra), dataclasses.asdict(rb)
        assert {k: v for k, v in da.items() if k not in skip} == \
            {k: v for k, v in db.items() if k not in skip}
    assert cp.records[-1].max_deflection > 0
    assert np.array_equal(el.u.x.array, cs.elasticity.u.x.array)
