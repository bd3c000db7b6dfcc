"""docs/design.md, "Validation cases", case 8: a bed of particles at rest on a clamped membrane (two-way coupled).

A layer of 36 softwood spheres (r = 10 mm, XDEM Table 3, with rolling resistance) settles
on a clamped P2 rubber plate (radius 0.2 m, 10 mm thick; generalized-alpha,
rho_inf = 0.8, half-critical damping of the lowest mode), coupled by
:class:`gsi.coupling.staggered.StaggeredCoupling` (gsi/studies/bed_on_membrane.py). References:

* at rest the supports carry the bed's weight (1 %; measured 0.002 %);
* the coupled deflection equals a static FE solve under the same nodal loads (1 %;
  measured 0.002 %);
* invariant of the transfer (holds by construction, not a physics check): every coupling
  step the nodal loads the FE holds sum to minus the time-averaged force of the wall on the
  particles (1e-12 relative; measured ~1e-15);
* P1 elements (consistent barycentric loads) balance too (they lock: 13x stiffer);
* quasi-static coupling (static solve per step, under-relaxed 0.03) reaches the same
  state (measured: deflection 0.1 % apart).
"""
import numpy as np
import pytest

from gsi.studies.bed_on_membrane import bed_on_membrane

D = "docs/design.md"  # where the references are written down


@pytest.fixture(scope="module")
def bed():
    return bed_on_membrane(h=0.05, scheme="generalized_alpha", rho_inf=0.8, zeta=0.5, duration=0.5)


def test_bed_is_at_rest(bed):
    # kinetic energy of the bed << its elastic contact energy scale (weight x overlap ~1e-6 J)
    assert bed["kinetic_energy"] < 1e-8


def test_support_reactions_carry_the_weight(bed, record_validation):
    W = bed["weight"]
    R = bed["reaction"]
    record_validation("bed at rest on the membrane: support reaction = weight", reference=W,
                      measured=R[2], tolerance=1e-2, unit="N", source=f'{D}, "Validation cases" 8')
    record_validation("bed at rest on the membrane: interface load = weight", reference=W,
                      measured=-bed["load"][2], tolerance=1e-2, unit="N",
                      source=f'{D}, "Validation cases" 8')
    assert R[2] == pytest.approx(W, rel=1e-2)
    assert np.hypot(R[0], R[1]) < 1e-2 * W
    # the time-averaged interface load of the last step is the weight too
    assert -bed["load"][2] == pytest.approx(W, rel=1e-2)


def test_deflection_matches_static_solve_under_the_same_loads(bed):
    assert bed["u_max"] > 0.0
    assert bed["u_diff_rel"] < 1e-2


def test_nodal_loads_balance_wall_force_invariant_of_the_transfer(bed, record_validation):
    rec = bed["records"]
    loaded = np.abs(rec["wall_force_z"]) > 0
    assert loaded.sum() > 0.9 * len(loaded)
    record_validation("bed on the membrane: nodal loads vs wall force, largest relative misbalance",
                      reference=0.0, measured=float(rec["balance_rel"].max()), tolerance=1e-12,
                      kind="abs", source=f'{D}, "Balance"')
    assert rec["balance_rel"].max() < 1e-12
    # and by components, directly from the record
    for c in "xyz":
        scale = np.abs(rec["wall_force_z"]).max()
        assert np.abs(rec[f"load_{c}"] - rec[f"wall_force_{c}"]).max() < 1e-12 * scale


def test_quasi_static_coupling_reaches_the_same_state(bed):
    qs = bed_on_membrane(h=0.05, scheme="static", relaxation=0.03, duration=0.5)
    assert qs["reaction"][2] == pytest.approx(qs["weight"], rel=1e-2)
    assert qs["u_diff_rel"] < 1e-2
    assert qs["u_max"] == pytest.approx(bed["u_max"], rel=1e-2)
    assert qs["records"]["balance_rel"].max() < 1e-12


def test_p1_membrane_balances_the_weight_too(bed):
    """P1: the barycentric weights are the consistent nodal loads (no midpoint nodes)."""
    p1 = bed_on_membrane(h=0.05, degree=1, duration=0.5)
    assert p1["reaction"][2] == pytest.approx(p1["weight"], rel=1e-2)
    assert p1["u_diff_rel"] < 1e-2
    assert p1["records"]["balance_rel"].max() < 1e-12
    # P1 tetrahedra lock in bending: the same plate deflects (much) less than with P2
    assert 0 < p1["u_max"] < 0.8 * bed["u_max"]
