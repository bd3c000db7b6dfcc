"""gsi.extrapolation: the pairing of eq. 6 (seed 003), the replay of Algorithm 3 with
eqs. 7-8 against a plain loop, its stability handling and conservation, and the error
measures of eqs. 9-10."""
import itertools

import numpy as np
import pytest

from gsi.dem.contact_log import ContactLog
from gsi.errors import GsiInputError
from gsi.extrapolation import (Replay, cell_error, cell_means, cell_sampling_level,
                               energy_transfer_error,
                               pair_particles, pairing_cost, voronoi_seeds)


def test_dense_pairing_is_the_optimum_of_all_permutations():
    rng = np.random.default_rng(3)
    for _ in range(5):
        x0 = rng.uniform(0, 1, (7, 3))
        x1 = rng.uniform(0, 1, (7, 3))
        best = min(pairing_cost(x0, x1, np.array(p)) for p in itertools.permutations(range(7)))
        sigma = pair_particles(x0, x1, method="dense")
        assert pairing_cost(x0, x1, sigma) == pytest.approx(best, rel=1e-12)


def test_sparse_pairing_matches_dense():
    """A bed shifted by a rigid step and jittered: the k-nearest restriction finds the
    dense optimum."""
    rng = np.random.default_rng(5)
    g = np.stack(np.meshgrid(*[np.arange(8)] * 3, indexing="ij"), -1).reshape(-1, 3) * 0.01
    x0 = g + rng.normal(0, 0.002, g.shape)
    x1 = g[rng.permutation(len(g))] + rng.normal(0, 0.002, g.shape) + [0.004, 0, 0]
    dense = pair_particles(x0, x1, method="dense")
    sparse = pair_particles(x0, x1, method="sparse", k=4)
    assert pairing_cost(x0, x1, sparse) == pytest.approx(pairing_cost(x0, x1, dense), rel=1e-12)
    assert np.array_equal(np.sort(sparse), np.arange(len(g)))


def test_sparse_pairing_when_the_bed_changes_shape():
    """The t1 positions fill half the width of the t0 box: the graph of each particle's
    k nearest t1 positions has no perfect matching (Hopcroft-Karp matches 132-149 of
    200), and the optimum is far from every particle's nearest positions; the auction's
    graph is grown by the check on all pairs (more than one round) and reaches the
    dense optimum."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import maximum_bipartite_matching
    from scipy.spatial import cKDTree
    n, k = 200, 2
    for seed in range(3):
        rng = np.random.default_rng(seed)
        x0 = rng.uniform(0, 1, (n, 3))
        x1 = rng.uniform(0, 1, (n, 3)) * [0.5, 1, 1] + [0.25, 0, 0]
        _, j = cKDTree(x1).query(x0, k=k)
        one_way = csr_matrix((np.ones(k * n), (np.repeat(np.arange(n), k), j.reshape(-1))),
                             shape=(n, n))
        assert (maximum_bipartite_matching(one_way, perm_type="column") < 0).any()
        dense = pair_particles(x0, x1, method="dense")
        info = {}
        sparse = pair_particles(x0, x1, method="sparse", k=k, info=info)
        assert info["rounds"] > 1
        assert np.array_equal(np.sort(sparse), np.arange(n))
        best = pairing_cost(x0, x1, dense)
        assert 0 < info["gap_bound"] < 1e-12 * best
        assert pairing_cost(x0, x1, sparse) == pytest.approx(best, rel=1e-12)


def test_sparse_pairing_of_a_bed_that_flowed():
    """1,500 particles of a bed whose top two layers heaped up to one side (a drum's
    surface after a turn): the first graph's auction breaks eps-CS somewhere (more than
    one round), and the grown graph's summed distance equals the dense optimum's."""
    rng = np.random.default_rng(7)
    g = np.stack(np.meshgrid(np.arange(20), np.arange(15), np.arange(5), indexing="ij"),
                 -1).reshape(-1, 3) * 0.01
    x0 = g + rng.normal(0, 0.001, g.shape)
    top = g[:, 2] >= 0.03
    x1 = g.astype(float).copy()
    x1[top, 2] += 0.02 * (g[top, 0] / 0.19 - 0.5)     # a wedge instead of a flat layer
    x1 = x1[rng.permutation(len(g))] + rng.normal(0, 0.001, g.shape)
    dense = pairing_cost(x0, x1, pair_particles(x0, x1, method="dense"))
    info = {}
    sparse = pair_particles(x0, x1, method="sparse", k=4, info=info)
    assert info["rounds"] > 1
    assert np.array_equal(np.sort(sparse), np.arange(len(g)))
    assert pairing_cost(x0, x1, sparse) == pytest.approx(dense, rel=1e-12)


def fake_log(rng, n=40, rows=3000, *, dur=5, dt=1e-4, C=1.0, walls=False):
    """A ContactLog with random pairs (random order of starts), sizes and capacities."""
    i = rng.integers(0, n, rows)
    j = (i + rng.integers(1, n, rows)) % n
    lo, hi = np.minimum(i, j), np.maximum(i, j)
    start = np.sort(rng.integers(0, 2000, rows)).astype(np.int32)
    nw = 5 if walls else 0
    pw = rng.integers(0, n, nw)
    return ContactLog(
        pp_i=lo.astype(np.int32), pp_j=hi.astype(np.int32), pp_start=start,
        pp_dur=np.full(rows, dur, np.uint16),
        pp_size=rng.uniform(1e-4, 1e-3, rows).astype(np.float32),
        pw_i=pw.astype(np.int32), pw_wall=np.array([0, 1, 0, 1, 0][:nw], np.int16),
        pw_tri=np.full(nw, -1, np.int32),
        pw_start=np.sort(rng.integers(0, 2000, nw)).astype(np.int32),
        pw_dur=np.full(nw, dur, np.uint16), pw_size=np.full(nw, 5e-4, np.float32),
        ids=np.arange(n), x0=rng.uniform(0, 1, (n, 3)), x1=rng.uniform(0, 1, (n, 3)),
        T0=rng.uniform(10, 30, n), T1=rng.uniform(10, 30, n),
        heat_capacity=C * rng.uniform(0.8, 1.2, n), type=np.zeros(n, np.int32),
        coef=np.array([[200.0, 150.0], [150.0, 100.0]]), wall_type=np.array([1, 1], np.int32),
        wall_T=np.array([50.0, 0.0]), wall_has_T=np.array([True, False]), dt=dt, t0=0.0,
        t1=0.2, every=1, split=dur, model="area", samples=2000)


def loop_replay(log, sigma, periods, T):
    """eqs. 7-8 row by row, particles k = sigma^p(a), l = sigma^p(b), walls after the
    pairs of the same start (the order Replay documents: by start, pairs first)."""
    T = T.copy()
    C = log.heat_capacity
    rows = [(s, 0, r) for r, s in enumerate(log.pp_start)]
    rows += [(s, 1, r) for r, s in enumerate(log.pw_start) if log.wall_has_T[log.pw_wall[r]]]
    rows.sort(key=lambda t: (t[0], t[1]))
    role = np.arange(log.n_particles)
    out = [T.copy()]
    for _ in range(periods):
        role = role[sigma]
        for _, kind, r in rows:
            if kind == 0:
                k, l = role[log.pp_i[r]], role[log.pp_j[r]]
                H = log.coef[0, 0] * float(log.pp_size[r])
                Q = H * (T[k] - T[l])
                m = log.pp_dur[r] * log.dt
                T[k], T[l] = T[k] - Q * m / C[k], T[l] + Q * m / C[l]
            else:
                k = role[log.pw_i[r]]
                H = log.coef[0, 1] * float(log.pw_size[r])
                T[k] += H * log.pw_dur[r] * log.dt * (log.wall_T[log.pw_wall[r]] - T[k]) / C[k]
        out.append(T.copy())
    return np.array(out)


def test_replay_is_eqs_7_8_through_the_pairing():
    rng = np.random.default_rng(11)
    log = fake_log(rng, walls=True)
    sigma = rng.permutation(log.n_particles)
    rep = Replay(log, sigma=sigma)
    res = rep.run(3, positions=True)
    want = loop_replay(log, sigma, 3, log.T1)
    np.testing.assert_allclose(res["T"], want, rtol=1e-13, atol=0)
    assert rep.n_rows == len(log.pp_i) + 3          # the adiabatic wall's rows dropped
    # positions: particle sigma^p(a) stands at x1[a] at t_{p+1}
    role = np.arange(log.n_particles)
    for p in range(1, 4):
        role = role[sigma]
        np.testing.assert_array_equal(res["x"][p][role], log.x1)
    np.testing.assert_array_equal(res["x"], rep.positions(3))
    np.testing.assert_allclose(res["time"], [0.2, 0.4, 0.6, 0.8])


def test_replay_conserves_heat_to_round_off():
    rng = np.random.default_rng(2)
    log = fake_log(rng, n=500, rows=50_000, dur=50)
    res = Replay(log).run(50)
    E = res["T"] @ log.heat_capacity
    assert np.abs(E - E[0]).max() <= 1e-12 * abs(E[0])
    assert res["T"][-1].std() < 0.1 * res["T"][0].std()          # it did mix


def test_unstable_rows_are_substepped_or_refused():
    rng = np.random.default_rng(4)
    # C = 1e-3 J/K: m H/C = 5e-4 s x 200 W/(m K) x ~5e-4 m / 1e-3 J/K ~ 0.05 ... x 100
    log = fake_log(rng, n=20, rows=200, dur=500, C=1e-3)
    with pytest.raises(GsiInputError, match="stability bound m < C/H.*dt_split <"):
        Replay(log, sigma=np.arange(20), on_unstable="error")
    rep = Replay(log, sigma=np.arange(20))
    assert rep.max_stability_ratio > 1 and rep.n_substepped > 0
    T = rep.run(1)["T"][1]
    # the same rows cut by hand into s equal sub-steps
    want = log.T1.copy()
    C = log.heat_capacity
    for r in range(len(log.pp_i)):
        a, b = log.pp_i[r], log.pp_j[r]
        w = log.pp_dur[r] * log.dt * 200.0 * float(log.pp_size[r])
        ratio = w / min(C[a], C[b])
        s = int(np.floor(ratio)) + 1 if ratio >= 1 else 1
        for _ in range(s):
            q = w / s * (want[a] - want[b])
            want[a] -= q / C[a]
            want[b] += q / C[b]
    np.testing.assert_allclose(T, want, rtol=1e-12)
    assert np.isfinite(T).all() and T.min() >= log.T1.min() - 1e-9 and \
        T.max() <= log.T1.max() + 1e-9                 # no overshoot: each step is monotone
    with pytest.raises(GsiInputError, match="permutation"):
        Replay(log, sigma=np.zeros(20, int))


def test_cell_error_and_energy_transfer_error():
    seeds = np.array([[0.0, 0, 0], [1.0, 0, 0]])
    x = np.array([[0.1, 0, 0], [-0.1, 0, 0], [0.9, 0, 0], [5.0, 0, 0]])
    means, counts = cell_means(seeds, x, [1.0, 3.0, 10.0, 20.0])
    np.testing.assert_allclose(means, [2.0, 15.0])
    np.testing.assert_array_equal(counts, [2, 2])
    # DEM: cell 0 mean 2, cell 1 mean 15; extrapolated: cell 0 mean 3, cell 1 empty
    ea, er, used = cell_error(seeds, x, np.array([1.0, 3.0, 10.0, 20.0]),
                              np.array([[0.0, 0, 0]]), np.array([3.0]),
                              hot=np.array([True, True, False, False]))
    assert (ea, used) == (1.0, 1)
    assert er == pytest.approx(1.0 / 13.0)
    e = energy_transfer_error(np.array([0.0, 10.0]), np.array([4.0, 6.0]),
                              np.array([0.0, 10.0]), np.array([3.0, 7.0]))
    assert e == pytest.approx((8.0 - 6.0) / 8.0)
    s = voronoi_seeds(np.arange(30.0).reshape(10, 3), 4, seed=1)
    assert len({tuple(p) for p in s}) == 4
    with pytest.raises(GsiInputError, match="more than the 10 particles"):
        voronoi_seeds(np.zeros((10, 3)), 11)


def test_cell_sampling_level_is_the_error_of_independent_samples():
    """Two fields drawn independently from the same temperature field (a left-right ramp
    with a particle-scale scatter) differ on the cells by the sampling level; the same
    particles differ by nothing, and a bias adds on top of the level."""
    rng = np.random.default_rng(3)
    n = 40_000

    def draw():
        x = rng.random((n, 3))
        return x, 20.0 * x[:, 0] + rng.normal(0.0, 4.0, n)

    x_d, T_d = draw()
    x_e, T_e = draw()
    seeds = voronoi_seeds(x_d, 200, seed=0)
    level = cell_sampling_level(seeds, x_d, T_d, x_e, T_e)
    # a cell holds ~200 particles with s >= 4 K (the scatter; the ramp adds ~2 K across a
    # cell of volume 1/200): the level sqrt(2/pi) s sqrt(2/200) is 0.32-0.42 K
    assert 0.32 < level < 0.42
    eps = cell_error(seeds, x_d, T_d, x_e, T_e)[0]
    assert eps == pytest.approx(level, rel=0.1)
    assert cell_error(seeds, x_d, T_d, x_d, T_d)[0] == 0.0
    assert cell_sampling_level(seeds, x_d, T_d, x_d, T_d) == pytest.approx(level, rel=0.1)
    assert np.isnan(cell_sampling_level(x_d[:5], x_d[:5], T_d[:5], x_e[:5], T_e[:5]))
    biased = cell_error(seeds, x_d, T_d, x_e, T_e + 1.0)[0]
    assert biased == pytest.approx(1.0, abs=0.1) and biased > 2.5 * level


def test_twin_dem_moves_the_positions_at_t1_and_diverges():
    """compare_with_dem(twin=a) restarts the DEM at t1 with the positions moved by up to
    a: with a = 1 um in a small turning drum the two runs part (eq. 9 > 0 between them),
    but far less than the extrapolation does from the DEM over the same periods."""
    from gsi.studies.drum import drum_geometry, prepare
    from gsi.extrapolation import compare_with_dem
    g = drum_geometry(200)
    sim, hot, _ = prepare(g, spin_up=0.05)
    steps = int(round(0.05 * g.steps_per_turn))
    r = compare_with_dem(sim, period_steps=steps, periods=2, samplings=((10, None),),
                         hot=hot, cells=20, twin=1e-6)
    tw = r["dem"]["twin"]
    assert tw["amplitude"] == 1e-6 and tw["eps_abs"].shape == (2,)
    assert (tw["eps_abs"] > 0).all() and np.isfinite(tw["eps_level"]).all()
    assert tw["eps_abs"].max() < r["runs"][0]["eps_abs"].max()
