"""Long-time heat extrapolation (Haydar, Martin & Bonnefoy 2023, "seed 003") in the
rotating drum of gsi.studies.drum, against gsi's own full DEM of the same drum.

Default suite: demos/drum_extrapolation.toml in its quick form, run by ``gsi run``'s
runner -- 640 particles in R = 0.06 m at the reference Froude number 0.048 (cascading), a
quarter turn as the period (the seed extrapolates by quarter, half and full turns, its
Figs. 13-15), six periods extrapolated and run as full DEM, sampling n = 10 with
Delta t_c^max = 0.01 s.  Checked:

- the contact log holds the DEM's conduction: replayed through the identity (no
  pairing) from the temperatures at t0, it gives the DEM's temperatures at t1;
- the DEM (adiabatic wall) and the replay conserve sum m c_p T to 1e-12;
- the mean temperatures of the initially hot and cold halves (the seed's Fig. 7):
  extrapolated against full DEM within 2 % of their gap at every t_n;
- eq. 10 (the heat moved in each period) within 10 %, and eq. 9 on 200 Voronoi cells
  within 5 K on average over the periods.  These two are bounds for this small drum, not
  the seed's targets (its Table 5: eps_rel <= 3.1 %, eps_abs <= 0.25 K with 400
  particles per cell; eq. 10 <= 5 %): with 640 particles a cell holds 3 particles and
  compares single particles' temperatures.  Measured here (2026-12-03): eq. 10 at most
  6.4 %, eq. 9 2.9-4.5 K; with the pairing inverted, 42 % and up to 12.7 K; with no
  pairing, 67 % and 11.9 K.  Eq. 9 is checked against its sampling level too (the error
  of other particles with the same temperatures in each cell): within 2 times it
  (measured 0.97-1.46 times, 1 and 2 threads).  The seed's targets are checked at the CI
  size (5,000 particles, full turns) in the slow test.
"""
import pathlib

import numpy as np
import pytest

from gsi.case import load_case
from gsi.dem.contact_log import ContactLog
from gsi.studies.drum import drum_geometry, prepare
from gsi.extrapolation import Replay, compare_with_dem, period_errors, voronoi_seeds
from gsi.run import run_case

ROOT = pathlib.Path(__file__).resolve().parents[2]
CASE = ROOT / "demos" / "drum_extrapolation.toml"


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("drum_extrapolation")
    r = run_case(load_case(CASE), out=out, quick=True, pictures=False, verbose=False)
    csv = np.genfromtxt(out / "extrapolation.csv", delimiter=",", names=True)
    return r, out, csv, ContactLog.load(out / "contact_log.npz")


def test_the_quick_drum_is_the_family_at_the_seed_froude_number(quick_run):
    r, _, csv, log = quick_run
    g = drum_geometry(640)
    assert g.regime == "cascading" and g.froude == pytest.approx(0.0483, abs=2e-4)
    assert drum_geometry(80_000).period == pytest.approx(5.0)
    assert r.n_particles == 640 and r.n_lost == 0
    assert log.period == pytest.approx(g.steps_per_turn // 4 * 1e-4)
    assert len(csv) == 7 and (log.every, log.split) == (10, 100)


def test_logged_period_replays_the_dems_conduction(quick_run):
    log = quick_run[3]
    T = Replay(log, sigma=np.arange(log.n_particles)).run(1, T=log.T0)["T"][1]
    dT = np.abs(log.T1 - log.T0)
    moved = (dT.sum() - np.abs(T - log.T0).sum()) / dT.sum()     # eq. 10 on the period
    assert abs(moved) <= 3e-3
    err = np.abs(T - log.T1)
    assert err.mean() <= 1e-2 * dT.mean() and err.max() <= 5e-2 * dT.max()


def test_heat_is_conserved_by_the_dem_and_the_replay(quick_run):
    _, _, csv, log = quick_run
    assert csv["energy_drift"].max() <= 1e-12
    E0 = log.heat_capacity @ log.T0
    assert abs(log.heat_capacity @ log.T1 - E0) <= 1e-12 * abs(E0)
    Tm = csv["T_mean_dem"]
    assert np.abs(Tm - Tm[0]).max() <= 1e-12 * abs(Tm[0])
    np.testing.assert_allclose(csv["T_mean_extra"], Tm, rtol=1e-12)


def test_hot_and_cold_means_follow_the_full_dem(quick_run):
    csv = quick_run[2]
    gap_dem = csv["T_hot_dem"] - csv["T_cold_dem"]
    gap_ext = csv["T_hot_extra"] - csv["T_cold_extra"]
    assert gap_dem[-1] < 0.7 * gap_dem[0]                       # the halves do mix
    assert np.abs(gap_ext - gap_dem).max() <= 0.02 * gap_dem.min()


def test_seed_error_measures_on_the_small_drum(quick_run):
    csv = quick_run[2]
    assert np.abs(csv["energy_error"][1:]).max() <= 0.10
    assert np.mean(csv["eps_abs"][1:]) <= 5.0
    eps_rel = csv["eps_abs"][1:] / (csv["T_hot_dem"] - csv["T_cold_dem"])[1:]
    np.testing.assert_allclose(csv["eps_rel"][1:], eps_rel, rtol=1e-12)
    # cells of 3 particles: eq. 9 is about the error of other particles with the same
    # temperatures in each cell (gsi.extrapolation.cell_sampling_level)
    ratio = csv["eps_abs"][1:] / csv["eps_level"][1:]
    assert (ratio <= 2.0).all(), ratio


def test_log_records_wall_contacts_with_their_triangles(quick_run):
    _, out, _, log = quick_run
    n_tri = len(load_case(CASE).quick_variant().walls[0].triangles())
    assert len(log.pw_i) > 0 and (log.pw_wall == 0).all()       # the drum, a mesh wall
    assert log.pw_tri.min() >= 0 and log.pw_tri.max() < n_tri
    assert not log.wall_has_T.any()                             # adiabatic
    assert log.bytes_per_collision() < 20.0
    assert (out / "contact_log.npz").stat().st_size > log.row_bytes()


@pytest.mark.slow
def test_every_step_sampling_replays_the_dems_conduction():
    """n = 1 with the seed's Delta t_c^max = 10 steps on the quick drum's logged period."""
    g = drum_geometry(640)
    sim, _, _ = prepare(g, settle=0.5, spin_up=0.25)
    sim.start_contact_log(every=1, dt_split=1e-3)
    sim.step(g.steps_per_turn // 4)
    log = sim.stop_contact_log()
    T = Replay(log, sigma=np.arange(log.n_particles)).run(1, T=log.T0)["T"][1]
    dT = np.abs(log.T1 - log.T0)
    assert abs((dT.sum() - np.abs(T - log.T0).sum()) / dT.sum()) <= 1e-3
    err = np.abs(T - log.T1)
    assert err.mean() <= 1e-3 * dT.mean() and err.max() <= 5e-3 * dT.max()


@pytest.mark.slow
def test_ci_size_drum_against_the_full_dem():
    """5,000 particles in R = 0.1191 m (Fr 0.048), one turn per period, six periods, n = 1
    and n = 10, Delta t_c^max = 0.01 s (about 45 min on this machine).

    The seed's targets (Table 5, 80,000 particles, 400 per Voronoi cell: eps_rel <= 3.1 %,
    eps_abs <= 0.25 K; eq. 10 <= 5 %) are not met at this size.  Measured
    (benchmarks/drum_extrapolation.py --quick --every 10, t2..t7): eps_abs 1.42, 1.45,
    1.35, 1.53, 1.24, 1.18 K on 200 cells (25 particles each) and 0.85, 0.73, 0.77, 0.86,
    0.76, 0.55 K on 12 cells of 400 particles; eps_rel grows to 177 % as the DEM's
    T_hot - T_cold falls from 8.6 to 0.66 K; eq. 10 -1.6, +4.9, +3.2, -3.4, -5.2, -0.0 %.
    Why: a cell of 25 particles compares particle-scale scatter; and at the bed scale the
    full DEM winds the left/right split into a radial pattern (outer particles 1 K warmer
    than the core at t7) while the frozen permutation of the extrapolation mixes more
    slowly (initially-hot fraction by x quintile at t7: 0.44-0.55 against 0.49-0.53).
    Checked here, with margins, so that a regression shows: conservation, the
    determinism of the restarted period, eq. 10 within 12 %, eq. 9 within 2 K (200 cells)
    and 1.2 K (400 particles per cell), the hot and cold means within 5 % of their gap
    at t1.
    """
    g = drum_geometry(5000)
    sim, hot, _ = prepare(g)
    r = compare_with_dem(sim, period_steps=g.steps_per_turn, periods=6,
                         samplings=((1, 0.01), (10, 0.01)), hot=hot)
    dem = r["dem"]
    assert dem["energy_drift"].max() <= 1e-12
    h = hot[r["runs"][0]["log"].ids]
    gap_dem = dem["T"][:, h].mean(1) - dem["T"][:, ~h].mean(1)
    seeds = voronoi_seeds(r["runs"][0]["log"].x1, 5000 // 400, seed=0)
    for run in r["runs"]:
        assert run["same_t1"] and run["energy_drift"].max() <= 1e-12
        assert np.abs(run["energy_error"]).max() <= 0.12
        assert run["eps_abs"].max() <= 2.0
        e400 = period_errors(run["log"], run, dem["T"], dem["x"], seeds, h)
        assert e400["eps_abs"].max() <= 1.2
        gap_ext = run["T"][:, h].mean(1) - run["T"][:, ~h].mean(1)
        assert np.abs(gap_ext - gap_dem).max() <= 0.05 * gap_dem[0]
