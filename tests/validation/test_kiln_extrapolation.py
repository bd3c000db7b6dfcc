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
- against the full run, per period: the bed's mean temperature and the mean
  temperatures of the initially hot and cold halves within 0.05 K, the shell's mean
  within 0.01 K, the heat the shell gives the bed in the period (the bed's heating)
  within 5 %;
- eq. 10 within the seed's 5 %;
- eq. 9: regression bounds, on 200 Voronoi cells (1.5 particles each: single
  particles, as in the drum's quick test) 10 K, on 12 cells of 25 particles 3.5 K.  The
  seed's Table 5 (eps_abs <= 0.25 K, eps_rel <= 3.1 %, with 400 particles per cell) is
  not reached: measured at t2, t3, t4 on 200 cells 4.1, 5.7, 7.6 K (eps_rel 21, 28,
  38 % of T_hot - T_cold = 20 K), on 12 cells 1.1, 1.6, 2.5 K.  With k = 2 W/(m K) a
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


@pytest.fixture(scope="module")
def kiln(tmp_path_factory):
    out = tmp_path_factory.mktemp("kiln")
    case = kiln_case(kiln_geometry(300), settle=0.5, spin_up=0.25, period_turns=0.25,
                     periods=20, compare_periods=3)
    case.output.pictures = False
    runner = Runner(case, out=out, pictures=False, verbose=False)
    res = runner.run()
    csv = np.genfromtxt(out / "extrapolation.csv", delimiter=",", names=True)
    return runner, res, csv, ContactLog.load(out / "contact_log.npz")


def test_the_kiln_is_the_drum_family_cascading(kiln):
    runner, res, csv, log = kiln
    g = kiln_geometry(300)
    assert g.regime == "cascading" and g.period == pytest.approx(2.0)
    assert res.n_particles == 300 and res.n_lost == 0
    assert log.period == pytest.approx(0.5) and len(csv) == 21
    # the FE wall's contacts are in the log, with their triangles
    fe_wall = runner.sim.wall_slot(runner.structures[0].wall)
    rows = log.pw_wall == fe_wall
    assert rows.sum() > 100
    assert log.pw_tri[rows].min() >= 0
    assert log.pw_tri[rows].max() < len(runner.structures[0].interface.triangles)


def test_replay_balances_bed_shell_and_outer_heat_to_round_off(kiln):
    _, res, csv, _ = kiln
    E = csv["E_particles_extra"] + csv["E_structure_extra"] - csv["Q_boundary_extra"]
    assert np.abs(E - E[0]).max() < 1e-12 * abs(E[0])
    assert res.summary["energy_balance_rel"] < 1e-12
    # heat did flow: the shell heated the bed, the jacket re-heated the shell
    assert csv["Q_wall_extra"][1:].min() > 0
    assert csv["T_mean_extra"][-1] > csv["T_mean_extra"][0] + 0.5
    assert csv["Q_boundary_extra"][-1] > 0


def test_replay_follows_the_full_dem_fe_run(kiln):
    _, res, csv, _ = kiln
    live = ~np.isnan(csv["T_mean_dem"])
    assert live.sum() == 4
    for a, b, tol in (("T_mean_extra", "T_mean_dem", 0.05), ("T_hot_extra", "T_hot_dem", 0.05),
                      ("T_cold_extra", "T_cold_dem", 0.05),
                      ("T_wall_mean_extra", "T_wall_mean_dem", 0.01)):
        assert np.abs(csv[a][live] - csv[b][live]).max() < tol, a
    # the heat the bed took in each period, extrapolated against full run
    C = csv["E_particles_extra"][0] / csv["T_mean_extra"][0]
    gain_dem = np.diff(csv["T_mean_dem"][live]) * C
    gain_ext = np.diff(csv["E_particles_extra"][live])
    assert np.abs(gain_ext / gain_dem - 1).max() < 0.05
    # eq. 10
    assert np.nanmax(np.abs(csv["energy_error"])) < 0.05
    # eq. 9 on 200 cells: single particles (a regression bound, see the docstring)
    assert np.nanmax(csv["eps_abs"]) < 10.0


def test_eq9_on_cells_of_25_particles(kiln):
    runner, _, csv, log = kiln
    xp = runner.extrapolation
    hot = xp.hot[log.ids]
    seeds = voronoi_seeds(log.x1, 12, seed=0)
    errs = []
    for n in range(1, 4):
        ea, er, used = cell_error(seeds, xp.dem_x[n], xp.dem_T[n], xp.res["x"][n],
                                  xp.res["T"][n], hot=hot)
        errs.append(ea)
        assert used == 12
    assert max(errs) < 3.5


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
