"""The seed's rolling regime (Haydar, Martin & Bonnefoy 2023, "seed 003", Figs. 11a and 12:
the 80,000-particle drum at 15 s per turn, Fr = 0.0054) on the 640-particle drum of the
family (gsi.studies.drum, 6.708 s per turn), extrapolated and compared with gsi's own
full DEM on an ensemble. Slow (``-m slow``, not in ``make test``): a member is 251,550
DEM steps, about 110 s on an idle core.

Set up as the quick cascading test (test_drum_extrapolation.py, the same member function
:func:`gsi.studies.drum.extrapolation_member`): filled, settled 0.5 s, halves hot/cold;
member k moved by up to k x 0.5 nm, a quarter turn of spin-up, half a turn (33,540
steps) logged with n = 10, Delta t_c^max = 0.01 s and replayed for four half turns
against the DEM run on, every member with a twin DEM from t1 (1 nm) for two of them. M
members run two at a time (gsi.studies.ensemble.run_ensemble).

The seed's Fig. 12 is a plot of the hot and cold means with no number; its nearest
quantitative goals are eq. 10's 5 % (Fig. 10) and the issue's eps_abs <= 1.5 eps_abs(twin).
Measured once (M = 16 at dt, 2026-12-05, 27 min of wall time at load 4-6), neither
holds in the rolling regime at 640 particles, and not for want of members: the
extrapolation moves more heat than the DEM in every period (eq. 10 signed -7.5, -6.4,
-11.4, -4.7 % at t2..t5, +- 1.0-1.7 %; |mean over the periods| 7.48 +- 0.67 %, member sd
2.7 %, mean + 3 SE 9.5 %); eps_abs against 1.5 eps_abs(twin): ratio of the means 1.36,
1.61 at t2, t3, excess -0.26 +- 0.11, +0.20 +- 0.25 K (mean + 3 SE +0.07, +0.94 K); and
the extrapolated halves mix faster than the DEM's, their gap off by 4.3, 10.1, 19.3,
28.5 % (+- 0.6-3.0) at t2..t5 while the twin's stays within 1.2, 3.2 % (the cascading
quick drum: 1-5 %). Heat is conserved to 1.3e-15. So:

- asserted: heat conserved by the DEM and the replay on every member (1e-12), the halves
  mix; eq. 10 within a 15 % regression bound at mean + 3 SE (set from the measured mean
  7.5 % and member sd 2.7 %: it holds for a mean up to 13 % at that sd with M = 16);
- the seed's 5 % for eq. 10 and the issue's eps_abs <= 1.5 eps_abs(twin) at t2, t3 are
  strict xfails: they measure the gap, and fail as XPASS once the rolling regime is
  extrapolated that well;
- printed and recorded: the hot/cold gap at t2..t5 (no bound: the seed gives none).
"""
import numpy as np
import pytest

from gsi.studies.drum import DT, ROLLING_PERIOD, drum_geometry, extrapolation_member, prepare

#: members (two at a time: 27 min of wall time at load 4-6, 160-240 s a member)
M = 16
PERIODS, TWIN_PERIODS = 4, 2
#: eq. 10's regression bound (module docstring); the seed's 5 % is the goal
EQ10_REGRESSION, EQ10_SEED = 0.15, 0.05

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def rolling(ens):
    g = drum_geometry(640, ROLLING_PERIOD)
    sim, hot, _ = prepare(g, settle=0.5, spin_up=0.0, dt=DT * ens.DT_SCALE)
    members = ens.run_ensemble(extrapolation_member, M, args=(
        g, sim.state(), hot, DT * ens.DT_SCALE, PERIODS, TWIN_PERIODS))
    return g, members


def _eq10(members, ens):
    e = np.array([m["run"]["energy_error"] for m in members])
    return e, ens.stat(np.abs(e.mean(1)))


def _excess(members, ens):
    ext = np.array([m["run"]["eps_abs"][:TWIN_PERIODS] for m in members])
    twin = np.array([m["dem"]["twin"]["eps_abs"] for m in members])
    return ext, twin, ens.stat(ext - 1.5 * twin)


def test_rolling_drum_conserves_heat_and_mixes(rolling, ens, record_validation):
    g, members = rolling
    assert g.regime == "rolling" and g.froude == pytest.approx(0.00537, abs=1e-5)
    for m in members:
        assert m["dem"]["energy_drift"].max() <= 1e-12
        assert m["run"]["energy_drift"].max() <= 1e-12
        assert m["run"]["log"].period == pytest.approx(g.steps_per_turn // 4 * 2 * DT *
                                                       ens.DT_SCALE, rel=1e-12)
    gd = np.array([m["gap_dem"] for m in members])
    ge = np.array([m["gap_ext"] for m in members])
    gt = np.array([m["gap_twin"] for m in members])
    rel = ens.stat(np.abs(ge - gd)[:, 1:] / gd[:, 1:])
    tw = ens.stat(np.abs(gt - gd[:, :TWIN_PERIODS + 1])[:, 1:] / gd[:, 1:TWIN_PERIODS + 1])
    print(f"rolling: |gap_ext - gap_dem|/gap_dem at t2..t{PERIODS + 1} {rel.text()}; signed "
          f"{ens.stat((ge - gd)[:, 1:] / gd[:, 1:]).text()}; twin DEM {tw.text()}; "
          f"gap_dem/gap_dem(t1) {ens.stat(gd[:, 1:] / gd[:, :1]).text()}")
    record_validation(f"rolling drum (640, 15 s per turn scaled, half turn, M = {M}): "
                      "|gap_extra - gap_DEM|/gap_DEM of the hot and cold means at t2..t5 "
                      "(ensemble means; measured, no bound)", reference=0.0,
                      measured=[round(float(v), 4) for v in rel.mean], tolerance="none",
                      kind="bound", note="printed, not asserted: the seed's Fig. 12 gives "
                      "no number", source="seed 003 Fig. 12",
                      goal="the extrapolated hot and cold means follow the DEM's")
    mix = ens.stat(gd[:, -1] / gd[:, 0], 0.01)
    assert (mix.upper() < 0.8).all(), mix.text()                 # the halves do mix


def test_rolling_heat_moved_per_period_eq10(rolling, ens, record_validation):
    """eq. 10, |mean over the four periods|, at mean + 3 SE: a regression bound."""
    e, s = _eq10(rolling[1], ens)
    print(f"rolling: eq. 10 (signed) at t2..t{PERIODS + 1} {ens.stat(e).text()}; |mean over "
          f"the periods| {s.text()}, sd {float(s.sd):.3g}, mean + 3 SE {float(s.upper()):.4f}")
    record_validation(f"rolling drum (640, 15 s per turn scaled, half turn, M = {M}): eq. 10, "
                      f"|mean over the {PERIODS} periods|, ensemble mean + 3 SE",
                      reference=EQ10_REGRESSION, measured=float(s.upper()),
                      tolerance=EQ10_REGRESSION, kind="bound",
                      source="seed 003 eq. 10 and Fig. 10",
                      goal=f"seed 003: <= 5 %, not met here (ensemble mean "
                           f"{100 * float(s.mean):.1f} %; a strict xfail)",
                      note="a regression bound; the extrapolation moves more heat than "
                           "the DEM in every period")
    assert s.upper() <= EQ10_REGRESSION, s.text()


@pytest.mark.xfail(strict=True, reason="rolling regime at 640 particles: eq. 10 7.5 +- 0.7 % "
                   "(module docstring)")
def test_rolling_eq10_at_the_seeds_5_percent(rolling, ens):
    _, s = _eq10(rolling[1], ens)
    assert s.upper() <= EQ10_SEED, s.text()


@pytest.mark.xfail(strict=True, reason="rolling regime at 640 particles: eps_abs over "
                   "1.5 twin at t3 (module docstring)")
def test_rolling_eps_abs_within_the_dems_own_chaos(rolling, ens, record_validation):
    """eq. 9: eps_abs(extrapolation) <= 1.5 eps_abs(twin) at t2, t3 (the issue's bound)."""
    ext, twin, s = _excess(rolling[1], ens)
    ratio = ext.mean(0) / twin.mean(0)
    print(f"rolling: eps_abs extra {ens.stat(ext).text()} K; twin {ens.stat(twin).text()} K; "
          f"ratio of means {np.round(ratio, 3)}; excess {s.text()} K, sd "
          f"{np.round(s.sd, 3)}, mean + 3 SE {np.round(s.upper(), 3)}")
    record_validation(f"rolling drum (640, 15 s per turn scaled, half turn, M = {M}): "
                      "eps_abs(extra) - 1.5 eps_abs(twin DEM), mean + 3 SE at t2, t3 (K; "
                      "not met: a strict xfail)", reference=0.0,
                      measured=[round(float(v), 3) for v in s.upper()], tolerance=0.0,
                      kind="bound", unit="K",
                      note=f"ratio of the means {ratio[0]:.2f}, {ratio[1]:.2f}",
                      source="the DEM's own chaos (twin DEM, 1 nm at t1)",
                      goal="seed 003 Fig. 12 (no number); Table 5 (cascading)")
    assert (s.upper() <= 0.0).all(), s.text()
