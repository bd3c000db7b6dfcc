"""Mesh refinement of the coupled membrane: the bed-on-membrane case (docs/design.md, "Validation cases", case 8,
gsi/studies/bed_on_membrane.py) on two P2 meshes, h = 25 mm and h = 18 mm (9.6k and 17.5k
dofs). The total interface load (= the bed's weight at rest) changes by < 1 % and the
maximum deflection by < 5 % (measured 0.02 % and 2.9 %; the sequence h = 50, 35, 25,
18 mm gives 139.4, 153.8, 163.2, 167.9 um: changes 10.4, 6.1, 2.9 %, converging).
"""
import pytest

from gsi.studies.bed_on_membrane import bed_on_membrane


def test_interface_load_and_deflection_converge_under_refinement():
    coarse = bed_on_membrane(h=0.025, duration=0.4)
    fine = bed_on_membrane(h=0.018, duration=0.4)
    assert fine["n_dofs"] > 1.5 * coarse["n_dofs"]
    assert fine["load"][2] == pytest.approx(coarse["load"][2], rel=1e-2)
    assert fine["load"][2] == pytest.approx(-fine["weight"], rel=1e-2)
    assert fine["u_max"] == pytest.approx(coarse["u_max"], rel=0.05)
    assert fine["u_max"] > coarse["u_max"]  # P2 plates converge from the stiff side
