"""Seed 000's thermo-mechanical wall-load study (demos/thermal_silo.toml) with surface
radiation of the bin's outer wall: ``[[structures.thermal.radiation]] tag = "outer",
emissivity = 0.8, T_ambient = 293.15`` beside the convection h = 25 W/(m^2 K).

The quick form (60 s of heating with the heat-capacity scale 200) is run with and
without radiation. Checked: the energy books still close (the radiated heat is in
Q_boundary_loss), radiation raises the outer loss, and the heat the bed gives the wall
(the DEM-FE conduction) is nearly unchanged while the wall stays much colder than the
clinker. The radiation here is the FE surface's only; the bed's own radiation (seed 000
eqs. 22-23, particle-particle and particle-wall) is demos/thermal_silo_radiation.toml,
studied in tests/validation/test_radiation_dem.py and benchmarks/silo_radiation_share.py.

Measured: outer loss 0.5829 J (convection) -> 0.6953 J with radiation (+19.3 %; scaled
energies, physical / 200); bed -> wall heat 26.22 -> 26.28 J (+0.23 %); heat flow into
the wall at the end 128 -> 127 W; wall mean 307.42 -> 307.39 K. At these wall
temperatures (~310 K) radiation adds h_rad = 4 eps sigma T^3 ~ 5 W/(m^2 K) to h = 25.
"""
import pathlib
import tomllib

import numpy as np
import pytest

from gsi.case import case_from_table
from gsi.run import run_case

ROOT = pathlib.Path(__file__).resolve().parents[2]
CASE = ROOT / "demos" / "thermal_silo.toml"


def _run(tmp, radiation):
    t = tomllib.loads(CASE.read_text())
    if radiation:
        t["structures"][0]["thermal"]["radiation"] = [
            dict(tag="outer", emissivity=0.8, T_ambient=293.15)]
    out = tmp / ("rad" if radiation else "plain")
    run_case(case_from_table(t, base_dir=CASE.parent), out=out, quick=True, verbose=False,
             pictures=False)
    return np.genfromtxt(out / "bin_energy.csv", delimiter=",", names=True)


@pytest.mark.slow
def test_radiation_changes_the_outer_loss_not_the_bed_to_wall_heat(tmp_path):
    plain, rad = _run(tmp_path, False), _run(tmp_path, True)
    for h in (plain, rad):
        assert np.abs(h["drift"]).max() <= 1e-10 * h["Q_particles"].sum()
    loss_p, loss_r = plain["Q_boundary_loss"].sum(), rad["Q_boundary_loss"].sum()
    in_p, in_r = plain["Q_structure"].sum(), rad["Q_structure"].sum()
    print(f"outer loss: convection {loss_p:.4g} J, convection + radiation {loss_r:.4g} J "
          f"(+{100 * (loss_r / loss_p - 1):.1f} %); bed -> wall heat {in_p:.4g} -> {in_r:.4g} J "
          f"({100 * (in_r / in_p - 1):+.3f} %); final wall flow {plain['heat_flow'][-1]:.4g} -> "
          f"{rad['heat_flow'][-1]:.4g} W; wall T_mean {plain['T_wall_mean'][-1]:.2f} -> "
          f"{rad['T_wall_mean'][-1]:.2f} K")
    assert loss_r > 1.1 * loss_p
    assert in_r == pytest.approx(in_p, rel=0.02)
    assert rad["T_wall_mean"][-1] < plain["T_wall_mean"][-1]
