"""Seed 001 (thesis), eq. II.4: the Biot number Bi = H/(k pi R) of the particle contacts.

The thesis's case 4 (``demos/graded/case4_two_particles.toml``: R = 2 mm, overlap 0.2 mm,
contact radius a = 0.6245 mm, ``radius`` model H = 2 k a = 0.481 W/K for copper) has
Bi = 0.481/(385 pi 0.002) = 0.199 = 2 a/(pi R): not << 1, so
:func:`gsi.case.biot_check.check_biot` warns naming ``dem.heat``. The ``area`` model on the same
contact gives 2 a/(sqrt(pi) R) = 0.352; a light contact (overlap 1 um) stays below 0.1.
"""
import dataclasses
import math
import pathlib
import warnings

import pytest

from gsi.case import load_case
from gsi.case.biot_check import BiotWarning, check_biot
from gsi.post.biot import biot_number
from gsi.run import build_simulation

GRADED = pathlib.Path(__file__).resolve().parents[2] / "demos" / "graded"
R, L = 2.0e-3, 3.8e-3


def _case4(**dem):
    case = load_case(GRADED / "case4_two_particles.toml")
    if dem:
        case.dem = dataclasses.replace(case.dem, **dem)
    sim, _, _ = build_simulation(case, dt=case.time_step())
    return case, sim


def test_case4_biot_is_0_2_and_warns(record_validation):
    case, sim = _case4()
    with pytest.warns(BiotWarning, match=r"dem.heat = 'radius'.*Bi = H/\(k pi R\) = 0.199"):
        rep = check_biot(case, sim)
    a = math.sqrt(R * R - 0.25 * L * L)
    assert rep.n_contacts == 1
    assert rep.a == pytest.approx(a, rel=1e-12)
    assert rep.H == pytest.approx(2 * 385.0 * a, rel=1e-12)
    assert rep.max == pytest.approx(0.481 / (385.0 * math.pi * R), rel=1e-3)
    assert rep.max == pytest.approx(2 * a / (math.pi * R), rel=1e-12)
    record_validation("seed 001 case 4: Biot number H/(k pi R) (radius model)", reference=0.1988,
                      measured=rep.max, tolerance=5e-4, kind="abs",
                      source="the thesis's eq. II.4 with case 4's contact")
    assert rep.max == pytest.approx(0.1988, abs=5e-4)
    # the conductance is the engine's: its explicit-heat stability number dt H / (m c_p)
    C = float(sim.heat_capacity[0])
    assert sim.heat_stability() * C / sim.dt == pytest.approx(rep.H, rel=1e-12)
    # alumina: the same geometry, the same Bi (H and k scale together)
    case.particles = [dataclasses.replace(p, material="alumina") for p in case.particles]
    sim_al, _, _ = build_simulation(case, dt=case.time_step())
    rep_al = check_biot(case, sim_al, warn=False)
    assert rep_al.max == pytest.approx(rep.max, rel=1e-12)
    assert rep_al.H == pytest.approx(2 * 36.0 * a, rel=1e-12)


def test_area_model_biot():
    case, sim = _case4(heat="area")
    with pytest.warns(BiotWarning, match="dem.heat = 'area'"):
        rep = check_biot(case, sim)
    a = math.sqrt(R * R - 0.25 * L * L)
    assert rep.max == pytest.approx(2 * a / (math.sqrt(math.pi) * R), rel=1e-12)
    assert rep.max == pytest.approx(biot_number(rep.H, 385.0, R), rel=1e-15)


def test_light_contact_does_not_warn(tmp_path):
    delta = 1.0e-6
    (tmp_path / "pair.csv").write_text(
        "x,y,z,radius,T\n"
        f"0.0231,0.002,0.01,{R},373.15\n{0.0231 + 2 * R - delta!r},0.002,0.01,{R},273.15\n")
    case = load_case(GRADED / "case4_two_particles.toml")
    case.particles = [dataclasses.replace(p, file=str(tmp_path / "pair.csv"))
                      for p in case.particles]
    sim, _, _ = build_simulation(case, dt=case.time_step())
    with warnings.catch_warnings():
        warnings.simplefilter("error", BiotWarning)
        rep = check_biot(case, sim)
    a = math.sqrt(R * delta - 0.25 * delta * delta)
    assert rep.max == pytest.approx(2 * a / (math.pi * R), rel=1e-6)
    assert rep.max < 0.1


def test_no_heat_no_report():
    case = load_case(GRADED / "case1_free_fall.toml")
    assert case.dem.heat == "none"
    assert check_biot(case, None) is None


def test_gsi_check_and_gsi_run_warn_naming_the_material_and_the_value(capsys, tmp_path):
    """``gsi check`` (which builds the DEM at t = 0) and ``gsi run`` (after the set-up)
    call check_biot: one ``warning:`` line with dem.heat, the material and Bi = 0.199."""
    from gsi.cli import main
    path = GRADED / "case4_two_particles.toml"
    assert main(["check", str(path)]) == 0
    err = capsys.readouterr().err
    warned = [ln for ln in err.splitlines() if ln.startswith("warning: ")]
    assert len(warned) == 1, err
    assert "dem.heat = 'radius'" in warned[0] and "copper" in warned[0]
    assert "Bi = H/(k pi R) = 0.199" in warned[0]
    case = load_case(path)
    from gsi.run import run_case
    with pytest.warns(BiotWarning, match=r"'radius'.*= 0.199 .*copper"):
        run_case(case, out=tmp_path / "run", quick=True, pictures=False, verbose=False)
    # a case whose contacts are light: no warning from either
    light = GRADED / "case5_hot_block.toml"
    assert main(["check", str(light)]) == 0
    assert "warning" not in capsys.readouterr().err
