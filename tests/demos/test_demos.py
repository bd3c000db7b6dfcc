"""The demos: each literate script builds the same case as its TOML twin, and each case
(the three demos and the cases written for no driver) runs in its quick form with the
physics it shows checked against an independent reference."""
import importlib.util
import math
import pathlib

import numpy as np
import pytest

from gsi.case import case_to_table, load_case
from gsi.case.case import validated
from gsi.run import demo_main, run_case

ROOT = pathlib.Path(__file__).resolve().parents[2]
DEMOS = ROOT / "demos"
HAVE_PYVISTA = importlib.util.find_spec("pyvista") is not None


def _module(name):
    spec = importlib.util.spec_from_file_location(f"demo_{name}", DEMOS / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("name", ["pour", "hopper_membrane", "thermal_silo",
                                  "drum_extrapolation", "kiln"])
def test_literate_demo_and_its_toml_twin_are_the_same_case(name):
    mod = _module(name)
    assert mod.result is None                 # importing runs nothing
    a = case_to_table(validated(mod.case))
    b = case_to_table(load_case(DEMOS / f"{name}.toml"))
    assert a == b


def test_pour_quick(tmp_path):
    """The settled bed's weight is carried by the walls (the literate script, in-process)."""
    res = demo_main(_module("pour").case, argv=["--quick", "--out", str(tmp_path)])
    assert res.n_particles == 2000 and res.n_lost == 0
    weight = np.linalg.norm(res.weight)
    # at rest the walls carry the weight: the residual motion of the bed at t = 0.25 s
    assert res.wall_load @ res.weight / weight ** 2 == pytest.approx(1.0, abs=0.02)
    box = res.monitors["box_load"]
    assert -box["Fz_N"][-1] == pytest.approx(weight, rel=0.02)
    # kinetic energy is small compared with the potential energy of the fall (m g * 5 cm)
    assert res.kinetic_energy < 1e-3 * weight * 0.05
    # 2000 beads of r ~ 2 mm (67 cm^3 of glass) in a 6 x 6 cm box at a packing fraction of
    # ~0.6 make a bed 3.1 cm deep; its top lies within a bead diameter or so above that
    solid = 2000 * 4 / 3 * np.pi * 0.002 ** 3
    h_bed = solid / (0.6 * 0.06 * 0.06)
    assert 0.8 * h_bed < res.monitors["bed"]["bed_top_m"][-1] < 1.3 * h_bed + 0.004
    pvd = (tmp_path / "particles" / "particles.pvd").read_text()
    assert pvd.count("<DataSet") == len(list((tmp_path / "particles").glob("particles_*.vtu")))
    assert (tmp_path / "monitors" / "box_load.csv").stat().st_size > 0
    if HAVE_PYVISTA:
        assert (tmp_path / "pour.png").stat().st_size > 0


def test_drum_from_a_mesh_file_turning_at_10_rpm(tmp_path):
    """DEM-only drum (its wall an STL file) at 10 rpm about a horizontal axis: the bed's
    weight rests on the drum, and the wall drags the bed up its rising side, so the bed's
    weight acts off the axis and resists the drive."""
    res = run_case(load_case(DEMOS / "drum.toml"), out=tmp_path, quick=True, pictures=False,
                   verbose=False)
    assert res.n_lost == 0 and res.n_particles == 800
    W = np.linalg.norm(res.weight)
    drive = res.monitors["drive"]
    late = drive["time_s"] >= 0.5          # settled, rolling
    # the drum carries the weight (vertical force of the bed on it, averaged)
    assert -drive["Fz_N"][late].mean() == pytest.approx(W, rel=0.05)
    # omega = +10 rpm about +y: at the bottom the wall moves toward -x and lifts the bed on
    # the -x side. In steady rolling the torque of the bed on the drum about the axis is
    # the torque of its weight, T_y = x_c W with x_c < 0 the centre-of-mass offset: it
    # opposes the drive (omega_y > 0), so the drive does work on the bed
    assert (drive["Ty_Nm"][late] < 0).all()
    x_c = drive["Ty_Nm"][late].mean() / W       # m, centre-of-mass offset (negative: -x)
    assert -0.1 < x_c < -0.005                  # a tilt inside the drum radius (0.1 m)


def test_belt_from_a_user_geo_file(tmp_path):
    """A hopper discharging onto a belt loaded from meshes/belt.geo, clamped by its
    physical tags mapped in TOML: the stream lands, the belt sags between its clamped ends,
    and the transfer balances at every coupling step."""
    res = run_case(load_case(DEMOS / "belt_hopper.toml"), out=tmp_path, quick=True,
                   pictures=False, verbose=False)
    s = res.structures["belt"]
    assert s["balance_max"] < 1e-12
    on = res.monitors["on_belt"]
    mass0 = 200 * 400.0 * 4 / 3 * math.pi * 0.01 ** 3
    assert on["mass_kg"][-1] + on["lost"][-1] * mass0 / 200 > 0.9 * mass0
    rec = np.genfromtxt(tmp_path / "belt_coupling.csv", delimiter=",", names=True)
    assert rec["min_uz"].min() < -1e-3                 # millimetres of sag under the heap
    assert -rec["load_z"].min() > 0.5 * mass0 * 9.81    # impacts load it


def test_two_coupled_structures(tmp_path):
    """An FE steel hopper (quasi-static, n_sub 17) and the FE membrane under it (dynamic,
    n_sub 34) on one DEM. Before the gate opens the settled bed's weight is shared by the
    hopper wall and the gate (a wall-load study: neither alone carries it); afterwards the
    membrane takes the discharge. Each structure keeps its transfer invariant."""
    res = run_case(load_case(DEMOS / "two_structures.toml"), out=tmp_path, quick=True,
                   pictures=False, verbose=False)
    hop, mem = res.structures["hopper"], res.structures["membrane"]
    assert (hop["n_sub"], mem["n_sub"]) == (17, 34)
    assert hop["intervals"] == 2 * mem["intervals"]
    assert max(hop["balance_max"], mem["balance_max"]) < 1e-12
    W = 300 * 400.0 * 4 / 3 * math.pi * 0.01 ** 3 * 9.81
    h, g = res.monitors["hopper"], res.monitors["gate"]
    assert np.array_equal(h["time_s"], g["time_s"])
    rest = (h["time_s"] > 0.6) & (h["time_s"] < 0.8)        # settled, gate still closed
    share = -(h["load_z_N"][rest] + g["Fz_N"][rest]) / W
    assert share.mean() == pytest.approx(1.0, abs=0.03)
    assert -h["load_z_N"][rest].mean() > 0.1 * W and -g["Fz_N"][rest].mean() > 0.1 * W
    assert h["max_von_mises_Pa"][rest].min() > 0
    dis = res.monitors["discharged"]
    assert dis["mass_kg"][-1] + dis["lost"][-1] * W / 9.81 / 300 > 0.95 * W / 9.81
    assert -res.monitors["membrane"]["load_z_N"][-1] > 0.5 * W


def test_kiln_quick(tmp_path):
    """The heated kiln (demos/kiln.py --quick): the bed heats toward the shell's 393.15 K
    over the extrapolated half hour, the books of bed, shell and jacket balance to
    round-off, and the live run's ParaView files and the hours picture are written."""
    res = demo_main(_module("kiln").case, argv=["--quick", "--out", str(tmp_path)])
    s = res.summary
    assert res.n_particles == 300 and res.n_lost == 0
    assert s["extrap_hours"] == pytest.approx(0.5)
    assert s["energy_balance_rel"] < 1e-12
    # heating toward the jacket temperature, not past it; the half hour is ~2.5 time
    # constants of the bed (it gains ~80 K of the ~90 K between it and the shell)
    assert s["bed_T_t1"] < 310.0 < 370.0 < s["bed_T_end"] < 393.15
    assert 393.15 - 1.0 < s["wall_T_end"] < 393.15
    # the jacket supplies what the bed takes (the shell's own heat content barely moves)
    assert s["wall_heat_flow_W"] == pytest.approx(s["boundary_heat_flow_W"], rel=0.02)
    assert s["eps_rel_max"] < 0.6 and s["energy_err_max"] < 0.05
    csv = np.genfromtxt(tmp_path / "extrapolation.csv", delimiter=",", names=True)
    assert len(csv) == 3601 and (~np.isnan(csv["T_mean_dem"])).sum() == 4
    assert (tmp_path / "shell.xdmf").stat().st_size > 0
    assert (tmp_path / "particles" / "particles.pvd").stat().st_size > 0
    assert (tmp_path / "extrapolation_hours.png").stat().st_size > 0


@pytest.mark.parametrize("name", ["plate_on_block", "thermal_silo_radiation"])
def test_the_other_shipped_cases_run_quick_and_carry_their_bed(name, tmp_path):
    """Every TOML under demos/ runs in --quick form in the tests (the others above, in
    tests/validation and tests/reliability): these two come to rest on their walls and
    structures, which carry the particles' weight (2 %: what the quick beds still move)."""
    res = run_case(load_case(DEMOS / f"{name}.toml"), out=tmp_path, quick=True,
                   pictures=False, verbose=False)
    assert res.n_lost == 0 and res.n_particles > 0
    g = np.linalg.norm(res.weight)
    assert float(res.wall_load @ res.weight / g ** 2) == pytest.approx(1.0, abs=0.02)


def test_thermal_silo_with_frictional_heating_books_the_friction(tmp_path):
    """demos/thermal_silo_friction.toml, its first 0.04 s (the bed poured; it reaches the wall at 0.02 s):
    the wall's half of the frictional heat reaches the FE through the nodal loads
    (balance_error = Q_structure - Q_particles - Q_friction stays at round-off: an
    invariant of the transfer), friction made heat in the contacts, and the energy
    monitor is written."""
    import tomllib
    from gsi.case import case_from_table
    t = tomllib.loads((DEMOS / "thermal_silo_friction.toml").read_text())
    t["quick"]["run"]["duration"] = 0.04
    t["quick"].setdefault("output", {})["interval"] = 0.02
    run_case(case_from_table(t, base_dir=DEMOS), out=tmp_path, quick=True, pictures=False,
             verbose=False)
    h = np.genfromtxt(tmp_path / "bin_energy.csv", delimiter=",", names=True)
    e = np.genfromtxt(tmp_path / "monitors" / "energy.csv", delimiter=",", names=True)
    assert h["Q_friction"].sum() > 0.0
    scale = np.abs(h["Q_structure"]).max()
    assert np.abs(h["balance_error"]).max() <= 1e-9 * scale
    assert e["heat_generated_J"][-1] >= h["Q_friction"].sum() > 0.0
