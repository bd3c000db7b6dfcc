"""XDMF + CSV output of a thermo-elastic run: columns carry the right numbers."""
import csv

import numpy as np
import pytest

from gsi import meshes
from gsi.fem.materials import MATERIALS
from gsi.fem.output import FemOutput
from gsi.fem.surface import ContactSurface
from gsi.fem.thermoelastic import ThermoElastic


def test_csv_and_xdmf_series(tmp_path):
    sm = meshes.build("silo", radius=0.3, height=0.5, thickness=0.01, h=0.08)
    steel = MATERIALS["steel"]
    te = ThermoElastic(sm, steel, dt=2.0, scheme="static", T_ref=20.0,
                       elasticity_options=dict(gravity=(0.0, 0.0, -9.81)))
    te.elasticity.clamp("support")
    te.heat.set_flux("contact", 500.0)
    te.heat.set_convection("outer", 10.0, 20.0)
    area = ContactSurface(heat=te.heat).area()
    rows = []
    with FemOutput(tmp_path, elasticity=te.elasticity, heat=te.heat) as out:
        for _ in range(2):
            te.step()
            rows.append(out.write(te.t))
    with open(tmp_path / "structure.csv") as fh:
        table = list(csv.DictReader(fh))
    assert len(table) == 2
    assert float(table[-1]["t"]) == pytest.approx(4.0)
    # statics under gravity + thermal strain: the base carries the weight (thermal
    # stress is self-equilibrated)
    volume = rows[-1]["reaction_z"] / (steel.rho * 9.81)
    vol_exact = np.pi * (0.31**2 - 0.3**2) * 0.5 + np.pi * 0.31**2 * 0.01
    assert volume == pytest.approx(vol_exact, rel=2e-2)
    assert float(table[-1]["reaction_z"]) == pytest.approx(rows[-1]["reaction_z"], rel=1e-9)
    assert float(table[-1]["heat_flow_contact"]) == pytest.approx(500.0 * area, rel=1e-9)
    assert float(table[-1]["T_max"]) > 20.0 and float(table[-1]["max_deflection"]) > 0
    assert float(table[-1]["max_von_mises"]) > 0
    xdmf = (tmp_path / "structure.xdmf").read_text()
    for name in ("displacement", "von_mises", "temperature"):
        assert xdmf.count(f'Attribute Name="{name}"') == 2
    assert (tmp_path / "structure.h5").stat().st_size > 0
