"""Neighbour lists against brute force; contact history survives rebuilds and deletions."""
import numpy as np
import pytest

from gsi.dem import Box, Material, Simulation, random_fill

MAT = {"m": Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.9)}


def test_half_list_equals_brute_force():
    L = 0.018
    sim = Simulation(MAT, gravity=(0, 0, 0), dt=2e-6, skin=3e-4, domain=((0, 0, 0), (L, L, L)))
    rng = np.random.default_rng(0)
    x, r = random_fill(Box((0, 0, 0), (L, L, L)), 1e-3, count=220, rng=rng)
    sim.add_particles(x, r * rng.uniform(0.8, 1.0, len(r)), material="m",
                      v=rng.normal(0, 0.5, x.shape))
    sim.step(200)
    nb_start, nb_j = sim.pairs.start, sim.pairs.j
    got = [(i, int(j)) for i in range(sim.n) for j in nb_j[nb_start[i]:nb_start[i + 1]]]
    assert len(got) == len(set(got))                  # each pair once
    got = {(min(i, j), max(i, j)) for i, j in got}
    x0, r = sim.particles.x0, sim.radius      # the list is built at x0
    d = np.linalg.norm(x0[:, None] - x0[None], axis=2)
    want = {(i, j) for i in range(sim.n) for j in range(i + 1, sim.n)
            if d[i, j] < r[i] + r[j] + sim.skin}
    assert sim.n_rebuilds > 1
    assert got == want and len(want) > 40


@pytest.mark.parametrize("sort", [False, True])
def test_history_survives_rebuild_and_deletion(sort):
    """Sheared touching pairs build springs; deleting an idle particle (rows shift) and
    rebuilding keeps every spring attached to the same pair of ids (also when the rows
    are re-ordered at each build)."""
    R, d = 1e-3, 2e-5
    L = 0.05
    sim = Simulation(MAT, gravity=(0, 0, 0), dt=2e-6, skin=3e-4, domain=((0, 0, 0), (L, L, L)),
                     sort_particles=sort)
    x, v = [], []
    for k in range(20):
        base = np.array([0.004 + 0.006 * (k % 5), 0.01 + 0.008 * (k // 5), 0.02])
        x += [base + [0, 0, 0.005], base, base + [2 * R - d, 0, 0]]   # idle one first
        v += [[0, 0, 0], [0, 0.01, 0], [0, -0.01, 0.0]]
    sim.add_particles(np.array(x), R, material="m", v=np.array(v))
    sim.step(50)
    assert (np.all(np.diff(sim.ids) > 0)) != sort      # sorted rows: ids out of order

    def springs():
        pr = sim.pairs
        nb_start, nb_j, hist, pact = pr.start, pr.j, pr.hist, pr.active
        ids = sim.ids
        return {(int(ids[i]), int(ids[nb_j[k]])): hist[k].copy()
                for i in range(sim.n) for k in range(nb_start[i], nb_start[i + 1]) if pact[k]}

    before = springs()
    assert len(before) == 20 and all(np.abs(h).max() > 0 for h in before.values())
    rb = sim.n_rebuilds
    sim.remove_particles(np.isin(sim.ids, [0, 3, 30]))     # three idle particles
    sim.rebuild_lists()
    after = springs()
    assert sim.n_rebuilds == rb + 1
    assert set(after) == set(before)
    for key, h in before.items():
        np.testing.assert_array_equal(after[key], h)


def test_sorted_rows_give_the_same_motion():
    """``sort_particles``: rows re-ordered at every build into the force pass's visiting
    order; the motion of each particle id is the unsorted one to round-off, and ids
    still find their rows (index, fix)."""
    def run(sort):
        L = 0.03
        sim = Simulation(MAT, gravity=(0, 0, -9.81), dt=2e-6, skin=3e-4,
                         domain=((0, 0, 0), (L, L, L)), sort_particles=sort)
        rng = np.random.default_rng(4)
        x, r = random_fill(Box((0, 0, 0), (L, L, 0.02)), 1e-3, count=900, rng=rng)
        ids = sim.add_particles(x, r, material="m", v=rng.normal(0, 1.0, x.shape))
        sim.add_plane((0, 0, 0), (0, 0, 1), material="m")
        sim.fix(ids[:5])
        sim.step(2000)
        return sim, x[:5]

    a, x_fixed = run(False)
    b, _ = run(True)
    assert a.n_lost == b.n_lost and np.array_equal(np.sort(b.ids), a.ids)
    ids = a.ids
    ra, rb = a.index(ids), b.index(ids)
    assert np.all(b.ids[rb] == ids) and not np.all(rb == ra)
    assert a.n_rebuilds == b.n_rebuilds > 3 and a.contact_count() == b.contact_count() > 50
    np.testing.assert_allclose(b.x[rb], a.x[ra], rtol=0, atol=1e-12)
    np.testing.assert_allclose(b.v[rb], a.v[ra], rtol=0, atol=1e-9 * np.abs(a.v).max())
    np.testing.assert_allclose(b.planes[0].force, a.planes[0].force, rtol=1e-9)
    np.testing.assert_array_equal(b.x[b.index(np.arange(5))], x_fixed)     # fixed by id


def test_slab_layout_is_wide_enough_and_splits_evenly_over_threads():
    from gsi.dem.neighbour import slab_layout
    coord = np.random.default_rng(1).uniform(0.0, 0.084, 5000)
    for threads, expect in [(1, 34), (2, 32), (4, 32), (8, 32), (32, 34)]:
        lo, inv_w, nslab = slab_layout(coord, 2.4e-3, threads)
        assert nslab == expect
        assert 1.0 / inv_w >= 2.4e-3
        s = np.floor((coord - lo) * inv_w)
        assert s.min() == 0 and s.max() == nslab - 1
    assert slab_layout(np.array([0.01]), 2.4e-3, 2)[2] == 1
    # a serial run of a small system: one slab per MIN_SLAB_PARTICLES particles at most
    # (a slab task's fixed cost), still a multiple of two
    assert slab_layout(coord[:1000], 2.4e-3, 1, min_per_slab=256)[2] == 2
    assert slab_layout(coord[:300], 2.4e-3, 1, min_per_slab=256)[2] == 1
    assert slab_layout(coord, 2.4e-3, 1, min_per_slab=256)[2] == 18


def test_pairs_are_stored_in_the_lower_of_two_adjacent_slabs():
    """The race-free force pass needs every pair within one slab or two adjacent ones,
    stored at the particle of the lower slab."""
    L = 0.03
    sim = Simulation(MAT, gravity=(0, 0, -9.81), dt=2e-6, skin=3e-4, domain=((0, 0, 0), (L, L, L)),
                     parallel_min_n=10)
    rng = np.random.default_rng(2)
    x, r = random_fill(Box((0, 0, 0), (L, L, 0.02)), 1e-3, count=600, rng=rng)
    sim.add_particles(x, r, material="m")
    sim.step(20)
    pr = sim.pairs
    slab_start, slab_list, nb_start, nb_j = pr.slab_start, pr.slab_list, pr.start, pr.j
    nslab = len(slab_start) - 1
    assert nslab >= 4 and nslab % 2 == 0
    slab_of = np.empty(sim.n, int)
    for s in range(nslab):
        slab_of[slab_list[slab_start[s]:slab_start[s + 1]]] = s
    for i in range(sim.n):
        d = slab_of[nb_j[nb_start[i]:nb_start[i + 1]]] - slab_of[i]
        assert np.all((d == 0) | (d == 1))


THREAD_CASE = r"""
import json, sys
import numba
import numpy as np
from gsi.dem import Box, Material, Simulation, random_fill
MAT = {"m": Material(E=5e6, nu=0.3, rho=2500, e=0.5, mu=0.9)}
L = float(sys.argv[1])
out = {}
for threads in (1, 2, 3):
    sim = Simulation(MAT, gravity=(0, 0, -9.81), dt=2e-6, skin=3e-4,
                     domain=((0, 0, 0), (L, L, L)), parallel_min_n=10)
    rng = np.random.default_rng(4)
    x, r = random_fill(Box((0, 0, 0), (L, L, 0.02)), 1e-3, count=900, rng=rng)
    sim.add_particles(x, r, material="m", v=rng.normal(0, 1.0, x.shape))
    sim.add_plane((0, 0, 0), (0, 0, 1), material="m")
    numba.set_num_threads(threads)
    sim.step(2000)
    out[threads] = dict(x=sim.x.tolist(), v=sim.v.tolist(), rebuilds=sim.n_rebuilds,
                        contacts=sim.contact_count(), plane=sim.planes[0].force.tolist(),
                        nslab=len(sim.pairs.slab_start) - 1)
json.dump(out, sys.stdout)
"""


@pytest.mark.parametrize("L, same_layout", [(0.03, True), (0.0355, False)])
def test_threads_give_the_serial_result(L, same_layout):
    """The parallel force-and-integrate pass (two colours of slabs) on 1, 2 and 3
    threads (one subprocess with NUMBA_NUM_THREADS=3, so it never depends on the
    caller's thread count).  With the same slab layout (L = 30 mm: 12 slabs for 1, 2
    and 3 threads) each particle sums its contacts in the same order: bitwise equal.
    When the slab count follows the thread count (L = 35.5 mm: 14 slabs on 1 thread,
    12 on 2 and 3), the summation order differs: equal to round-off."""
    import json
    import os
    import pathlib
    import subprocess
    import sys
    root = pathlib.Path(__file__).resolve().parents[3]
    env = dict(os.environ, NUMBA_NUM_THREADS="3", PYTHONPATH=str(root))
    r = subprocess.run([sys.executable, "-c", THREAD_CASE, str(L)], capture_output=True,
                       text=True, env=env, timeout=900)
    assert r.returncode == 0, r.stderr[-2000:]
    res = {int(k): v for k, v in json.loads(r.stdout.strip().splitlines()[-1]).items()}
    a = res[1]
    assert (len({res[t]["nslab"] for t in (1, 2, 3)}) == 1) == same_layout
    for t in (2, 3):
        b = res[t]
        assert a["rebuilds"] == b["rebuilds"] and a["contacts"] == b["contacts"] > 50
        np.testing.assert_allclose(b["x"], a["x"], rtol=0, atol=1e-12)
        np.testing.assert_allclose(b["v"], a["v"], rtol=0, atol=1e-9 * np.abs(a["v"]).max())
        np.testing.assert_allclose(b["plane"], a["plane"], rtol=1e-9)
        if same_layout:
            assert b["x"] == a["x"] and b["v"] == a["v"] and b["plane"] == a["plane"]


def test_plane_moving_onto_particles_is_seen():
    """A plane moving along its normal (a piston) reaches particles that were far from
    it at the last build: plane motion counts in the rebuild criterion, so the plane
    candidates of the particles are renewed before it arrives."""
    L = 0.05
    sim = Simulation(MAT, gravity=(0, 0, 0), dt=2e-6, skin=3e-4, domain=((0, 0, 0), (L, L, L)))
    sim.add_particles([[0.02, 0.025, 0.025], [0.03, 0.025, 0.025]], 1e-3, material="m")
    piston = sim.add_plane((0.005, 0, 0), (1, 0, 0), material="m", velocity=(1.0, 0, 0))
    sim.step(1)
    assert sim.wall_contacts.plane_cand.tolist() == [0, 0]
    sim.step(9000)                   # the piston moves 18 mm: it meets the first particle
    x_plane = piston.point[0]
    assert x_plane > 0.022
    assert sim.x[0, 0] - x_plane > 0.9e-3          # pushed ahead, never passed through
    assert sim.v[0, 0] > 0.5
    assert sim.n_rebuilds > 5


@pytest.mark.parametrize("short", [False, True])
def test_one_pass_serial_lists_equal_the_two_pass_parallel_ones(short):
    """A small system on one thread builds its pair list in one pass over half the cell
    stencil (:func:`gsi.dem.neighbour.find_pairs_serial`, entries sized from the last
    build); each row holds the same partners as the two-pass list, the same list entry
    by entry once the rows are sorted (``sort_rows``, as the lists do), also when the
    first guess is too short (``short``: the entries grow)."""
    from gsi.dem import cells, neighbour as nbr
    rng = np.random.default_rng(3)
    L, skin = 0.02, 1.5e-3
    lo, hi = np.zeros(3), np.full(3, L)
    x, r = random_fill(Box((0, 0, 0), (L, L, L)), 1e-3, count=400, rng=rng)
    r = r * rng.uniform(0.7, 1.0, len(r))
    n = len(x)
    g_lo, dims, inv_cs = cells.particle_grid(*cells.bounding_box(x), lo, hi, 2 * r.max() + skin, n)
    assert dims.prod() > 27                       # more than one stencil
    cell_of = np.empty(n, np.int64)
    cells.cell_index(n, x, g_lo, inv_cs, dims, cell_of)
    cell_start, cell_list = cells.bin_cells(n, cell_of, int(dims.prod()))
    slab_of, _, _ = nbr.slab_sort(n, x, cell_list, 2, *nbr.slab_layout(x[:, 2], 3e-3, 1))
    counts, two_start = np.empty(n, np.int64), np.zeros(n + 1, np.int64)
    args = (n, x, r, skin, cell_of, slab_of, cell_start, cell_list, dims)
    nbr.find_pairs(*args, counts, two_start, np.empty(0, np.int32), False)
    np.cumsum(counts, out=two_start[1:])
    two_j = np.empty(two_start[-1], np.int32)
    nbr.find_pairs(*args, counts, two_start, two_j, True)
    assert len(two_j) > 500
    one_start = np.zeros(n + 1, np.int64)
    one_j = nbr.find_pairs_serial(n, nbr.cell_ordered(x, r, cell_list), *args[3:], one_start,
                                  7 if short else len(two_j) + 10)
    np.testing.assert_array_equal(one_start, two_start)
    nbr.sort_rows(one_start, one_j)
    nbr.sort_rows(two_start, two_j)
    np.testing.assert_array_equal(one_j, two_j)   # the same rows once sorted
    for i in range(n):
        assert np.all(np.diff(one_j[one_start[i]:one_start[i + 1]]) > 0)


def _folded_sheet(L):
    """A folded sheet of 200 triangles across a box of side L: (vertices, triangles)."""
    g = np.linspace(0, L, 11)
    X, Y = np.meshgrid(g, g, indexing="ij")
    vx = np.column_stack([X.ravel(), Y.ravel(), 0.5 * L + 0.3 * np.abs(X.ravel() - 0.5 * L)])
    k = np.arange(100).reshape(10, 10)
    a, b, c, d = k[:, :] + k[:, :] // 10, k + k // 10 + 1, k + k // 10 + 11, k + k // 10 + 12
    tri = np.vstack([np.column_stack([a.ravel(), b.ravel(), d.ravel()]),
                     np.column_stack([a.ravel(), d.ravel(), c.ravel()])]).astype(np.int64)
    return vx, tri


@pytest.mark.parametrize("grid", ["particles", "domain"])
def test_triangle_candidates_are_exactly_the_triangles_within_reach(grid):
    """near_triangles_by_cell (one pass over the triangles, the particles of the cells
    near each) against the definition, particle by particle: particle i lists triangle t,
    in ascending order, exactly when t is not degenerate and lies closer than R_i + skin
    (a folded sheet, random triangles, a degenerate one; the grid over the particles'
    bounding box as the lists use it, and over the whole domain)."""
    from gsi.dem import cells, neighbour as nbr
    from gsi.dem.geometry import closest_point_triangle
    rng = np.random.default_rng(5)
    L, skin = 0.02, 1.5e-3
    lo, hi = np.full(3, -0.002), np.full(3, L + 0.002)
    x, r = random_fill(Box((0, 0, 0), (L, L, L)), 1e-3, count=300, rng=rng)
    r = r * rng.uniform(0.7, 1.0, len(r))
    n = len(x)
    vx, tri = _folded_sheet(L)
    extra = rng.random((30, 3)) * L
    tri = np.vstack([tri, len(vx) + rng.integers(0, 30, (40, 3)), [[len(vx), len(vx), 1]]])
    vx = np.vstack([vx, extra])
    cut = 2 * r.max() + skin
    if grid == "particles":
        g_lo, dims, inv_cs = cells.particle_grid(*cells.bounding_box(x), lo, hi, cut, n)
    else:
        g_lo, (dims, inv_cs) = lo, cells.grid_for(lo, hi, cut, n)
    cell_of = np.empty(n, np.int64)
    cells.cell_index(n, x, g_lo, inv_cs, dims, cell_of)
    cell_start, cell_list = cells.bin_cells(n, cell_of, int(dims.prod()))
    mc_start, mc_tri = nbr.near_triangles_by_cell(nbr.cell_ordered(x, r, cell_list), skin,
                                                  cell_start, cell_list, g_lo, inv_cs, dims,
                                                  r.max() + skin, vx, tri)
    total = 0
    tv_lo, tv_hi = vx[tri].min(axis=1), vx[tri].max(axis=1)
    for i in range(n):
        want = []
        rc = r[i] + skin           # (a triangle farther along an axis is farther anyway)
        for t in np.flatnonzero(((tv_lo - rc < x[i]) & (x[i] < tv_hi + rc)).all(axis=1)):
            tv = vx[tri[t]]
            if not np.cross(tv[1] - tv[0], tv[2] - tv[0]).any():
                continue                                     # degenerate: never listed
            q = np.array(closest_point_triangle(*x[i], *tv[0], *tv[1], *tv[2])[:3])
            if ((q - x[i]) ** 2).sum() < (r[i] + skin) ** 2:
                want.append(int(t))
        assert mc_tri[mc_start[i]:mc_start[i + 1]].tolist() == want, i
        total += len(want)
    assert mc_start[-1] == total > 100


def test_triangle_bins_are_exactly_the_cells_within_reach():
    """bin_triangles (one pass, a plane pre-test, a counting sort) against its definition,
    cell by cell: a cell lists triangle t, in ascending order, exactly when it is in t's
    bounding box inflated by ``inflate`` and its centre lies within half a cell diagonal
    plus ``inflate`` of t (random meshes, flat sheets and a degenerate triangle)."""
    from gsi.dem import cells, neighbour as nbr
    from gsi.dem.geometry import closest_point_triangle
    rng = np.random.default_rng(7)
    for trial in range(12):
        v = rng.random((20, 3)) * 0.1
        if trial % 3 == 0:
            v[:, 2] = 0.03                                  # a flat sheet
        tri = rng.integers(0, 20, (25, 3)).astype(np.int64)
        tri[0] = [0, 0, 1]                                  # degenerate: a segment
        lo, hi = np.full(3, -0.005), np.full(3, 0.105)
        dims, inv_cs = cells.grid_for(lo, hi, 0.1 * rng.choice([0.1, 0.25]), 100)
        inflate = 0.1 * rng.choice([0.0, 0.02])
        tstart, tlist = nbr.bin_triangles(v, tri, lo, inv_cs, dims, inflate)
        cs = 1.0 / inv_cs
        reach2 = (0.5 * np.sqrt((cs ** 2).sum()) + inflate) ** 2
        for c in range(int(dims.prod())):
            k = np.array(np.unravel_index(c, dims))
            p = lo + (k + 0.5) * cs
            want = []
            for t in range(len(tri)):
                tv = v[tri[t]]
                k_lo = np.maximum(0, np.floor((tv.min(0) - inflate - lo) * inv_cs))
                k_hi = np.minimum(dims - 1, np.floor((tv.max(0) + inflate - lo) * inv_cs))
                q = np.array(closest_point_triangle(*p, *tv[0], *tv[1], *tv[2])[:3])
                # not farther (a degenerate triangle's closest point is NaN: kept)
                if (k_lo <= k).all() and (k <= k_hi).all() and not ((q - p) ** 2).sum() > reach2:
                    want.append(t)
            assert tlist[tstart[c]:tstart[c + 1]].tolist() == want, (trial, c)
