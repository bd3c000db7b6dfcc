"""Long-time heat extrapolation (Haydar, Martin & Bonnefoy 2023, "seed 003") in the
rotating drum of gsi.studies.drum, against gsi's own full DEM of the same drum, judged on
an ensemble (tests/validation/conftest.py).

Default suite: the quick drum of demos/drum_extrapolation.toml -- 640 particles in
R = 0.06 m at the reference Froude number 0.048 (cascading), settled 0.5 s, a quarter
turn of spin-up, and half a turn (11,180 steps) as the period, replayed for four periods
(the seed extrapolates by quarter, half and full turns, its Figs. 13-15), sampling n = 10
with Delta t_c^max = 0.01 s (the seed's 0.001 s and n = 1 give the same eq. 10 within
0.1 % of the heat moved: benchmarks/drum_sweep.py, docs/design.md "Long-time heat
extrapolation"). Half a turn rather than a quarter: with a quarter turn the eps_abs ratio
to the twin at t2 was 1.50-1.57 and eq. 10 6-8 %; with half a turn 1.0-1.14 and 3-4 %
(ensemble means, benchmarks/drum_sweep.py). The demo's case itself runs once through
``gsi run``'s runner in its quick form, with the reference DEM cut to one period; its
``extrapolation.csv`` and ``contact_log.npz`` are checked for what holds on any
trajectory (conservation, the log's wall rows).

The flow is chaotic (a single-run form of this test failed on 5 of 6 neighbouring
trajectories dt x (1 + k 1e-12)), so M = 12 realisations are run, two at a time
(gsi.studies.ensemble.run_ensemble; the settling is shared, passed as a state;
gsi.studies.drum.extrapolation_member): member k's positions are moved by up to k x 0.5 nm
after the settling, the drum turns a quarter turn to t0, one period is logged and
extrapolated for P = 4 periods, and the DEM runs on as the reference. Beside it, the DEM's
own chaos is the yardstick (the "twin"): a second DEM from t1 with every position moved by
up to 1 nm, run for two periods (t2, t3) and compared with the reference by the same eq. 9
-- the error of a prediction as good as the DEM itself. Only the first M_TWIN = 4 members
run the twin (eq. 9's test); it is a quarter of a member's DEM steps, and eq. 10 and the
gap, which use all 12, are bit for bit the same without it (the reference runs first).

Checked (claims on the ensemble mean, bound = mean +- 3 SE, conftest; measured at dt,
dt (1 + 1e-12), dt (1 + 2e-12), 2026-12-05):

- per member (true on any trajectory): the log replayed through the identity gives the
  DEM's t1; sum m c_p T conserved to 1e-12 by the DEM and the replay; eq. 9 of the
  library equal to a brute-force nearest-seed computation from the raw fields, and
  eps_rel = eps_abs/|T_hot - T_cold| from the DEM's raw temperatures;
- eq. 9 (the 4 twin members): eps_abs(extrapolation) <= 1.5 eps_abs(twin) at t2 and t3
  (the issue's bound; ratio of the means 1.12, 1.06; 1.16, 1.00; 1.14, 1.07 at t2, t3;
  excess at mean + 3 SE at most -0.48 K);
- the hot and cold means (the seed's Fig. 7): the halves mix, and the extrapolated gap
  T_hot - T_cold is off the DEM's by at most e (G1/Gn - 1) of Gn: the gap G is the heat
  the halves have exchanged since t1, so moved with a relative error e it is off by that;
  e = GAP_E = 0.25 and the DEM's own G1/Gn give 5.6 and 15 % at t2, t3, capped by the
  flat 10 % it replaced; asserted at t2, t3 (mean + 3 SE at most 1.8 %, 4.65 %); t4, t5
  are printed (mean + 3 SE 6.0-7.0 %, 7.6-8.8 %: within the 10 % cap, without a margin).
  The extrapolated halves always mix faster (signed -1 % at t2 to -3..-5 % at t5), while
  the twin's gap stays within 0.05-0.7 % of the reference's: the gap error is the
  method's bias, so the twin is no yardstick here;
- eq. 10 (heat moved per period) on the mean over the four replayed periods, |mean over
  t2..t5|, at ensemble mean + 3 SE: the seed's 5 % (its Fig. 10: 0.1-4.5 %). A pairing
  inverted or left out gives 42 % and 67 % over two periods.

Eq. 10 at the seed's 5 %. One period of one member scatters by +-4-9 % (mostly the flow's
own chaos: the twin DEM against the DEM +-0.6-6 %), with a trend over the periods (-4.8 %
at t2 to +1.2 % at t5), so the test averages over four. Over 36 members (12 at each of
the three dt) the members' |mean| is 2.59 % with sd 1.50 % (member sd 1.39-1.63 % per
ensemble of 12), so mean + 3 SE <= 4 % (a point of margin) needs M >= 12: expected 3.89 %
at M = 12, failing 5 % for about one redraw in 120-200 (normal model; resampling the 36).
Measured, M = 12: 2.64 +- 0.47, 2.81 +- 0.45, 2.33 +- 0.40 % (mean +- SE), mean + 3 SE
4.05, 4.16, 3.53 %; with M = 4 it was 4.95, 4.09, 4.61 %. Cost: 4 members with the twin
and 8 without, about as much DEM as 10 full members: the ensemble's set-up took 256 s of
CPU against 112 s for M = 4 (so about 121 s against 53 s on two idle cores, +68 s; on the
shared host 226 s at load 3-4 against 209 s at load 4-5).
A reference with less chaos, eq. 10 against the mean heat moved of the DEM and its twin
(two realisations from t1, as legitimate as one), was measured over t2, t3 on the same 36
members: SE 1.06, 0.94, 0.69 % against 1.08, 1.04, 0.82 % for the DEM alone, about a
tenth smaller, while over four periods it costs two more twin periods per member (+27 %
of its steps): not adopted.

The seed's Table 5 (80,000 particles, 400 per cell: eps_abs 0.241 ... 0.03 K, eps_rel
<= 3.1 %) is shown as the goal on the validation page; at 640 particles (3 per cell)
eps_abs is 3-5 K, set by the particle-scale scatter that the twin DEM shows as well.
"""
import dataclasses
import pathlib

import numpy as np
import pytest

from gsi.case import load_case
from gsi.dem.contact_log import ContactLog
from gsi.run import run_case

from gsi.errors import GsiInputError
from gsi.studies.drum import DT, ROLLING_PERIOD, drum_geometry, extrapolation_member, prepare
from gsi.extrapolation import Replay, compare_with_dem, period_errors, voronoi_seeds

ROOT = pathlib.Path(__file__).resolve().parents[2]
CASE = ROOT / "demos" / "drum_extrapolation.toml"
M, PERIODS = 12, 4
#: the members that also run the twin DEM (the first M_TWIN), and its periods (t2, t3):
#: eq. 9's yardstick; eq. 10 and the gap use all M members and all PERIODS
M_TWIN, TWIN_PERIODS = 4, 2
#: sd floors (conftest): about the smallest member spreads measured on two ensembles of
#: the half-turn period (M = 4 at dt and dt (1 + 1e-12): sd 0.36-0.58 K, 0.006-0.018,
#: 0.022-0.028)
SD_EPS_EXCESS = 0.35       # K, eps_abs(extra) - 1.5 eps_abs(twin)
SD_GAP = 0.006             # relative gap difference
SD_EQ10 = 0.013            # eq. 10 over four periods (M = 12: sd 0.0139-0.0163)
#: eq. 10's bound (test_heat_moved_per_period_eq10): the seed's 5 % (its Fig. 10), on the
#: mean over four half turns at ensemble mean + 3 SE (module docstring)
EQ10_BOUND = 0.05
#: the relative error e of the heat moved that the hot/cold gap's bound carries over
#: (test_hot_and_cold_means_follow_the_full_dem): eq. 10's regression value of the
#: two-period test; the seed's 5 % carried the same way is shown as the goal
GAP_E = 0.25


@pytest.fixture(scope="module")
def ensemble(ens):
    g = drum_geometry(640)
    sim, hot, case = prepare(g, settle=0.5, spin_up=0.0, dt=DT * ens.DT_SCALE)
    members = ens.run_ensemble(extrapolation_member, M, args=(
        g, sim.state(), hot, DT * ens.DT_SCALE, PERIODS, TWIN_PERIODS),
        kwargs=dict(twin_members=M_TWIN))
    return g, members, case


def test_the_quick_drum_is_the_family_at_the_seed_froude_number(ensemble, ens):
    g, members, _ = ensemble
    assert g.regime == "cascading" and g.froude == pytest.approx(0.0483, abs=2e-4)
    assert drum_geometry(80_000).period == pytest.approx(5.0)
    for m in members:
        log = m["run"]["log"]
        assert log.n_particles == 640 and (log.every, log.split) == (10, 100)
        assert log.period == pytest.approx(g.steps_per_turn // 4 * 2 * DT * ens.DT_SCALE)
        assert m["dem"]["T"].shape == (PERIODS + 1, 640)
    for m in members[:M_TWIN]:
        assert m["dem"]["twin"]["T"].shape == (TWIN_PERIODS + 1, 640)
        assert m["dem"]["twin"]["eps_abs"].shape == (TWIN_PERIODS,)
    assert all(m["dem"]["twin"] is None for m in members[M_TWIN:])
    # the members are distinct realisations: their t1 differs
    assert not np.array_equal(members[0]["run"]["log"].x1, members[1]["run"]["log"].x1)


def test_the_rolling_family_is_the_seeds_fig12_drum():
    """The seed's rolling regime (Figs. 11a, 12: 15 s per turn of the 80,000-particle
    drum) scaled to small drums at its Froude number (benchmarks/drum_sweep.py
    --reference-period 15)."""
    big = drum_geometry(80_000, ROLLING_PERIOD)
    assert big.period == pytest.approx(15.0) and big.regime == "rolling"
    assert big.froude == pytest.approx((2 * np.pi / 15.0) ** 2 * 0.30 / 9.81, rel=1e-12)
    small = drum_geometry(640, ROLLING_PERIOD)
    assert small.radius == drum_geometry(640).radius and small.regime == "rolling"
    assert small.froude == pytest.approx(big.froude, rel=1e-3)
    assert small.steps_per_turn == pytest.approx(3 * drum_geometry(640).steps_per_turn, abs=2)
    with pytest.raises(GsiInputError, match="reference_period"):
        drum_geometry(640, 0.0)
    # a twin longer than the comparison is refused before any DEM runs
    with pytest.raises(GsiInputError, match="twin_periods"):
        compare_with_dem(None, period_steps=10, periods=2, twin=1e-9, twin_periods=3)


def test_logged_period_replays_the_dems_conduction(ensemble):
    for m in ensemble[1]:
        log = m["run"]["log"]
        T = Replay(log, sigma=np.arange(log.n_particles)).run(1, T=log.T0)["T"][1]
        dT = np.abs(log.T1 - log.T0)
        moved = (dT.sum() - np.abs(T - log.T0).sum()) / dT.sum()     # eq. 10 on the period
        assert abs(moved) <= 3e-3
        err = np.abs(T - log.T1)
        assert err.mean() <= 1e-2 * dT.mean() and err.max() <= 5e-2 * dT.max()


def test_heat_is_conserved_by_the_dem_and_the_replay(ensemble):
    for m in ensemble[1]:
        log, run, dem = m["run"]["log"], m["run"], m["dem"]
        assert dem["energy_drift"].max() <= 1e-12 and run["energy_drift"].max() <= 1e-12
        E0 = log.heat_capacity @ log.T0
        assert abs(log.heat_capacity @ log.T1 - E0) <= 1e-12 * abs(E0)


def _brute_cell_error(seeds, x_a, T_a, x_b, T_b):
    """eq. 9's eps_abs with the nearest seed found by brute force (all distances)."""
    def means(x, T):
        cell = np.argmin(((x[:, None, :] - seeds[None]) ** 2).sum(2), axis=1)
        out = np.full(len(seeds), np.nan)
        for c in np.unique(cell):
            out[c] = T[cell == c].mean()
        return out
    a, b = means(x_a, T_a), means(x_b, T_b)
    both = np.isfinite(a) & np.isfinite(b)
    return np.abs(a[both] - b[both]).mean()


def test_eq9_from_the_raw_fields(ensemble):
    """The library's eq. 9 (k-d tree cells, period_errors) against a brute-force
    computation from the raw positions and temperatures of the DEM and the replay."""
    m = ensemble[1][0]
    run, dem, seeds, h = m["run"], m["dem"], m["seeds"], m["hot"]
    for n in range(1, PERIODS + 1):
        e = _brute_cell_error(seeds, dem["x"][n], dem["T"][n], run["x"][n], run["T"][n])
        gap = abs(dem["T"][n][h].mean() - dem["T"][n][~h].mean())
        assert run["eps_abs"][n - 1] == pytest.approx(e, rel=1e-12)
        assert run["eps_rel"][n - 1] == pytest.approx(e / gap, rel=1e-12)
    # the measure sees a wrong field: the DEM against itself is 0, against the
    # temperatures of t1 (no conduction) it is not
    assert _brute_cell_error(seeds, dem["x"][1], dem["T"][1], dem["x"][1], dem["T"][1]) == 0
    assert _brute_cell_error(seeds, dem["x"][2], dem["T"][2], dem["x"][2], dem["T"][0]) > 0.1


def test_extrapolation_error_within_the_dems_own_chaos(ensemble, ens, record_validation):
    """eps_abs(extrapolation) <= 1.5 eps_abs(twin) at every t_n, on the ensemble."""
    members = ensemble[1][:M_TWIN]
    ext = np.array([m["run"]["eps_abs"][:TWIN_PERIODS] for m in members])
    twin = np.array([m["dem"]["twin"]["eps_abs"] for m in members])
    s = ens.stat(ext - 1.5 * twin, SD_EPS_EXCESS)
    ratio = ext.mean(0) / twin.mean(0)
    print(f"eps_abs extra {ens.stat(ext).text()} K; twin {ens.stat(twin).text()} K;"
          f" ratio of means {np.round(ratio, 3)}; excess {s.text()} K")
    record_validation(f"quick drum (640, half turn, M = {M_TWIN}): eps_abs(extra)/eps_abs(twin "
                      "DEM) of the ensemble means, largest over t2, t3", reference=1.5,
                      measured=float(ratio.max()), tolerance=1.5, kind="bound",
                      note="mean + 3 SE of eps_abs(extra) - 1.5 eps_abs(twin) <= 0 at every "
                           "t_n", source="the DEM's own chaos (twin DEM, 1 nm at t1)",
                      goal="seed 003 Table 5 (80,000): eps_abs 0.241 .. 0.03 K")
    assert (s.upper() <= 0.0).all(), s.text()


def test_hot_and_cold_means_follow_the_full_dem(ensemble, ens, record_validation):
    members = ensemble[1]
    gd = np.array([m["gap_dem"] for m in members])
    ge = np.array([m["gap_ext"] for m in members])
    mix = ens.stat(gd[:, -1] / gd[:, 0], 0.01)
    assert (mix.upper() < 0.8).all(), mix.text()                 # the halves do mix
    # asserted at t2, t3; t4, t5 are printed, not asserted: mean + 3 SE 6.0-8.8 % on 12
    # members at the three dt, within the 10 % cap without a margin (module docstring)
    every = ens.stat(np.abs(ge - gd)[:, 1:] / gd[:, 1:], SD_GAP)
    s = ens.stat(np.abs(ge - gd)[:, 1:TWIN_PERIODS + 1] / gd[:, 1:TWIN_PERIODS + 1], SD_GAP)
    # the bound: the gap is the heat the halves have exchanged since t1; moved with eq.
    # 10's relative error e (the extrapolation's heat moved per period), the extrapolated
    # gap at t_n is off by e (G1 - Gn), i.e. by e (G1/Gn - 1) of Gn, with e = GAP_E
    # and G1/Gn the DEM's own mixing (its ensemble mean)
    mixed = (gd[:, :1] / gd[:, 1:]).mean(0) - 1.0
    # ... and never looser than the flat 10 % it replaced (at t3 the carried bound is 15 %)
    bound = np.minimum(GAP_E * mixed, 0.10)[:TWIN_PERIODS]
    gt = np.array([m["gap_twin"] for m in members[:M_TWIN]])
    k = gt.shape[1]
    tw = ens.stat(np.abs(gt - gd[:M_TWIN, :k])[:, 1:] / gd[:M_TWIN, 1:k])
    print(f"|gap_ext - gap_dem|/gap_dem at t2..t{PERIODS + 1}: {every.text()}; bounds at t2, "
          f"t3 {np.round(bound, 4)}; "
          f"signed {ens.stat((ge - gd)[:, 1:] / gd[:, 1:]).text()}; twin DEM {tw.text()}; "
          f"gap_dem/gap_dem(t1) at the end {mix.text()}")
    record_validation(f"quick drum (640, half turn, M = {M}): |gap_extra - gap_DEM|/gap_DEM "
                      "of the hot and cold means, largest (ensemble mean + 3 SE)/bound",
                      reference=1.0, measured=float((s.upper() / bound).max()), tolerance=1.0,
                      kind="bound", source="seed 003 Fig. 7; eq. 10's bound carried to the gap",
                      note="bound at t_n: min(0.25 (G1/Gn - 1), 10 %) = " +
                           ", ".join(f"{100 * b:.1f} %" for b in bound),
                      goal="the seed's eq. 10 <= 5 %: 0.05 (G1/Gn - 1) = " +
                           ", ".join(f"{100 * b:.2f} %" for b in 0.05 * mixed[:TWIN_PERIODS]))
    assert (s.upper() <= bound).all(), s.text()


def test_heat_moved_per_period_eq10(ensemble, ens, record_validation):
    """eq. 10 averaged over the four replayed periods, |mean over t2..t5|, on the
    ensemble: mean + 3 SE <= the seed's 5 % (module docstring)."""
    members = ensemble[1]
    e = np.array([m["run"]["energy_error"] for m in members])
    s = ens.stat(np.abs(e.mean(1)), SD_EQ10)
    print(f"eq. 10 (signed) at t2..t{PERIODS + 1}: {ens.stat(e).text()}; |mean over the "
          f"periods| {s.text()}, sd {float(s.sd):.3g}, mean + 3 SE {float(s.upper()):.4f} "
          f"(bound {EQ10_BOUND})")
    record_validation(f"quick drum (640, half turn, M = {M}): eq. 10, |mean over the "
                      f"{PERIODS} periods|, ensemble mean + 3 SE", reference=EQ10_BOUND,
                      measured=float(s.upper()), tolerance=EQ10_BOUND,
                      kind="bound", source="seed 003 eq. 10 and Fig. 10",
                      goal="seed 003 Fig. 10: 0.1-4.5 % per period (<= 5 %)",
                      note="the seed's 5 % on the mean over four half-turn periods")
    assert s.upper() <= EQ10_BOUND, s.text()


@pytest.fixture(scope="module")
def demo_run(tmp_path_factory):
    """demos/drum_extrapolation.toml, quick, through the runner; one period of reference."""
    out = tmp_path_factory.mktemp("drum_extrapolation")
    case = load_case(CASE).quick_variant()
    xp = dataclasses.replace(case.extrapolation, compare_periods=1)
    case.extrapolation = xp
    case.run = dataclasses.replace(case.run, duration=xp.end())
    r = run_case(case, out=out, pictures=False, verbose=False)
    csv = np.genfromtxt(out / "extrapolation.csv", delimiter=",", names=True)
    return case, r, out, csv, ContactLog.load(out / "contact_log.npz")


def test_the_demo_case_writes_a_conserving_extrapolation(demo_run):
    case, r, out, csv, log = demo_run
    assert r.n_particles == 640 and r.n_lost == 0
    assert len(csv) == 7 and (log.every, log.split) == (10, 100)
    assert log.period == pytest.approx(drum_geometry(640).steps_per_turn // 4 * DT)
    assert csv["energy_drift"][:2].max() <= 1e-12
    E0 = log.heat_capacity @ log.T0
    assert abs(log.heat_capacity @ log.T1 - E0) <= 1e-12 * abs(E0)
    Tm = csv["T_mean_extra"]
    assert np.abs(Tm - Tm[0]).max() <= 1e-12 * abs(Tm[0])
    np.testing.assert_allclose(csv["T_mean_dem"][:2], Tm[:2], rtol=1e-12)
    assert np.isnan(csv["T_mean_dem"][2:]).all()              # one period of reference
    gap = csv["T_hot_extra"] - csv["T_cold_extra"]
    assert (np.diff(gap) < 0).all()                             # the replay mixes the halves


def test_log_records_wall_contacts_with_their_triangles(demo_run):
    case, _, out, _, log = demo_run
    n_tri = len(case.walls[0].triangles())
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
    and n = 10, Delta t_c^max = 0.01 s (about 45 min on this machine). One realisation:
    a regression check, not an ensemble claim (the ensemble is the quick test's).

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
