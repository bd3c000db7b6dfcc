"""The heated kiln (gsi.studies.kiln): the long-time heat extrapolation of Haydar, Martin &
Bonnefoy (2023, "seed 003") with a wall that is an FE heat structure, against gsi's own
full DEM + FE run of the same kiln.

The kiln at CI size: 300 spheres (r = 5 mm, k = 2 W/(m K)) in a 5 mm steel shell of
R = 0.0466 m held at 393.15 K outside, turning once per 2 s about x (Fr = 0.047,
cascading); the halves at 313.15 K and 293.15 K when it starts; a quarter turn logged
(n = 10, Delta t_c^max = 0.01 s) and replayed for 20 quarter turns, the full DEM + FE
run on for 3 of them.  Checked:

- the replay steps the FE once per coupling interval and keeps sum m c_p T (bed) +
  int rho c T dx (shell) - (heat in through the outer surface) to round-off (1e-12
  relative) over the 20 periods;
- against the full run (chaotic: judged on an ensemble of M = 12 realisations whose
  start positions differ by up to k x 0.5 nm, tests/validation/conftest.py, run two at a
  time; each member's largest error over the compared periods, the ensemble mean + 3 SE
  below the bound): the bed's mean temperature and the mean temperatures of the
  initially hot and cold halves within 0.05 K, the shell's mean within 0.01 K;
- the heat per period, at the seed's 5 % (its eq. 10 and Fig. 10): the heat the shell
  gives the bed in a period (the bed's heating, relative error) and eq. 10, each
  member's largest over the three compared periods. One member scatters by 0.9-5.0 %, so
  with M = 3 mean + 3 SE reached 6.0 % and the bound was a 10 % regression bound. With
  M = 12, measured at dt, dt (1 + 1e-12), dt (1 + 2e-12) (mean +- SE): gain 2.87 +- 0.33,
  2.39 +- 0.23, 2.10 +- 0.29 %, mean + 3 SE 3.9, 3.1, 3.0 %; eq. 10 2.80 +- 0.29,
  2.87 +- 0.35, 2.49 +- 0.40 %, mean + 3 SE 3.7, 3.9, 3.7 %: a margin of more than a
  point, about 3 SE of the ensemble mean (member sd 0.8-1.4 %; on 15 members mean + 3 SE
  at most 3.8 %, on 10 at most 4.05 %);
- eq. 9 (ensemble, as above): regression bounds, on 200 Voronoi cells (1.5 particles
  each: single particles, as in the drum's quick test) 10 K, on 12 cells of 25 particles
  3.5 K. The seed's Table 5 (eps_abs <= 0.25 K, eps_rel <= 3.1 %, with 400 particles per
  cell) is not reached: the members' largest eps_abs over t2..t4 on 200 cells 7.2-7.6 K
  (sd 0.6-0.7 K; eps_rel of one realisation 21, 28, 38 % of T_hot - T_cold = 20 K at t2,
  t3, t4), on 12 cells 2.2-2.3 K (M = 15 at the three dt).  The means: largest
  differences 0.003-0.004 K (bed), 0.008-0.013 / 0.011-0.017 K (hot / cold halves),
  0.0011-0.0016 K (shell).
  With k = 2 W/(m K) a
  particle keeps its temperature for many turns, so the field is carried by the
  particles' identities, and the cell error counts the particles that the relabelling
  (sigma^p of one quarter turn) puts in other cells than the DEM's own mixing does; it
  grows with the periods.  The means, eq. 10 and the heat from the shell do not depend
  on where a particle is, and agree.
"""
import numpy as np
import pytest

from gsi.dem.contact_log import ContactLog
from gsi.extrapolation import cell_error, voronoi_seeds
from gsi.studies.kiln import kiln_case, kiln_geometry
from gsi.run import Runner

#: realisations (tests/validation/conftest.py: member k's start positions moved by up to
#: k x 0.5 nm)
M = 12
#: sd floors (conftest): about the smallest member sd of three ensembles (M = 15 at dt,
#: dt (1 + 1e-12), dt (1 + 2e-12)); measured sd: T_mean 0.0016-0.0022 K, T_hot
#: 0.0055-0.0074 K, T_cold 0.0058-0.0096 K, T_wall_mean 0.0006-0.0009 K, gain
#: 0.0084-0.0116, eq. 10 0.0099-0.0141, eps 200 cells 0.57-0.70 K, 12 cells 0.31-0.45 K
SD_FLOOR = {"T_mean": 0.0015, "T_hot": 0.005, "T_cold": 0.005, "T_wall_mean": 0.0005,
            "gain": 0.008, "eq10": 0.01, "eps200": 0.5, "eps12": 0.3}


def _case():
    case = kiln_case(kiln_geometry(300), settle=0.5, spin_up=0.25, period_turns=0.25,
                     periods=20, compare_periods=3)
    case.output.pictures = False
    return case


def _extract(runner):
    """What the ensemble tests need of a member (picklable): counts, the summary, the
    extrapolation's CSV, the logged period, the FE wall's rows in the log, the errors."""
    res = runner.result
    csv = np.genfromtxt(runner.out / "extrapolation.csv", delimiter=",", names=True)
    log = ContactLog.load(runner.out / "contact_log.npz")
    fe_wall = runner.sim.wall_slot(runner.structures[0].wall)
    rows = log.pw_wall == fe_wall
    return dict(n=res.n_particles, lost=res.n_lost, summary=res.summary, csv=csv,
                period=log.period, x1=log.x1, fe_rows=int(rows.sum()),
                fe_tri=(int(log.pw_tri[rows].min()), int(log.pw_tri[rows].max())),
                n_tri=len(runner.structures[0].interface.triangles),
                errors=_errors(runner, csv, log))


@pytest.fixture(scope="module")
def kiln_members(tmp_path_factory, ens):
    """M realisations of the kiln side by side; member 0 runs in this process (its
    runner, with the FE shell, is :func:`kiln`'s)."""
    out = tmp_path_factory.mktemp("kiln")
    return ens.run_members(_case, out, M, extract=_extract, keep=(0,))


@pytest.fixture(scope="module")
def kiln_ensemble(kiln_members):
    """Per member: the dict of :func:`_extract`."""
    return [_extract(m) if k == 0 else m for k, m in enumerate(kiln_members)]


@pytest.fixture(scope="module")
def kiln(kiln_members):
    """Member 0, the case as it is: (runner, result, csv, log)."""
    r = kiln_members[0]
    return (r, r.result, np.genfromtxt(r.out / "extrapolation.csv", delimiter=",", names=True),
            ContactLog.load(r.out / "contact_log.npz"))


def _errors(runner, csv, log):
    """The chaotic quantities of one member against its own full DEM + FE run: the largest
    difference over the compared periods of the bed's, the hot and cold halves' and the
    shell's mean temperatures (K), of the heat the bed took per period (relative), of
    eq. 10, and eq. 9 on 200 cells and on 12 cells of 25 particles (K)."""
    live = ~np.isnan(csv["T_mean_dem"])
    assert live.sum() == 4
    e = {a: float(np.abs(csv[f"{a}_extra"][live] - csv[f"{a}_dem"][live]).max())
         for a in ("T_mean", "T_hot", "T_cold", "T_wall_mean")}
    C = csv["E_particles_extra"][0] / csv["T_mean_extra"][0]
    gain_dem = np.diff(csv["T_mean_dem"][live]) * C
    gain_ext = np.diff(csv["E_particles_extra"][live])
    e["gain"] = float(np.abs(gain_ext / gain_dem - 1).max())
    e["eq10"] = float(np.nanmax(np.abs(csv["energy_error"])))
    e["eps200"] = float(np.nanmax(csv["eps_abs"]))
    xp = runner.extrapolation
    hot = xp.hot[log.ids]
    seeds = voronoi_seeds(log.x1, 12, seed=0)
    errs = []
    for n in range(1, 4):
        ea, _, used = cell_error(seeds, xp.dem_x[n], xp.dem_T[n], xp.res["x"][n],
                                 xp.res["T"][n], hot=hot)
        assert used == 12
        errs.append(ea)
    e["eps12"] = float(max(errs))
    return e


def test_the_kiln_is_the_drum_family_cascading(kiln_ensemble):
    g = kiln_geometry(300)
    assert g.regime == "cascading" and g.period == pytest.approx(2.0)
    for m in kiln_ensemble:
        assert m["n"] == 300 and m["lost"] == 0
        assert m["period"] == pytest.approx(0.5) and len(m["csv"]) == 21
        # the FE wall's contacts are in the log, with their triangles
        assert m["fe_rows"] > 100
        assert m["fe_tri"][0] >= 0 and m["fe_tri"][1] < m["n_tri"]
    # the members are distinct realisations
    assert not np.array_equal(kiln_ensemble[0]["x1"], kiln_ensemble[1]["x1"])


def test_replay_balances_bed_shell_and_outer_heat_to_round_off(kiln_ensemble):
    for m in kiln_ensemble:
        csv = m["csv"]
        E = csv["E_particles_extra"] + csv["E_structure_extra"] - csv["Q_boundary_extra"]
        assert np.abs(E - E[0]).max() < 1e-12 * abs(E[0])
        assert m["summary"]["energy_balance_rel"] < 1e-12
        # heat did flow: the shell heated the bed, the jacket re-heated the shell
        assert csv["Q_wall_extra"][1:].min() > 0
        assert csv["T_mean_extra"][-1] > csv["T_mean_extra"][0] + 0.5
        assert csv["Q_boundary_extra"][-1] > 0


#: the claims on the ensemble: quantity, bound, unit, what the bound is (module
#: docstring: the heat per period at the seed's 5 %, eq. 9 and the means regression bounds)
BOUNDS = (("T_mean", 0.05, "K", "bed mean temperature, largest |extra - DEM| over t1..t4"),
          ("T_hot", 0.05, "K", "initially hot half's mean temperature"),
          ("T_cold", 0.05, "K", "initially cold half's mean temperature"),
          ("T_wall_mean", 0.01, "K", "shell's mean temperature"),
          ("gain", 0.05, "", "heat the bed took per period, largest relative error, "
                             "the seed's 5 %"),
          ("eq10", 0.05, "", "eq. 10, largest |error| per period, the seed's 5 %"),
          ("eps200", 10.0, "K", "eq. 9 on 200 cells (1.5 particles each), regression bound"),
          ("eps12", 3.5, "K", "eq. 9 on 12 cells of 25 particles, regression bound"))


@pytest.mark.parametrize("key,bound,unit,what", BOUNDS, ids=[b[0] for b in BOUNDS])
def test_replay_follows_the_full_dem_fe_run(kiln_ensemble, ens, record_validation, key,
                                            bound, unit, what):
    """Ensemble mean + 3 SE of each member's largest error <= the bound."""
    v = [m["errors"][key] for m in kiln_ensemble]
    s = ens.stat(v, SD_FLOOR[key])
    print(f"kiln {key}: members {np.round(v, 5)}; {s.text()}; sd {float(s.sd):.3g}")
    record_validation(f"kiln (300, FE shell, M = {M}): {what}, ensemble mean + 3 SE",
                      reference=bound, measured=float(s.upper()), tolerance=bound,
                      kind="bound", unit=unit,
                      source=("seed 003's 5 % (eq. 10, Fig. 10); " if key in ("gain", "eq10")
                              else "") + "gsi's own full DEM + FE run",
                      goal="seed 003 Table 5 eps_abs <= 0.25 K (400 per cell)"
                      if key.startswith("eps") else "")
    assert s.upper() <= bound, s.text()


def test_wall_contacts_turn_with_the_shell(kiln):
    """The logged wall triangles are numbered in the shell's frame: turned by the shell's
    angle at t1 they lie under the bed at t1; the DEM turns the wall as the replay's
    rotation does; after one period the replay's triangle stands where the logged one
    stood (a quarter turn back in the shell's frame)."""
    from scipy.spatial import cKDTree
    from gsi.extrapolation import FEWallReplay, rotate
    runner, _, _, log = kiln
    st = runner.structures[0]
    itf = st.interface
    omega = 2 * np.pi / 2.0                       # rad/s, one turn per 2 s about +x
    axis, centre = np.array([1.0, 0.0, 0.0]), np.zeros(3)
    # the DEM's wall at the end of the run (t = 3 s, turning since 0.5 s)
    assert np.abs(st.wall.vertices - rotate(itf.x0, axis, centre, omega * 2.5)).max() < 1e-9
    fe_wall = runner.sim.wall_slot(st.wall)
    K = int(round(log.period / log.dt))
    open_at_t1 = (log.pw_wall == fe_wall) & (log.pw_start + log.pw_dur == K)
    tri = np.unique(log.pw_tri[open_at_t1])
    assert len(tri) > 20
    c = itf.x0[itf.triangles].mean(axis=1)
    lab_t1 = rotate(c[tri], axis, centre, omega * (log.t1 - 0.5))
    d, _ = cKDTree(log.x1).query(lab_t1)
    assert np.median(d) < 0.006 and d.max() < 0.012      # r = 5 mm, triangles ~12 mm
    rep = FEWallReplay(log, st, fe_wall=fe_wall, omega=omega * axis, centre=centre)
    assert rep.n_intervals == 2 and rep.turn_per_period == pytest.approx(np.pi / 2)
    m = rep.triangle_map(1)
    lab_t2 = rotate(c[m[tri]], axis, centre, omega * (log.t1 + log.period - 0.5))
    assert np.median(np.linalg.norm(lab_t2 - lab_t1, axis=1)) < 0.006
    assert rep.triangle_map(4) is None                   # a whole turn: the identity


@pytest.mark.slow
def test_kiln_2000_against_the_seeds_targets(tmp_path):
    """2,000 particles (R = 0.0877 m, 3 s per turn, Fr = 0.039), a quarter turn logged, six
    of full DEM + FE, half an hour extrapolated (~5 min here).  The seed's Table 5 on
    cells of 400 particles (its count): eps_rel <= 3.1 % is met (measured 1.4-2.9 %),
    eps_abs <= 0.25 K is not (0.29-0.56 K; 5 cells only); on 200 cells (10 particles)
    1.9-4.3 K, on 80 (25) 1.4-2.7 K.  Eq. 10 <= 2.0 %, the means within 0.02 K; the bounds
    below are regression bounds with the targets beside them."""
    case = kiln_case(kiln_geometry(2000), settle=0.5, spin_up=0.25, period_turns=0.25,
                     periods=2400, compare_periods=6)
    runner = Runner(case, out=tmp_path, pictures=False, verbose=False)
    res = runner.run()
    s = res.summary
    assert s["energy_balance_rel"] < 1e-12
    assert s["energy_err_max"] < 0.05                    # the seed's eq. 10 target
    csv = np.genfromtxt(tmp_path / "extrapolation.csv", delimiter=",", names=True)
    live = ~np.isnan(csv["T_mean_dem"])
    for a in ("T_mean", "T_hot", "T_cold", "T_wall_mean"):
        assert np.abs(csv[f"{a}_extra"][live] - csv[f"{a}_dem"][live]).max() < 0.05, a
    xp = runner.extrapolation
    log = xp.log
    hot = xp.hot[log.ids]
    seeds = voronoi_seeds(log.x1, 5, seed=0)
    e = np.array([cell_error(seeds, xp.dem_x[n], xp.dem_T[n], xp.res["x"][n], xp.res["T"][n],
                             hot=hot)[:2] for n in range(1, 7)])
    assert e[:, 1].max() < 0.031                        # the seed's eps_rel target
    assert e[:, 0].max() < 0.8                          # target 0.25 K: not met
    assert np.nanmax(csv["eps_abs"]) < 6.0              # 200 cells of 10 particles
