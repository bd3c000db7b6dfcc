"""Seed 002's FE-FE contact heat on the case model: demos/plate_on_block.toml (``--quick``).

Hot particles heat a steel plate; the plate heats a concrete block through a
``[[thermal_contacts]]`` resistance R_c = 1e-3 m^2 K/W; the block's foot is held at
293.15 K. The contact model is validated against analytic references in
tests/validation/test_fdem_contact_heat.py; here the case-level books are checked from
the run's own records: the heat the plate gives equals the heat the block takes every
step (an invariant of the contact), each structure's energy closes with its particle,
contact and boundary heat, the contact area is the plates' 0.1 x 0.1 m overlap, and the
heat crosses from the hotter body to the colder one.
"""
import pathlib
import tomllib

import numpy as np
import pytest

from gsi.case import case_from_table, load_case
from gsi.errors import GsiInputError
from gsi.run import Runner

ROOT = pathlib.Path(__file__).resolve().parents[2]
CASE = ROOT / "demos" / "plate_on_block.toml"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("plate_on_block")
    runner = Runner(load_case(CASE), out=out, quick=True, verbose=False)
    res = runner.run()
    books = {n: np.genfromtxt(out / f"{n}_energy.csv", delimiter=",", names=True)
             for n in ("plate", "block")}
    return runner, res, books


def test_contact_exchange_is_equal_and_opposite_every_step(run):
    _, res, h = run
    q_plate, q_block = h["plate"]["Q_contact"], h["block"]["Q_contact"]
    assert np.all(q_block > 0)                                     # plate -> block
    assert np.abs(q_plate + q_block).max() <= 1e-12 * np.abs(q_block).max()
    assert res.structures["block"]["Q_contact"] == pytest.approx(
        -res.structures["plate"]["Q_contact"], rel=1e-12)


def test_energy_books_of_each_structure(run):
    _, res, h = run
    p, b = h["plate"], h["block"]
    # the plate: particles' heat in, contact heat out (the particles touch only the plate)
    assert np.abs(p["drift"]).max() <= 1e-10 * p["Q_particles"].sum()
    assert p["E_structure"][-1] == pytest.approx(p["Q_structure"].sum() + p["Q_contact"].sum(),
                                                 rel=1e-10)
    # the block: contact heat in, the fixed foot's reaction out
    assert b["E_structure"][-1] == pytest.approx(
        b["Q_contact"].sum() - b["Q_boundary_loss"].sum(), rel=1e-10)
    assert res.n_lost == 0


def test_the_contact_of_the_run(run):
    runner, _, h = run
    (group,) = runner.contact_groups
    (contact,) = group.contacts
    assert contact.area == pytest.approx(0.01, rel=1e-12)         # 0.1 x 0.1 m overlap
    assert contact.total_conductance == pytest.approx(0.01 / 1e-3, rel=1e-12)
    # theta = 1: the last step's contact heat is the flow at the end-of-step temperatures
    assert contact.heat_flow() * runner.structure("block").dt == pytest.approx(
        h["block"]["Q_contact"][-1], rel=1e-10)
    plate, block = runner.structure("plate").heat, runner.structure("block").heat
    assert plate.mean_temperature() > block.mean_temperature() > 293.15


def _table():
    return tomllib.loads(CASE.read_text())


@pytest.mark.parametrize("edit,message", [
    (lambda t: t["thermal_contacts"][0].update(structures=["plate", "slab"]),
     r"^thermal_contacts\[0\].structures = \['plate', 'slab'\]: 'slab' is not a "
     r"\[\[structures\]\] name"),
    (lambda t: t["thermal_contacts"][0].update(structures=["plate", "plate"]),
     r"must name two different structures"),
    (lambda t: t["thermal_contacts"][0].update(tags=["z0"]),
     r"^thermal_contacts\[0\].tags = \['z0'\]: must name two"),
    (lambda t: t["thermal_contacts"][0].update(R_c=-1.0),
     r"^thermal_contacts\[0\].R_c = -1.0: must be > 0 \(m\^2 K/W\)"),
])
def test_bad_thermal_contacts_are_named(edit, message):
    t = _table()
    edit(t)
    with pytest.raises(GsiInputError, match=message):
        case_from_table(t, base_dir=CASE.parent).check()


def test_a_mechanical_structure_cannot_take_a_heat_contact():
    t = _table()
    t["structures"][1]["contact"]["mode"] = "mechanical"
    t["structures"][1]["supports"] = ["z0"]
    del t["structures"][1]["thermal"]
    with pytest.raises(GsiInputError, match=r"'block' has contact.mode = 'mechanical'"):
        case_from_table(t, base_dir=CASE.parent).check()


def test_different_fe_steps_are_refused(tmp_path):
    t = _table()
    t["structures"][1]["contact"]["n_sub"] = 50
    runner = Runner(case_from_table(t, base_dir=CASE.parent), out=tmp_path, quick=True,
                    verbose=False)
    with pytest.raises(GsiInputError, match=r"same FE step and theta.*same contact.n_sub"):
        runner.setup()
