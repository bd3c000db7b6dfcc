"""A uniformly heated free bin expands by alpha dT without stress, and the DEM wall follows.

A steel bin (``meshes.build("silo")``, flat floor), insulated, starts uniformly at
T_ref + dT. Held only against rigid-body motion (floor underside: u_z = 0; one floor
vertex: u_x, u_y; a second one: u_y, the values those points take in the free expansion
about O = (0, 0, -thickness)), the exact solution is the stress-free expansion
u = alpha dT (x - O). Through the thermo-mechanical coupling the DEM wall must take the
expanded positions, the von Mises stress must vanish (round-off against E alpha dT), and
the insulated bin must keep its temperature and heat content.
"""
import numpy as np
import pytest
from petsc4py import PETSc

from gsi import meshes
from gsi.coupling.staggered import StaggeredCoupling
from gsi.coupling.thermal import ThermalCoupling
from gsi.dem import Material, Simulation
from gsi.fem import compat
from gsi.fem.elasticity import Elasticity
from gsi.fem.heat import Heat
from gsi.fem.materials import MATERIALS
from gsi.fem.surface import ContactSurface

STEEL = MATERIALS["steel"]
RADIUS, HEIGHT, THICK = 0.05, 0.06, 0.004
T_REF, DT_HEAT = 293.15, 150.0


def _hold_point(el, gid, comps, values):
    """Dirichlet conditions on components ``comps`` of the vertex with global id ``gid``
    (owned or ghost on this rank)."""
    nodes = np.flatnonzero(el.vmap.global_ids == gid)
    for c, v in zip(comps, values):
        dofs = (el.vmap.node_dof[nodes].astype(np.int32) * 3 + c).astype(np.int32)
        el.bcs.append(compat.dirichletbc(PETSc.ScalarType(v), dofs, el.V.sub(c)))


@pytest.fixture(scope="module")
def bin_run():
    sm = meshes.build("silo", radius=RADIUS, height=HEIGHT, thickness=THICK, h=0.02)
    heat = Heat(sm, STEEL, dt=1e-3, T_initial=T_REF + DT_HEAT)
    el = Elasticity(sm, STEEL, T_ref=T_REF)
    el.clamp("support", components=[2])                 # floor underside: u_z = 0
    floor = ContactSurface(elasticity=el, tag="support")
    O = np.array([0.0, 0.0, -THICK])
    eps = STEEL.alpha * DT_HEAT
    r = np.linalg.norm(floor.x0[:, :2], axis=1)
    a = int(np.argmin(r))                                # near the axis
    b = int(np.argmax(floor.x0[:, 0]))                   # far out on +x
    _hold_point(el, floor.global_ids[a], (0, 1), eps * (floor.x0[a, :2] - O[:2]))
    _hold_point(el, floor.global_ids[b], (1,), [eps * (floor.x0[b, 1] - O[1])])
    sim = Simulation({"steel": Material(E=STEEL.E, nu=STEEL.nu, rho=STEEL.rho, k=STEEL.k,
                                        cp=STEEL.c)},
                     heat="area", dt=1e-4, skin=1e-3,
                     domain=((-0.1, -0.1, -0.1), (0.1, 0.1, 0.2)))
    mech = StaggeredCoupling(sim, el, wall_material="steel", n_sub=10)
    tc = ThermalCoupling(sim, heat, mechanics=mech, T_ref=T_REF)
    tc.run(3)
    return tc, O, eps


def test_dem_wall_takes_the_free_expansion(bin_run):
    tc, O, eps = bin_run
    x0 = tc.mechanics.interface.x0
    expected = x0 + eps * (x0 - O)
    assert np.abs(tc.wall.vertices - expected).max() <= 1e-9 * eps * RADIUS
    # the bin grew by alpha dT: inner radius and height
    r = np.linalg.norm(tc.wall.vertices[:, :2], axis=1)
    assert r.max() == pytest.approx(RADIUS * (1 + eps), rel=1e-12)


def test_free_expansion_is_stress_free(bin_run):
    tc, _, eps = bin_run
    assert tc.records[-1].max_von_mises <= 1e-8 * STEEL.E * eps


def test_insulated_bin_keeps_its_heat(bin_run):
    tc, _, _ = bin_run
    h = tc.history()
    assert tc.heat.min_max() == pytest.approx((T_REF + DT_HEAT,) * 2, rel=1e-12)
    assert np.abs(h["drift"]).max() <= 1e-12 * h["E_structure"][0]
    assert np.all(h["Q_particles"] == 0.0) and np.all(h["Q_structure"] == 0.0)
