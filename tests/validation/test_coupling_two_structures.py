"""Two coupled structures on one DEM, with different sub-cycles (gsi.coupling.coupled_structure).

Two clamped rubber plates side by side, both from one user .geo script (a DefineConstant
offset x0 places them), carry a few falling spheres each. Plate A is coupled every 5 DEM
steps (P2, generalized-alpha), plate B every 8 (P1, Newmark). A runner-style loop advances
the DEM to the next interval end of either structure and calls begin/finish of each at
its own interval boundaries (interleaved). Checked:

* each structure's invariant of the transfer (nodal loads = minus the time-averaged wall
  force, every interval) holds to round-off;
* each structure receives the impulse it receives when coupled ALONE to a DEM that holds
  only its own spheres (independent run): the other structure's begin/finish does not
  touch this one's accumulators (see the test for why this is 2 % and not round-off);
* interval counts: A has 40, B 25 after 200 DEM steps.
"""
import numpy as np
import pytest
from mpi4py import MPI

from gsi.case.structure import Structure
from gsi.config.schema import load
from gsi.dem import Material, Simulation

GEO = """SetFactory("OpenCASCADE");
DefineConstant[ x0 = {0, Name "Parameters/x0"}, lc = {0.02, Name "Parameters/lc"} ];
Box(1) = {x0, 0, 0, 0.1, 0.1, 0.01};
MeshSize{ PointsOf{ Volume{1}; } } = lc;
Physical Surface("upper") = {6};
Physical Surface("rim") = {1, 2, 3, 4};
Physical Volume("rubber") = {1};
"""
R, DT_STEPS = 0.005, 200
SPHERE = Material(E=1e6, nu=0.3, rho=1000.0, e=0.5, mu=0.5)


def _table(name, x0, degree, scheme, n_sub):
    return dict(name=name, file="plate.geo", geometry=dict(x0=x0),
                tags=dict(support="rim", contact="upper"), material="rubber",
                degree=degree, scheme=scheme, rho_inf=0.5, damping_ratio=0.1,
                contact=dict(tags=["contact"], n_sub=n_sub, e=0.5, mu=0.5))


SPECS = {"A": _table("plate_a", 0.0, 2, "generalized_alpha", 5),
         "B": _table("plate_b", 0.15, 1, "newmark", 8)}


def _spheres(x0):
    return np.array([[x0 + 0.03, 0.05, 0.01 + 1.2 * R], [x0 + 0.07, 0.05, 0.01 + 1.5 * R]])


def _run(names, base_dir):
    comm = MPI.COMM_WORLD
    dt = 2e-4
    sts = {k: load(Structure, SPECS[k], f"structures[{i}]") for i, k in enumerate(names)}
    css = {k: st.build(comm=comm, dt_dem=dt, base_dir=base_dir) for k, st in sts.items()}
    mats = {"ball": SPHERE}
    for st in sts.values():
        n, m = st.dem_wall_material(mats)
        mats[n] = m
    sim = Simulation(mats, dt=dt, skin=0.002, gravity=(0, 0, -9.81),
                     domain=((-0.05, -0.05, -0.05), (0.3, 0.15, 0.1)))
    for k in names:
        sim.add_particles(_spheres(SPECS[k]["geometry"]["x0"]), R, material="ball")
    for cs in css.values():
        cs.attach(sim)
    # the runner's loop: begin at each interval start, finish after exactly n_sub steps
    start = {k: 0 for k in names}
    for cs in css.values():
        cs.begin()
    step = 0
    while step < DT_STEPS:
        nxt = min(start[k] + css[k].n_sub for k in names)
        sim.step(nxt - step)
        step = nxt
        for k in names:
            if start[k] + css[k].n_sub == step:
                css[k].finish()
                start[k] = step
                if step < DT_STEPS:
                    css[k].begin()
    return css


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    d = tmp_path_factory.mktemp("two")
    (d / "plate.geo").write_text(GEO)
    return _run(["A", "B"], d), {k: _run([k], d)[k] for k in ("A", "B")}


def test_each_structure_keeps_its_own_sub_cycle(runs):
    both, _ = runs
    assert (both["A"].n_sub, both["B"].n_sub) == (5, 8)
    assert both["A"].n_intervals == DT_STEPS // 5
    assert both["B"].n_intervals == DT_STEPS // 8
    assert both["A"].t == pytest.approx(DT_STEPS * 2e-4, rel=1e-12)


def test_load_balance_invariant_per_structure(runs):
    both, _ = runs
    for cs in both.values():
        h = cs.mechanics.history()
        assert np.count_nonzero(h["wall_force_z"]) > 5          # the spheres landed
        assert h["balance_rel"].max() <= 1e-12


def test_each_structure_gets_the_impulse_it_gets_alone(runs):
    """Against the same structure coupled alone to a DEM with only its own spheres: the
    same first contact interval and the same impulse delivered over the run (within
    2 %, measured 0.06 % (A) and 0.4 % (B)). Not to round-off: every finish() moves its wall
    (MeshWall.set_vertices), which makes the DEM re-evaluate ALL contact forces at the
    next step; that re-evaluation is not idempotent in the DEM engine (a no-op force
    invalidation every 8 steps in a single-structure run changes its loads by 0.4 % of
    the peak), so the other structure's interval boundaries perturb this one's contacts."""
    both, alone = runs
    for k in ("A", "B"):
        a, b = both[k].mechanics.history(), alone[k].mechanics.history()
        assert np.flatnonzero(a["load_z"])[0] == np.flatnonzero(b["load_z"])[0]
        dt = both[k].dt
        J_a, J_b = a["load_z"].sum() * dt, b["load_z"].sum() * dt
        assert J_b < 0
        assert J_a == pytest.approx(J_b, rel=0.02), k
