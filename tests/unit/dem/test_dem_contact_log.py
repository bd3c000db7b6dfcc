"""The contact log (gsi.dem.contact_log): its rows against the contacts of every step of
an unlogged twin run, the splitting of Algorithm 2 (seed 003), sampling every n steps,
wall and triangle ids, bit-identical trajectories with the log on, growth, the file."""
import math

import numpy as np
import pytest

from gsi.dem import Material, Simulation
from gsi.dem.contact_log import ContactLog
from gsi.errors import GsiInputError, GsiRunError

R = 0.005
DT = 1e-4
STEPS = 600
# the drum's law combination (Hertz, rolling resistance, the "area" model): one more
# compiled engine for the log variant only
MATS = {"grain": Material(E=1e7, nu=0.3, rho=2500.0, e=0.2, mu=0.3, mu_r=0.002, k=100.0,
                          cp=840.0),
        "wall": Material(E=1e7, nu=0.3, rho=2500.0, e=0.2, mu=0.5, mu_r=0.002, k=50.0,
                         cp=840.0)}


def make_sim():
    """24 spheres thrown into a box: a mesh floor (32 triangles), two plane sides with a
    temperature and two adiabatic ones."""
    sim = Simulation(MATS, contact="hertz", rolling=True, heat="area", dt=DT, skin=0.4 * R,
                     domain=((-0.05, -0.05, -0.01), (0.05, 0.05, 0.2)), seed=1)
    rng = np.random.default_rng(7)
    g = np.stack(np.meshgrid(np.arange(4), np.arange(3), np.arange(2), indexing="ij"),
                 -1).reshape(-1, 3)
    x = (g - [1.5, 1.0, 0.0]) * 2.3 * R + [0.0, 0.0, 1.2 * R] \
        + rng.uniform(-0.1, 0.1, (len(g), 3)) * R
    v = rng.uniform(-0.3, 0.3, (len(g), 3))
    sim.add_particles(x, R, material="grain", v=v, T=rng.uniform(10.0, 30.0, len(g)))
    sim.add_plane((-0.022, 0, 0), (1, 0, 0), material="wall", temperature=40.0)
    sim.add_plane((0.022, 0, 0), (-1, 0, 0), material="wall")
    sim.add_plane((0, -0.018, 0), (0, 1, 0), material="wall", temperature=5.0)
    sim.add_plane((0, 0.018, 0), (0, -1, 0), material="wall")
    from gsi.dem.shapes import plate
    V, T = plate(centre=(0, 0, 0), edge_u=(0.06, 0, 0), edge_v=(0, 0.06, 0), n_u=4, n_v=4)
    sim.add_mesh_wall(V, T, material="wall")
    return sim


def contacts_now(sim):
    """{key: size} of the contacts of the last force pass, computed here from the state:
    key (i, j) for pairs (ids, i < j), (i, "plane", p), (i, "tri", t)."""
    out = {}
    P, pairs, pl, M, wc = sim.bundles()
    x, r, ids = P.x, P.radius, P.id
    for i in range(sim.n):
        for k in range(pairs.start[i], pairs.start[i + 1]):
            if not pairs.active[k]:
                continue
            j = pairs.j[k]
            L2 = float(((x[j] - x[i]) ** 2).sum())
            s = (r[i] ** 2 - r[j] ** 2 + L2) / (2 * math.sqrt(L2))
            a2 = r[i] ** 2 - s * s
            out[(min(ids[i], ids[j]), max(ids[i], ids[j]))] = math.sqrt(math.pi * a2)
        for p in range(len(pl.point)):
            if (int(wc.plane_mask[i]) >> p) & 1:
                delta = r[i] - float((x[i] - pl.point[p]) @ pl.normal[p])
                out[(ids[i], "plane", p)] = math.sqrt(math.pi * (2 * r[i] * delta - delta ** 2))
        for s_ in range(wc.count[i]):
            delta = r[i] - float(np.linalg.norm(wc.point[i, s_] - x[i]))
            out[(ids[i], "tri", int(wc.tri[i, s_]))] = math.sqrt(
                math.pi * (2 * r[i] * delta - delta ** 2))
    return out


@pytest.fixture(scope="module")
def reference():
    """The unlogged twin: the contacts after each of STEPS single steps, and its end."""
    sim = make_sim()
    sim.step(5)                       # t0 is not the start
    per_step = []
    for _ in range(STEPS):
        sim.step(1)
        per_step.append(contacts_now(sim))
    return per_step, sim


def expected_rows(per_step, every, split):
    """Rows by run lengths: a contact seen in consecutive samples (steps every, 2 every,
    ... after t0) is one run, cut into chunks of ``split`` samples (None: whole); a chunk
    starts ``every`` steps before its first sample and lasts samples x every steps."""
    samples = per_step[every - 1::every]
    keys = sorted({k for s in samples for k in s}, key=repr)
    rows = []
    for key in keys:
        seen = [m for m, s in enumerate(samples) if key in s]
        runs, run = [], [seen[0]]
        for m in seen[1:]:
            if m == run[-1] + 1:
                run.append(m)
            else:
                runs.append(run)
                run = [m]
        runs.append(run)
        for run in runs:
            step = split or len(run)
            for c in range(0, len(run), step):
                chunk = run[c:c + step]
                size = float(np.mean([samples[m][key] for m in chunk]))
                rows.append((key, chunk[0] * every, len(chunk) * every, size))
    return rows


def log_rows(log):
    """The log's rows as (key, start, duration, size) with the keys of contacts_now."""
    rows = [((int(log.ids[i]), int(log.ids[j])), int(s), int(d), float(z))
            for i, j, s, d, z in zip(log.pp_i, log.pp_j, log.pp_start, log.pp_dur,
                                     log.pp_size)]
    for i, w, t, s, d, z in zip(log.pw_i, log.pw_wall, log.pw_tri, log.pw_start, log.pw_dur,
                                log.pw_size):
        key = (int(log.ids[i]), "plane", int(w)) if t < 0 else (int(log.ids[i]), "tri", int(t))
        if t >= 0:
            assert w == 4                    # the mesh floor: after the four planes
        rows.append((key, int(s), int(d), float(z)))
    return rows


def run_logged(every, dt_split, capacity=None):
    sim = make_sim()
    sim.step(5)
    sim.start_contact_log(every=every, dt_split=dt_split, capacity=capacity)
    sim.step(STEPS // 2)
    sim.step(STEPS - STEPS // 2)
    return sim.stop_contact_log(), sim


@pytest.mark.parametrize("every,dt_split", [(1, None), (1, 3 * DT), (4, 8 * DT), (5, None)])
def test_rows_are_the_contacts_of_every_sample(reference, every, dt_split):
    per_step, ref = reference
    log, sim = run_logged(every, dt_split)
    # the log does not change the trajectory, bit for bit
    for name in ("x", "v", "omega", "T"):
        assert np.array_equal(getattr(sim, name), getattr(ref, name)), name
    split = None if dt_split is None else int(round(dt_split / (every * DT)))
    want = sorted(expected_rows(per_step, every, split), key=lambda r: (r[1], repr(r[0])))
    got = sorted(log_rows(log), key=lambda r: (r[1], repr(r[0])))
    assert [r[:3] for r in got] == [r[:3] for r in want]
    np.testing.assert_allclose([r[3] for r in got], [r[3] for r in want], rtol=1e-6)
    kinds = {r[0][1] if isinstance(r[0][1], str) else "pair" for r in got}
    assert kinds == {"pair", "plane", "tri"}
    # rows in order of start; the scalars
    assert np.all(np.diff(log.pp_start) >= 0) and np.all(np.diff(log.pw_start) >= 0)
    assert (log.every, log.split, log.samples) == (every, 0 if split is None else split * every,
                                                   STEPS // every)
    assert log.t0 == pytest.approx(5 * DT) and log.t1 == pytest.approx((5 + STEPS) * DT)
    if split:
        assert log.pp_dur.max() <= split * every
    np.testing.assert_array_equal(log.wall_has_T, [True, False, True, False, False])
    np.testing.assert_array_equal(log.wall_T[:4], [40.0, 0.0, 5.0, 0.0])


def test_growing_log_gives_the_same_rows():
    small, _ = run_logged(1, 2 * DT, capacity=1)        # grows at nearly every sample
    big, _ = run_logged(1, 2 * DT)
    for k in ContactLog.ROWS:
        assert np.array_equal(getattr(small, k), getattr(big, k)), k


def test_file_round_trip(tmp_path):
    log, _ = run_logged(2, 6 * DT)
    size = log.save(tmp_path / "log.npz")
    back = ContactLog.load(tmp_path / "log.npz")
    for k in ContactLog.ROWS + ContactLog.PARTICLES + ContactLog.WALLS:
        assert np.array_equal(getattr(back, k), getattr(log, k)), k
    assert (back.dt, back.every, back.split, back.model) == (DT, 2, 6, "area")
    n_pp, n_pw = len(log.pp_i), len(log.pw_i)
    assert log.row_bytes() == 18 * n_pp + 20 * n_pw
    assert size > log.row_bytes()
    (tmp_path / "bad.npz").write_bytes(b"not a file")
    with pytest.raises(GsiInputError, match="contact log file"):
        ContactLog.load(tmp_path / "bad.npz")


def test_bad_calls():
    sim = make_sim()
    with pytest.raises(GsiInputError, match="every = 0"):
        sim.start_contact_log(every=0)
    with pytest.raises(GsiInputError, match="dt_split = 0.00025: must be a positive multiple"):
        sim.start_contact_log(every=1, dt_split=2.5 * DT)
    with pytest.raises(GsiInputError, match="no contact log is running"):
        sim.stop_contact_log()
    state = sim.state()
    sim.start_contact_log(every=1)
    with pytest.raises(GsiInputError, match="already running"):
        sim.start_contact_log(every=1)
    with pytest.raises(GsiInputError, match="set_state: a contact log is running"):
        sim.set_state(state)
    sim.step(3)
    sim.add_particles([[0.0, 0.0, 0.1]], R, material="grain")
    sim.step(3)
    with pytest.raises(GsiRunError, match="inserted or lost"):
        sim.stop_contact_log()
    assert not sim.contact_logging
