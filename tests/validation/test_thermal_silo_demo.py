"""The thermal silo demo in its quick form, checked for physics (DESIGN.md case 9 at scale).

450 clinker particles at 800 K settle in a steel bin cooled outside (demos/thermal_silo.toml,
``--quick``: 200 coupling steps, 60 s of heating with the documented time scale 200).
Checked from the run's own records: the heat the particles lose to the wall equals the heat
the wall receives every step; each side's energy books balance separately (particles:
their stored heat falls by exactly what they gave the wall, pair conduction conserving;
structure: its stored heat rises by what it received minus the convective loss); the wall
warms measurably; the bed at rest puts its weight on the wall; and the outputs exist.
"""
import importlib.util
import pathlib

import numpy as np
import pytest

from gsi.config.case import load_case
from gsi.drivers import run_case

ROOT = pathlib.Path(__file__).resolve().parents[2]
CASE = ROOT / "demos" / "thermal_silo.toml"


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    out = tmp_path_factory.mktemp("thermal_silo")
    return run_case(load_case(CASE), out=out, quick=True), out


def test_heat_balance_every_step(result):
    r, _ = result
    h = r.history
    assert np.abs(h["balance_error"]).max() <= 1e-12 * np.abs(h["Q_particles"]).max()
    assert r.Q_structure == pytest.approx(r.Q_particles, rel=1e-12)


def test_energy_books_of_particles_and_wall(result):
    r, _ = result
    h = r.history
    E_p0 = h["E_particles"][0] + h["Q_particles"][0]   # before the first step
    E_s0 = h["E_structure"][0] - h["Q_structure"][0] + h["Q_boundary_loss"][0]
    assert E_s0 == pytest.approx(0.0, abs=1e-9)         # wall starts at T_ref
    assert h["E_particles"][-1] - E_p0 == pytest.approx(-h["Q_particles"].sum(), rel=1e-10)
    assert h["E_structure"][-1] == pytest.approx(
        h["Q_structure"].sum() - h["Q_boundary_loss"].sum(), rel=1e-10)
    assert r.drift_rel <= 1e-10


def test_wall_warms_and_carries_the_bed(result):
    r, _ = result
    assert r.n_lost == 0
    assert r.T_wall_max > r.T_wall_initial + 10.0
    assert r.T_particles_mean < 800.0
    assert r.heat_flow > 10.0                            # W into the wall at the end
    assert r.Q_convection > 0                            # the cooled outer wall loses heat
    assert r.wall_load_z == pytest.approx(r.weight, rel=0.03)
    # the restrained, heated floor: thermal stress dominates the bed's load stress
    assert r.max_von_mises_thermal > 10 * r.max_von_mises_mechanical > 0


def test_outputs_written(result):
    r, out = result
    for name in ("structure.xdmf", "structure.h5", "particles.pvd", "energy.csv",
                 "stress.csv", "history.png"):
        assert (out / name).is_file(), name
    if importlib.util.find_spec("pyvista") is not None:
        assert len(list(out.glob("silo_*.png"))) >= 2 and (out / "silo.gif").is_file()
    rows = (out / "energy.csv").read_text().splitlines()
    assert len(rows) == 1 + len(r.history["t"])
