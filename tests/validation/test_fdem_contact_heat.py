"""Seed 002 (the FDEM contact-heat paper), section 3 and "Perfect contact validation":
heat across the overlap of two meshed bodies (:mod:`gsi.fem.contact_heat`).

References (all independent of the contact code):

* contact area: two boxes overlapping by p on their end faces share the cross-section
  0.1 x 0.1 m exactly, whatever the two meshes (the intersection polygons tile it);
* perfect contact (tiny R_c): two 0.5 m bars overlapping by p = 0.001 m behave as the
  single 1 m bar of the slab test (tests/validation/test_fdem_slab.py) -- the paper's
  Figs. 9-10; the issue's target: within 0.5 % of Delta T;
* a real contact resistance, steady: the bar chain T = 1 | 0.5 m | R_c | 0.5 m | T = 0
  carries q = 1/(L_A/k + R_c + L_B/k) and jumps by q R_c at the contact (P1 is exact for
  the linear profiles, so this holds to solver round-off);
* lumped bodies: two blocks at 1 and 0 degC with adiabatic outer faces exchange
  g (T_A - T_B), g = S/R_c: T_A - T_B = exp(-g (1/C_A + 1/C_B) t). The ``mean`` variant
  (explicit) is exactly the forward-Euler recursion (1 - lambda dt)^n of that ODE; the
  ``local`` variant on conducting blocks (Biot g L/(k S) = 1e-3) follows the exponential
  within the backward-Euler time error;
* energy: with adiabatic outer faces the stored heat is constant to round-off, and the
  heat one body gives is the heat the other takes.
"""
import math

import numpy as np
import pytest

from gsi import meshes
from gsi.errors import GsiInputError
from gsi.fem import compat
from gsi.fem.contact_heat import ContactHeatSystem, ThermalContact, triangle_tetra_area
from gsi.fem.heat import Heat
from gsi.fem.materials import StructuralMaterial

MAT = StructuralMaterial(E=1e9, nu=0.3, rho=1000.0, c=1.0, k=1.0)      # alpha = 1e-3 m^2/s
P = 0.001                                                              # penetration (m)


def bar(length, h, shift=0.0, **kw):
    sm = meshes.build("box", length_x=length, length_y=0.1, length_z=0.1, h=h, **kw)
    compat.geometry_x(sm.mesh)[:, 0] += shift
    return sm


def pair(h_a, h_b, dt, *, theta=1.0, R_c=1e-6, mat=MAT, length=0.5, **kw):
    """Bars A = [0, L], B = [L - P, 2L - P]; B's far end at 1 degC if ``fixed``."""
    ha = Heat(bar(length, h_a), mat, dt=dt, theta=theta)
    hb = Heat(bar(length, h_b, length - P), mat, dt=dt, theta=theta)
    c = ThermalContact(ha, hb, tags_a=["x1"], tags_b=["x0"], R_c=R_c, **kw)
    return ha, hb, c


def test_triangle_in_tetrahedron_area():
    tet = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    inside = np.array([[0.1, 0.1, 0.1], [0.3, 0.1, 0.1], [0.1, 0.3, 0.1]])
    assert triangle_tetra_area(inside, tet) == pytest.approx(0.02, rel=1e-14)
    big = np.array([[-1, -1, 0.5], [3, -1, 0.5], [-1, 3, 0.5]], float)
    assert triangle_tetra_area(big, tet) == pytest.approx(0.5 * 0.5 * 0.5, rel=1e-14)  # z = 1/2 section
    assert triangle_tetra_area(big + [0, 0, 2], tet) == 0.0


@pytest.mark.parametrize("h_a,h_b", [(0.05, 0.05), (0.05, 0.034), (0.1, 0.05)])
def test_flat_overlap_area_is_exact_on_any_meshes(h_a, h_b, record_validation):
    _, _, c = pair(h_a, h_b, 1.0)
    assert c.S_tar == pytest.approx(0.01, rel=1e-12)
    assert c.S_con == pytest.approx(0.01, rel=1e-12)
    record_validation(f"FE-FE contact area of two overlapping boxes (h {h_a} / {h_b} m)",
                      reference=0.01, measured=c.area, tolerance=1e-12, unit="m^2",
                      source="the FDEM paper's §3: S_c of a flat overlap")
    assert c.area == pytest.approx(0.01, rel=1e-12)
    assert c.total_conductance == pytest.approx(0.01 / 1e-6, rel=1e-12)


def _profile(heat, times):
    """{t: {node position: T}} of ``heat``, stepped to each of ``times``."""
    out = {}
    for t in times:
        while heat.t < t - 1e-9:
            heat.step()
        out[t] = _by_point(heat.V.tabulate_dof_coordinates(), heat.T.x.array)
    return out


def _by_point(x, T):
    """{node position rounded to 1e-9 m: temperature}."""
    return {tuple(np.round(p, 9)): v for p, v in zip(x, T)}


def test_two_bars_with_a_perfect_contact_equal_the_single_bar():
    """Both on h = 0.05 m (theta = 1, dt = 0.05 s), nodes compared at the same (unrolled)
    positions. Measured: largest nodal difference to the single bar 0.016 / 0.023 / 0.0023
    % of Delta T at 10 / 50 / 100 s (target 0.5 %); the stored heat equals the Dirichlet
    inflow to 1e-10."""
    dt, times = 0.05, (10.0, 50.0, 100.0)
    single = Heat(bar(1.0, 0.05), MAT, dt=dt, theta=1.0)
    single.fix_temperature("x1", 1.0)
    ref = _profile(single, times)
    ha, hb, c = pair(0.05, 0.05, dt)
    hb.fix_temperature("x1", 1.0)
    group = ContactHeatSystem([c])
    inflow = 0.0
    diffs = []
    for t in times:
        while ha.t < t - 1e-9:
            group.step()
            inflow += hb.dirichlet_heat_flow() * dt
            assert abs(ha.contact_heat.sum() + hb.contact_heat.sum()) < 1e-9 * c.total_conductance
        xb = hb.V.tabulate_dof_coordinates() + [P, 0.0, 0.0]     # unrolled: B at [0.5, 1]
        d = 0.0
        for x, T in ((ha.V.tabulate_dof_coordinates(), ha.T.x.array), (xb, hb.T.x.array)):
            d = max(d, max(abs(v - ref[t][k]) for k, v in _by_point(x, T).items()))
        diffs.append(d)
    print("max |T_two - T_single| / dT at 10, 50, 100 s:", np.round(diffs, 6))
    assert max(diffs) <= 0.005
    stored = ha.stored_heat() + hb.stored_heat()
    assert abs(stored - inflow) <= 1e-10 * stored


@pytest.mark.parametrize("h_b", [0.05, 0.034])
@pytest.mark.parametrize("R_c", [0.5, 0.05])
def test_steady_jump_is_q_times_Rc(R_c, h_b, record_validation):
    """T = 1 on A's far end, 0 on B's: q = 1/(0.5/k + R_c + 0.5/k), jump q R_c.

    The heat flow is q S to 2.5e-5 (measured 1.1e-5); the profiles are linear to 1e-3 of
    Delta T (measured 4.8e-4 to 7.4e-4) and the jump is q R_c to 2e-3 (measured 5e-5 to
    4.3e-4): the paper's equal split of a couple's heat over its cells' surface nodes is
    not the consistent load of a uniform flux where a cell touches the surface by an edge
    only, so the contact faces are not quite isothermal. A's mesh h = 0.05 m."""
    ha, hb, c = pair(0.05, h_b, 1e10, R_c=R_c)
    ha.fix_temperature("x0", 1.0)
    hb.fix_temperature("x1", 0.0)
    ContactHeatSystem([c]).step()                       # backward Euler, dt >> L^2/alpha
    q = 1.0 / (0.5 / MAT.k + R_c + 0.5 / MAT.k)
    xa = ha.V.tabulate_dof_coordinates()[:, 0]
    xb = hb.V.tabulate_dof_coordinates()[:, 0] - (0.5 - P)
    assert np.allclose(ha.T.x.array, 1.0 - q * xa / MAT.k, atol=1e-3, rtol=0)
    assert np.allclose(hb.T.x.array, q * (0.5 - xb) / MAT.k, atol=1e-3, rtol=0)
    jump = ha.T.x.array[np.isclose(xa, 0.5)].mean() - hb.T.x.array[np.isclose(xb, 0.0)].mean()
    src = "q = 1/(L_A/k + R_c + L_B/k), jump q R_c (the FDEM paper's contact)"
    record_validation(f"steady contact (R_c = {R_c}, h_B = {h_b} m): temperature jump",
                      reference=q * R_c, measured=jump, tolerance=2e-3, unit="K", source=src)
    record_validation(f"steady contact (R_c = {R_c}, h_B = {h_b} m): heat flow",
                      reference=q * 0.01, measured=c.heat_flow(), tolerance=2.5e-5, unit="W",
                      source=src)
    assert jump == pytest.approx(q * R_c, rel=2e-3)
    assert c.heat_flow() == pytest.approx(q * 0.01, rel=2.5e-5)
    assert hb.dirichlet_heat_flow("x1") == pytest.approx(-q * 0.01, rel=2.5e-5)
    assert ha.dirichlet_heat_flow("x0") == pytest.approx(q * 0.01, rel=2.5e-5)


def _blocks(variant, dt, k):
    """Two 0.1 m cubes at 1 and 0 degC, R_c = 10 m^2 K/W: g = 1e-3 W/K, C = 1 J/K each."""
    mat = StructuralMaterial(E=1e9, nu=0.3, rho=1000.0, c=1.0, k=k)
    ha = Heat(bar(0.1, 0.05), mat, dt=dt, theta=1.0, T_initial=1.0)
    hb = Heat(bar(0.1, 0.05, 0.1 - P), mat, dt=dt, theta=1.0, T_initial=0.0)
    c = ThermalContact(ha, hb, tags_a=["x1"], tags_b=["x0"], R_c=10.0, temperature=variant)
    return ha, hb, c, ContactHeatSystem([c])


def test_lumped_two_bodies_mean_variant_is_the_exact_recursion():
    """lambda = g (1/C_A + 1/C_B) = 2e-3 1/s; 200 steps of 5 s: (1 - lambda dt)^n to 1e-12."""
    dt, n = 5.0, 200
    ha, hb, c, group = _blocks("mean", dt, 1.0)
    lam = c.total_conductance * (1 / ha.heat_capacity() + 1 / hb.heat_capacity())
    assert lam == pytest.approx(2e-3, rel=1e-12)
    E0 = ha.stored_heat() + hb.stored_heat()
    for _ in range(n):
        group.step()
    d = ha.mean_temperature() - hb.mean_temperature()
    assert d == pytest.approx((1 - lam * dt) ** n, rel=1e-10)
    assert ha.stored_heat() + hb.stored_heat() == pytest.approx(E0, rel=1e-12)
    with pytest.raises(GsiInputError, match=r"temperature = 'mean' is applied explicitly"):
        _blocks("mean", 600.0, 1.0)[3].step()


def test_lumped_two_bodies_local_variant_follows_the_exponential():
    """Conducting blocks (k = 100, Biot g L/(k S) = 1e-4): the local variant with theta = 1
    tracks the backward-Euler recursion (1 + lambda dt)^-n of the lumped ODE to 2.3e-5 of
    Delta T (measured) and so exp(-lambda t) within that recursion's own time error (1.83e-3
    here; measured 1.86e-3); heat conserved to 1e-10 (LU round-off over 200 steps)."""
    dt, n = 5.0, 200
    ha, hb, c, group = _blocks("local", dt, 100.0)
    lam = 2e-3
    E0 = ha.stored_heat() + hb.stored_heat()
    err_exp, err_be = 0.0, 0.0
    for i in range(1, n + 1):
        group.step()
        d = ha.mean_temperature() - hb.mean_temperature()
        err_exp = max(err_exp, abs(d - math.exp(-lam * dt * i)))
        err_be = max(err_be, abs(d - (1 + lam * dt) ** -i))
    bound = max(abs((1 + lam * dt) ** -i - math.exp(-lam * dt * i)) for i in range(n + 1))
    print(f"local variant: max |d - exp| = {err_exp:.3e}, |d - BE| = {err_be:.3e}, "
          f"BE-exp bound {bound:.3e}")
    assert err_be < 2e-4
    assert err_exp < bound + 2e-4
    assert ha.stored_heat() + hb.stored_heat() == pytest.approx(E0, rel=1e-10)


def test_explicit_contact_needs_its_own_limit():
    """theta = 0: the stiff contact (tiny R_c) is refused at the bodies' own explicit step;
    a soft one (R_c = 10) runs and conserves the heat."""
    probe = Heat(bar(0.5, 0.1), MAT, dt=1.0, theta=0.0)
    dt = 0.9 * probe.stable_dt()
    ha, hb, c = pair(0.1, 0.1, dt, theta=0.0, R_c=1e-6)
    with pytest.raises(GsiInputError, match=r"above the explicit stability limit .* of the "
                                            r"bodies and their contact"):
        ContactHeatSystem([c]).step()
    ha, hb, c = pair(0.1, 0.1, dt, theta=0.0, R_c=10.0)
    ha.T.x.array[:] = 1.0
    group = ContactHeatSystem([c])
    for _ in range(50):
        group.step()
    assert ha.stored_heat() + hb.stored_heat() == pytest.approx(1.0 * 0.5 * 0.01 * 1000.0,
                                                                rel=1e-12)
    assert 0.0 < hb.mean_temperature() < ha.mean_temperature() < 1.0


def test_bad_contacts_are_refused():
    ha, hb, _ = pair(0.1, 0.1, 1.0)
    with pytest.raises(GsiInputError, match=r"^thermal_contact.R_c = 0: must be > 0"):
        ThermalContact(ha, hb, tags_a="x1", tags_b="x0", R_c=0)
    with pytest.raises(GsiInputError, match=r"^thermal_contact.tags\[0\] = 'top': not a surface"):
        ThermalContact(ha, hb, tags_a="top", tags_b="x0", R_c=1.0)
    with pytest.raises(GsiInputError, match=r"do not overlap"):
        ThermalContact(ha, hb, tags_a="x0", tags_b="x1", R_c=1.0)
    with pytest.raises(GsiInputError, match=r"must be one of 'local', 'mean'"):
        ThermalContact(ha, hb, tags_a="x1", tags_b="x0", R_c=1.0, temperature="avg")
    other = Heat(bar(0.5, 0.1, 0.5 - P), MAT, dt=2.0, theta=1.0)
    c = ThermalContact(ha, other, tags_a="x1", tags_b="x0", R_c=1.0)
    with pytest.raises(GsiInputError, match=r"same FE step and theta"):
        ContactHeatSystem([c])
