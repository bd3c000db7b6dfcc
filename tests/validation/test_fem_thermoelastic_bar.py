"""docs/design.md, "Validation cases", case 7: thermo-elastic bar heated uniformly by dT.

* free bar (held only on three symmetry planes): elongation alpha dT L, zero stress;
* bar clamped axially at both ends, laterally free (uniaxial stress state):
  sigma_xx = -E alpha dT, sigma_yy = sigma_zz = 0, end reaction E alpha dT A.
Both states are linear/uniform, so the FE answer is exact to round-off.
The clamped case takes its temperature from the coupled ThermoElastic problem (a heat
problem started uniform at T_ref + dT with insulated faces stays there).
"""
import numpy as np
import pytest
import ufl

from gsi import meshes
from gsi.fem import compat
from gsi.fem.elasticity import Elasticity
from gsi.fem.materials import MATERIALS
from gsi.fem.thermoelastic import ThermoElastic

D = "docs/design.md"  # where the references are written down

STEEL = MATERIALS["steel"]
L, B, DT, T_REF = 1.0, 0.1, 150.0, 20.0


def _bar():
    return meshes.build("box", length_x=L, length_y=B, length_z=B, n=(10, 2, 2))


def _stress_components(p):
    S = compat.function(compat.vector_space(p.mesh, 0, "DG"))
    s = p.sigma()
    compat.interpolate_expression(S, ufl.as_vector([s[0, 0], s[1, 1], s[2, 2]]))
    return S.x.array.reshape(-1, 3)


def test_free_bar_expands_without_stress(record_validation):
    p = Elasticity(_bar(), STEEL, T_ref=T_REF)
    p.clamp("x0", components=[0])
    p.clamp("y0", components=[1])
    p.clamp("z0", components=[2])
    p.set_temperature(T_REF + DT)
    p.solve()
    x = p.V.tabulate_dof_coordinates()
    U = p.u.x.array.reshape(-1, 3)
    eps = STEEL.alpha * DT
    assert np.abs(U - eps * x).max() <= 1e-10 * eps * L
    record_validation("free thermo-elastic bar: elongation alpha dT L", reference=eps * L,
                      measured=U[:, 0].max(), tolerance=1e-10, unit="m",
                      source=f'{D}, "Validation cases" 7')
    assert U[:, 0].max() == pytest.approx(eps * L, rel=1e-10)
    E_a = STEEL.E * eps
    assert np.abs(_stress_components(p)).max() <= 1e-9 * E_a


def test_clamped_bar_carries_minus_E_alpha_dT(record_validation):
    te = ThermoElastic(_bar(), STEEL, dt=1.0, T_ref=T_REF, T_initial=T_REF + DT)
    p = te.elasticity
    p.clamp("x0", components=[0])
    p.clamp("x1", components=[0])
    p.clamp("y0", components=[1])
    p.clamp("z0", components=[2])
    te.step()  # no heat boundary conditions: T stays T_ref + DT
    assert te.heat.min_max() == pytest.approx((T_REF + DT, T_REF + DT), rel=1e-12)
    S = _stress_components(p)
    E_a = STEEL.E * STEEL.alpha * DT
    assert np.abs(S[:, 0] + E_a).max() <= 1e-9 * E_a
    assert np.abs(S[:, 1:]).max() <= 1e-9 * E_a
    record_validation("clamped thermo-elastic bar: end reaction -E alpha dT A",
                      reference=-E_a * B * B, measured=p.reaction("x1")[0], tolerance=1e-9,
                      unit="N", source=f'{D}, "Validation cases" 7')
    assert p.reaction("x1")[0] == pytest.approx(-E_a * B * B, rel=1e-9)
    assert te.n_factorizations == 2
