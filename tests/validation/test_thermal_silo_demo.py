"""The thermal silo demo in its quick form, checked for physics (docs/design.md, "Validation cases", case 9 at scale).

450 clinker particles at 800 K settle in a steel bin cooled outside (demos/thermal_silo.toml,
``--quick``: 200 coupling steps, 60 s of heating with the documented time scale 200).
Checked from the run's own records (``bin_energy.csv``): the heat the particles lose to the
wall equals the heat the wall receives every step (an invariant of the transfer); each
side's energy books balance separately (particles: their stored heat falls by exactly what
they gave the wall, pair conduction conserving; structure: its stored heat rises by what it
received minus the convective loss); the wall warms measurably; the bed at rest puts its
weight on the wall; and the outputs exist.
"""
import importlib.util
import pathlib

import numpy as np
import pytest

from gsi.case import load_case
from gsi.run import run_case

ROOT = pathlib.Path(__file__).resolve().parents[2]
CASE = ROOT / "demos" / "thermal_silo.toml"


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    out = tmp_path_factory.mktemp("thermal_silo")
    r = run_case(load_case(CASE), out=out, quick=True, verbose=False)
    h = np.genfromtxt(out / "bin_energy.csv", delimiter=",", names=True)
    return r, out, h


def test_heat_balance_every_step_is_an_invariant_of_the_transfer(result):
    r, _, h = result
    assert np.abs(h["balance_error"]).max() <= 1e-12 * np.abs(h["Q_particles"]).max()
    s = r.structures["bin"]
    assert s["Q_structure"] == pytest.approx(s["Q_particles"], rel=1e-12)


def test_energy_books_of_particles_and_wall(result):
    r, _, h = result
    E_p0 = h["E_particles"][0] + h["Q_particles"][0]   # before the first step
    E_s0 = h["E_structure"][0] - h["Q_structure"][0] + h["Q_boundary_loss"][0]
    assert E_s0 == pytest.approx(0.0, abs=1e-9)         # wall starts at T_ref
    assert h["E_particles"][-1] - E_p0 == pytest.approx(-h["Q_particles"].sum(), rel=1e-10)
    assert h["E_structure"][-1] == pytest.approx(
        h["Q_structure"].sum() - h["Q_boundary_loss"].sum(), rel=1e-10)
    assert np.abs(h["drift"]).max() <= 1e-10 * h["Q_particles"].sum()


def test_wall_warms_and_carries_the_bed(result):
    r, _, h = result
    assert r.n_lost == 0
    assert h["T_wall_max"][-1] > 293.15 + 10.0
    T = r.monitors["clinker_T"]
    assert T["T_mean_K"][-1] < 800.0 and T["T_max_K"][-1] <= 800.0 + 1e-9
    assert h["heat_flow"][-1] > 10.0                     # W into the wall at the end
    assert h["Q_boundary_loss"].sum() > 0                # the cooled outer wall loses heat
    assert -r.structures["bin"]["load_z"] == pytest.approx(np.linalg.norm(r.weight), rel=0.03)
    # a restrained heated steel floor: a thermal stress of order E alpha dT (~100 MPa)
    assert r.structures["bin"]["max_von_mises"] > 1e7


def test_outputs_written(result):
    r, out, h = result
    for name in ("bin.xdmf", "bin.h5", "particles/particles.pvd", "bin_energy.csv",
                 "monitors/clinker_T.csv", "monitors.png"):
        assert (out / name).is_file(), name
    if importlib.util.find_spec("pyvista") is not None:
        assert len(list((out / "pictures").glob("frame_*.png"))) >= 2
        assert (out / "thermal_silo.gif").is_file()
    rows = (out / "bin_energy.csv").read_text().splitlines()
    assert len(rows) == 1 + r.structures["bin"]["intervals"]
