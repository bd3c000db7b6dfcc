"""begin / DEM steps / finish is the coupling step, bit for bit (gsi.coupling).

A runner drives each coupled structure by ``begin()``, n_sub DEM steps in any pieces,
``finish()``. Hot particles fall on a thermo-mechanical plate (contact mode "both", P2,
heat-capacity scale 10) built by Structure.build; one run calls ``step()``, the other
``begin()``, ``sim.step(7)``, ``sim.step(13)``, ``finish()``: every record, the FE fields
and the particles are identical. Also the per-interval invariants of the transfer: nodal
loads = minus the wall force, heat into the structure = heat out of the particles.
"""
import dataclasses

import numpy as np
import pytest
from mpi4py import MPI

from gsi.case.structure import Structure
from gsi.config.schema import load
from gsi.coupling.thermal import scale_heat_capacity
from gsi.dem import Material, Simulation

L, LZ, R = 0.03, 0.003, 2.0e-3
DT, N_SUB, N_INTERVALS = 2.0e-5, 20, 40
TABLE = dict(name="plate", mesh="box", geometry=dict(length_x=L, length_y=L, length_z=LZ,
                                                      n=[6, 6, 1]),
             material="steel", degree=2, scheme="static", supports=["z0"],
             thermal=dict(T_ref=300.0, convection=[dict(tag="z0", h=200.0, T_ambient=300.0)]),
             contact=dict(tags=["z1"], mode="both", n_sub=N_SUB))


def _run(split: bool):
    st = load(Structure, TABLE, "structures[0]")
    cs = st.build(comm=MPI.COMM_WORLD, dt_dem=DT, heat_scale=10.0)
    ore = {"ore": Material(E=5e7, nu=0.25, rho=3000.0, e=0.3, mu=0.5, k=2.0, cp=100.0)}
    wall_name, wall = st.dem_wall_material(ore)
    sim = Simulation({**scale_heat_capacity(ore, 10.0), wall_name: wall}, heat="area",
                     gravity=(0, 0, -9.81), dt=DT, skin=5e-4,
                     domain=((-0.01, -0.01, -0.01), (L + 0.01, L + 0.01, 0.05)))
    g = np.linspace(0.25 * L, 0.75 * L, 3)
    x = np.array([(a, b, LZ + 1.1 * R + 0.2 * R * k) for k, (a, b) in
                  enumerate((a, b) for a in g for b in g)])
    sim.add_particles(x, R, material="ore", T=600.0)
    cs.attach(sim)
    recs = []
    for _ in range(N_INTERVALS):
        if split:
            cs.begin()
            sim.step(7)
            sim.step(N_SUB - 7)
            recs.append(cs.finish())
        else:
            recs.append(cs.step(sim))
    return cs, sim, recs


def _fields(rec):
    d = dataclasses.asdict(rec)
    return {k: v for k, v in d.items() if not k.startswith("wall_")}   # not the wall clock


@pytest.fixture(scope="module")
def runs():
    return _run(False), _run(True)


def test_split_interval_equals_step_bitwise(runs):
    (a, sim_a, ra), (b, sim_b, rb) = runs
    for x, y in zip(ra, rb):
        assert _fields(x.mechanical) == _fields(y.mechanical)
        assert _fields(x.thermal) == _fields(y.thermal)
    assert np.array_equal(a.elasticity.u.x.array, b.elasticity.u.x.array)
    assert np.array_equal(a.heat.T.x.array, b.heat.T.x.array)
    assert np.array_equal(sim_a.x, sim_b.x) and np.array_equal(sim_a.T, sim_b.T)
    assert np.array_equal(a.wall.vertices, b.wall.vertices)
    # something happened: contacts, heating, deflection
    h = a.thermal.history()
    assert h["Q_particles"].sum() > 0 and a.max_displacement() > 0


def test_transfer_invariants_hold_every_interval(runs):
    (a, _, _), _ = runs
    m, h = a.mechanics.history(), a.thermal.history()
    assert np.count_nonzero(m["wall_force_z"]) > N_INTERVALS // 2
    assert m["balance_rel"].max() <= 1e-12
    assert np.abs(h["balance_error"]).max() <= 1e-12 * np.abs(h["Q_particles"]).max()
    # one wall for both couplings, on the deformed FE surface, at the FE temperature
    assert a.mechanics.wall is a.thermal.wall is a.wall
    assert np.abs(a.wall.vertices - a.interface.positions()).max() <= 1e-15
    assert np.array_equal(a.thermal.wall_temperature(), a.interface.wall_temperature())


def test_finish_after_the_wrong_number_of_dem_steps_is_refused(runs):
    (a, sim, _), _ = runs
    a.begin()
    sim.step(N_SUB - 1)
    with pytest.raises(RuntimeError, match=r"advanced 19 steps .* n_sub = 20"):
        a.finish()


def test_thermal_only_contact_split_equals_step_and_keeps_the_heat_balance(tmp_path):
    """mode = "thermal": heat only, the wall stays at its reference position; the same
    split/step identity and the heat invariant; the structure's files are written."""
    table = dict(TABLE, name="hot", scheme="static",
                 contact=dict(tags=["z1"], mode="thermal", n_sub=N_SUB))
    out = []
    for split in (False, True):
        st = load(Structure, table, "structures[0]")
        cs = st.build(comm=MPI.COMM_WORLD, dt_dem=DT)
        assert cs.elasticity is None and cs.mechanics is None
        ore = {"ore": Material(E=5e7, nu=0.25, rho=3000.0, k=2.0, cp=100.0)}
        name, wall = st.dem_wall_material(ore)
        sim = Simulation({**ore, name: wall}, heat="area", gravity=(0, 0, 0), dt=DT,
                         skin=5e-4, domain=((-0.01, -0.01, -0.01), (L + 0.01, L + 0.01, 0.05)))
        sim.fix(sim.add_particles([[0.5 * L, 0.5 * L, LZ + R - 4e-5]], R, material="ore",
                                  T=600.0))
        cs.attach(sim)
        if split:
            cs.open_output(tmp_path)
        for _ in range(10):
            if split:
                cs.begin()
                sim.step(N_SUB)
                rec = cs.finish()
            else:
                rec = cs.step(sim)
            assert rec.mechanical is None
        out.append((cs, sim))
    (a, sim_a), (b, sim_b) = out
    assert [_fields(r) for r in a.thermal.records] == [_fields(r) for r in b.thermal.records]
    assert np.array_equal(a.heat.T.x.array, b.heat.T.x.array)
    h = b.thermal.history()
    assert h["Q_particles"].sum() > 0
    assert np.abs(h["balance_error"]).max() <= 1e-12 * np.abs(h["Q_particles"]).max()
    assert np.array_equal(b.wall.vertices, b.interface.x0)        # the wall does not move
    row = b.write_output(b.t)
    b.close()
    assert row["T_max"] > 300.0
    files = b.output_files()
    assert [f.name for f in files] == ["hot.xdmf", "hot.csv", "hot_energy.csv"]
    assert all(f.is_file() for f in files)
    lines = (tmp_path / "hot_energy.csv").read_text().splitlines()
    assert len(lines) == 11 and lines[0].startswith("step,t,t_thermal,Q_particles")
    s = b.summary()
    assert s["intervals"] == 10 and s["Q_particles"] == pytest.approx(h["Q_particles"].sum())
    assert s["T_mean"] > 300.0 and np.isnan(s["max_displacement"])
