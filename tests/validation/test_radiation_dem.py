"""Seed 000 (packed-bed pyrolysis paper), eqs. 22-23: radiation of DEM particles
(:mod:`gsi.dem.radiation`).

- One particle in a black enclosure at 0 K: m c dT/dt = -eps sigma A T^4, so
  t = m c/(3 eps sigma A) (T^-3 - T0^-3); the explicit update (every DEM step) follows it
  within 0.5 % (measured 0.07 % at dt 4 eps sigma T0^3 A/(m c) = 0.002).
- An enclosure of particles at two temperatures (radii 0.8-1.2 mm on a lattice, the box
  walls adiabatic, i.e. not radiating): sum m c T is conserved to round-off and the
  temperatures relax toward one value, the hottest never rising and the coldest never
  falling (the update is a convex combination below the stability bound).
- Pairwise reciprocity on a small configuration of unequal spheres: the exchange areas
  are symmetric and the pair rates antisymmetric bit for bit, and they are the
  symmetrised eq. 23 view factors computed here by brute force.
- Particle-wall: a plane and the same plane as a triangle mesh at the same temperature
  give the same rate, sigma eps_i eps_w S (T_w^4 - T_i^4) with S from eq. 23, and their
  books (plane heat; mesh vertex and wall heat) take exactly the heat the particle gets.
- A coupled FE plate heated only by radiation from particles held above it: the
  coupling's books close to round-off and Q_radiation is all of Q_particles.
- Bad options give one-line errors naming the key.
"""
import math
import pathlib

import numpy as np
import pytest

from gsi.dem import Material, Simulation
from gsi.dem.radiation import SIGMA
from gsi.errors import GsiInputError

MAT = Material(E=1e8, nu=0.3, rho=2500.0, cp=800.0, k=1.0)


def _sim(dt, *, lo=-0.02, hi=0.02, mats=None, heat=None):
    return Simulation(mats or {"a": MAT, "w": MAT}, heat=heat, gravity=(0, 0, 0), dt=dt,
                      skin=1e-4, domain=((lo,) * 3, (hi,) * 3), dt_checked=True)


def test_one_particle_cools_into_a_0K_enclosure_as_the_quadrature_says():
    r, eps, T0 = 1e-3, 0.8, 1000.0
    rho, cp = 8900.0, 385.0
    m = rho * 4.0 / 3.0 * math.pi * r ** 3
    A = 4.0 * math.pi * r * r
    mc = m * cp
    lam0 = 4.0 * eps * SIGMA * A * T0 ** 3 / mc
    sim = _sim(0.002 / lam0, mats={"cu": Material(E=1e8, nu=0.3, rho=rho, cp=cp)})
    sim.add_particles([[0.0, 0.0, 0.0]], r, material="cu", T=T0)
    rad = sim.set_radiation({"cu": eps}, T_enclosure=0.0)
    worst = 0.0
    for _ in range(10):
        sim.step(500)
        T = float(sim.T[0])
        t_exact = mc / (3.0 * eps * SIGMA * A) * (T ** -3 - T0 ** -3)
        worst = max(worst, abs(sim.time / t_exact - 1.0))
    print(f"one particle: T {T0:g} -> {T:.1f} K, worst |t/t_exact - 1| = {worst:.2e}")
    assert T < 500.0
    assert worst < 0.005
    assert rad.enclosure_heat == pytest.approx(mc * (T - T0), rel=1e-12)
    assert rad.evaluations == 5000


def _lattice(rng, n_side=4, spacing=2.6e-3):
    g = (np.arange(n_side) - 0.5 * (n_side - 1)) * spacing
    x = np.array([(a, b, c) for a in g for b in g for c in g])
    return x, rng.uniform(0.8e-3, 1.2e-3, len(x))


def test_two_temperature_enclosure_conserves_energy_and_relaxes():
    rng = np.random.default_rng(5)
    x, r = _lattice(rng)
    light = Material(E=1e8, nu=0.3, rho=2500.0, cp=100.0)
    sim = _sim(0.01, lo=-0.006, hi=0.006, mats={"a": light, "w": light})
    for p in range(3):                                     # adiabatic box: no temperature
        for s in (-1, 1):
            normal = np.zeros(3)
            normal[p] = -s
            sim.add_plane(point=s * 0.006 * np.eye(3)[p], normal=normal, material="w")
    T = np.where(x[:, 0] < 0.0, 1000.0, 400.0)
    sim.add_particles(x, r, material="a", T=T)
    rad = sim.set_radiation({"a": 0.9, "w": 0.9}, every=5)  # the walls have no temperature
    mc = sim.heat_capacity
    E0 = float((mc * sim.T).sum())
    hi, lo = [sim.T.max()], [sim.T.min()]
    for _ in range(40):
        sim.step(250)
        hi.append(sim.T.max())
        lo.append(sim.T.min())
    E = float((mc * sim.T).sum())
    mean = E0 / mc.sum()
    print(f"enclosure: |dE|/E = {abs(E / E0 - 1):.2e}, spread {hi[0] - lo[0]:.0f} -> "
          f"{hi[-1] - lo[-1]:.1f} K around {mean:.1f} K, {rad.evaluations} evaluations")
    assert abs(E / E0 - 1.0) <= 1e-12
    assert np.all(np.diff(hi) <= 0.0) and np.all(np.diff(lo) >= 0.0)
    assert hi[-1] - lo[-1] < 0.1 * (hi[0] - lo[0])
    assert lo[-1] < mean < hi[-1]
    assert rad.plane_heat.tolist() == [0.0] * 6 and sim.plane_state.heat.tolist() == [0.0] * 6
    assert np.array_equal(sim.x, x)                         # no contact, no gravity


def _eq23_exchange_areas(x, r, c):
    """S_ij = min(A_i F_i->j, A_j F_j->i), F_i->j = A_j / sum_{k in N_i} A_k (brute force)."""
    n = len(r)
    A = 4.0 * np.pi * r * r
    L = np.linalg.norm(x[:, None] - x[None], axis=2)
    nb = (L < c * (r[:, None] + r[None])) & ~np.eye(n, dtype=bool)
    sums = (nb * A[None]).sum(1)
    F = np.where(nb, A[None] / np.where(sums > 0, sums, 1.0)[:, None], 0.0)
    return np.minimum(A[:, None] * F, (A[:, None] * F).T), F, nb


def test_pairwise_reciprocity_on_a_small_configuration():
    rng = np.random.default_rng(11)
    n = 9
    x = rng.uniform(-4e-3, 4e-3, (n, 3))
    r = rng.uniform(0.5e-3, 1.5e-3, n)
    sim = _sim(1e-3)
    sim.add_particles(x, r, material="a", T=rng.uniform(300.0, 1200.0, n))
    eps = {"a": 0.7}
    rad = sim.set_radiation(eps, cutoff=2.0)
    R = rad.rates(record=True)
    S_ref, F, nb = _eq23_exchange_areas(x, r, 2.0)
    A = 4.0 * np.pi * r * r
    assert nb.sum() >= 10 and (~nb & ~np.eye(n, dtype=bool)).sum() >= 10   # both kinds
    assert not np.allclose(A[:, None] * F, (A[:, None] * F).T)  # eq. 23 alone: not reciprocal
    # reciprocity and antisymmetry against an independent computation: each pair's
    # exchange area and rate from a plain double loop over the particles (neighbour sums
    # of each side counted separately), not from the engine's symmetric matrices
    eps2 = 0.49
    T4 = sim.T ** 4
    for i in range(n):
        for j in range(n):
            if i == j:
                continue
            L_ij = math.dist(x[i], x[j])
            if L_ij >= 2.0 * (r[i] + r[j]):
                assert R.S[i, j] == 0.0 and R.Q_pair[i, j] == 0.0
                continue
            sum_i = sum(A[k] for k in range(n) if k != i
                        and math.dist(x[i], x[k]) < 2.0 * (r[i] + r[k]))
            sum_j = sum(A[k] for k in range(n) if k != j
                        and math.dist(x[j], x[k]) < 2.0 * (r[j] + r[k]))
            S_ij = min(A[i] * A[j] / sum_i, A[j] * A[i] / sum_j)
            assert R.S[i, j] == pytest.approx(S_ij, rel=1e-14)
            Q_ij = SIGMA * eps2 * S_ij * (T4[j] - T4[i])         # into i from j
            assert R.Q_pair[i, j] == pytest.approx(Q_ij, rel=1e-13, abs=1e-15)
    assert np.allclose(R.S, S_ref, rtol=1e-14, atol=0.0)
    assert np.all(R.S.sum(1) <= A * (1 + 1e-15))               # no more than its surface
    Q_ref = SIGMA * 0.49 * (S_ref * (T4[None] - T4[:, None])).sum(1)
    assert np.allclose(R.Q, Q_ref, rtol=1e-13, atol=1e-12 * np.abs(Q_ref).max())
    assert abs(R.Q.sum()) <= 1e-13 * np.abs(R.Q).sum()


def _flat_mesh(z, T):
    v = np.array([[-0.02, -0.02, z], [0.02, -0.02, z], [0.02, 0.02, z], [-0.02, 0.02, z]])
    return v, np.array([[0, 1, 2], [0, 2, 3]]), np.full(4, T)


@pytest.mark.parametrize("kind", ["plane", "mesh"])
def test_particle_wall_exchange_and_its_books(kind):
    r, Tp, Tw, eps_p, eps_w = 1e-3, 300.0, 1000.0, 0.9, 0.6
    sim = _sim(1e-3)
    if kind == "plane":
        wall = sim.add_plane(point=(0, 0, 0), normal=(0, 0, 1), material="w", temperature=Tw)
    else:
        v, t, T = _flat_mesh(0.0, Tw)
        wall = sim.add_mesh_wall(v, t, material="w", vertex_temperature=T)
    # particle 0 sees the wall (its image) and particle 1; particle 2 is out of reach
    x = np.array([[0.0, 0.0, 1.2e-3], [2.5e-3, 0.0, 1.6e-3], [0.0, 0.0, 8e-3]])
    sim.add_particles(x, r, material="a", T=Tp)
    rad = sim.set_radiation({"a": eps_p, "w": eps_w})
    R = rad.rates()
    A = 4.0 * math.pi * r * r
    Q_w = (R.Q_plane if kind == "plane" else R.Q_wall)[:, 0]
    # eq. 23 with the image: particle 0 has the wall (A) and particle 1 (A): F = 1/2 each
    assert Q_w[0] == pytest.approx(SIGMA * eps_p * eps_w * A / 2 * (Tw ** 4 - Tp ** 4),
                                   rel=1e-13)
    assert Q_w[1] == 0.0 and Q_w[2] == 0.0          # 1 is 1.6 R from the wall: 1.5 R reach
    assert R.Q[2] == 0.0                            # no neighbour, no enclosure
    T0 = sim.T.copy()
    sim.step(1)
    mc = sim.heat_capacity
    gained = float((mc * (sim.T - T0)).sum())
    assert gained == pytest.approx(Q_w[0] * sim.dt, rel=1e-12)
    assert rad.heat_from(wall) == pytest.approx(Q_w[0] * sim.dt, rel=1e-14)
    assert wall.heat_to_particles == pytest.approx(Q_w[0] * sim.dt, rel=1e-14)
    if kind == "mesh":
        assert wall.vertex_heat.sum() == pytest.approx(-Q_w[0] * sim.dt, rel=1e-13)
        # the centre is over the shared edge: the heat goes to its two ends (0 and 2)
        assert np.abs(wall.vertex_heat[[1, 3]]).max() <= 1e-15 * abs(Q_w[0] * sim.dt)


def test_plane_and_mesh_wall_give_the_same_rate():
    rates = []
    for kind in ("plane", "mesh"):
        sim = _sim(1e-3)
        if kind == "plane":
            sim.add_plane(point=(0, 0, 0), normal=(0, 0, 1), material="w", temperature=900.0)
        else:
            sim.add_mesh_wall(*_flat_mesh(0.0, 900.0)[:2], material="w",
                              vertex_temperature=np.full(4, 900.0))
        x = np.array([[0.003, 0.001, 1.3e-3], [0.0, 0.0, 1.1e-3], [0.0, 0.0, 3.1e-3]])
        sim.add_particles(x, 1e-3, material="a", T=[500.0, 600.0, 700.0])
        rates.append(sim.set_radiation({"a": 0.8, "w": 0.7}).rates().Q)
    assert np.allclose(rates[0], rates[1], rtol=1e-13, atol=0.0)


@pytest.mark.parametrize("degree", [1, 2], ids=["P1-heat", "P2-thermoelastic"])
def test_coupled_plate_heated_by_radiation_only_closes_its_books(degree):
    """P1: the heat-only coupling; P2: the thermo-elastic one, whose DEM wall is the face
    split at its edge midpoints (the radiated heat goes to the six parent nodes)."""
    from gsi import meshes
    from gsi.coupling.staggered import StaggeredCoupling
    from gsi.coupling.thermal import ThermalCoupling
    from gsi.fem.elasticity import Elasticity
    from gsi.fem.heat import Heat
    L, LZ, R, dt, n_sub = 0.02, 0.002, 1e-3, 1e-4, 10
    steel = dict(E=210e9, nu=0.3, rho=7850.0, c=44.0, k=53.3, alpha=12e-6)
    plate = meshes.build("box", length_x=L, length_y=L, length_z=LZ, n=(4, 4, 1))
    heat = Heat(plate, steel, dt=n_sub * dt, T_initial=300.0)
    sim = Simulation({"ore": Material(E=5e7, nu=0.25, rho=3000.0, k=2.0, cp=5.0),
                      "steel": Material(E=210e9, nu=0.3, rho=7850.0, k=53.3, cp=44.0)},
                     heat="area", gravity=(0, 0, 0), dt=dt, skin=2e-4, dt_checked=True,
                     domain=((-0.01, -0.01, -0.01), (L + 0.01, L + 0.01, 0.02)))
    if degree == 1:
        cp = ThermalCoupling(sim, heat, wall_material="steel", n_sub=n_sub, tag="z1",
                             T_ref=300.0)
    else:
        el = Elasticity(plate, steel, degree=2, T_ref=300.0)
        el.clamp("z0")
        mech = StaggeredCoupling(sim, el, wall_material="steel", n_sub=n_sub, tag="z1")
        cp = ThermalCoupling(sim, heat, mechanics=mech, tag="z1", T_ref=300.0)
        assert mech.interface.n_midpoints > 0
    g = np.linspace(0.25 * L, 0.75 * L, 3)
    x = np.array([(a, b, LZ + 1.3 * R) for a in g for b in g])     # no contact: 0.3 R gap
    ids = sim.add_particles(x, R, material="ore", T=900.0)
    sim.fix(ids)
    sim.set_radiation({"ore": 0.9, "steel": 0.8}, every=5)
    cp.run(40)
    h = cp.history()
    E_total = steel["rho"] * steel["c"] * L * L * LZ * 300.0 + abs(h["E_particles"][0])
    print(f"coupled: Q_particles {h['Q_particles'].sum():.4g} J, all radiated: "
          f"{h['Q_radiation'].sum():.4g} J, max |drift| {np.abs(h['drift']).max():.2e} J")
    assert h["Q_particles"].sum() > 0 and h["T_wall_max"][-1] > 300.0
    assert np.allclose(h["Q_radiation"], h["Q_particles"], rtol=1e-12, atol=0.0)
    assert np.abs(h["balance_error"]).max() <= 1e-12 * np.abs(h["Q_particles"]).max()
    assert np.abs(h["drift"]).max() <= 1e-12 * E_total
    assert h["n_contacts"].max() == 0


def _hot_floor_bed():
    sim = _sim(2e-4, mats={"a": MAT, "w": MAT})
    v, t, T = _flat_mesh(0.0, 900.0)
    sim.add_mesh_wall(v, t, material="w", vertex_temperature=T)
    g = (np.arange(4) - 1.5) * 2.2e-3
    x = np.array([(p, q, z) for p in g for q in g for z in (1.1e-3, 3.3e-3)])
    sim.add_particles(x, 0.9e-3, material="a", T=np.linspace(400.0, 800.0, len(x)))
    sim.set_radiation({"a": 0.9, "w": 0.7}, every=7)
    return sim


def test_resume_from_a_state_is_bitwise():
    """A run restored from :meth:`Simulation.state` between two evaluations continues
    bit for bit (temperatures, the wall's books, the radiation totals)."""
    a = _hot_floor_bed()
    a.step(31)
    saved = a.state()
    a.step(40)
    b = _hot_floor_bed()
    b.set_state(saved)
    b.step(40)
    assert np.array_equal(a.T, b.T) and np.array_equal(a.x, b.x)
    assert np.array_equal(a.mesh_state.vertex_heat, b.mesh_state.vertex_heat)
    assert np.array_equal(a.radiation.wall_heat, b.radiation.wall_heat)
    assert a.radiation.evaluations == b.radiation.evaluations == 11
    assert a.radiation.wall_heat[0] > 0.0


def test_bad_options_give_one_line_errors():
    sim = _sim(1e-3)
    sim.add_particles([[0.0, 0.0, 0.0]], 1e-3, material="a", T=1000.0)
    cases = [
        (dict(emissivity={"b": 0.5}), "materials.b.emissivity"),
        (dict(emissivity={"a": 1.5}), "materials.a.emissivity"),
        (dict(emissivity={"a": 0.5}, cutoff=0.5), "dem.radiation_cutoff"),
        (dict(emissivity={"a": 0.5}, every=0), "dem.radiation_every"),
        (dict(emissivity={"a": 0.5}, T_enclosure=-3.0), "dem.radiation_T_enclosure"),
    ]
    for kw, key in cases:
        with pytest.raises(GsiInputError) as exc:
            sim.set_radiation(kw.pop("emissivity"), **kw)
        assert key in str(exc.value) and "\n" not in str(exc.value)
    # unstable: every x dt x 4 eps sigma T^3 A/(m c) with A/m = 3/(R rho)
    ratio = 20000 * 1e-3 * 4.0 * SIGMA * 1000.0 ** 3 * 3.0 / (1e-3 * MAT.rho * MAT.cp)
    sim.set_radiation({"a": 1.0}, every=20000, T_enclosure=0.0)
    with pytest.raises(GsiInputError) as exc:
        sim.step(1)
    msg = str(exc.value)
    assert msg.startswith("dem.radiation_every = 20000:") and "\n" not in msg
    assert f"= {ratio:.3g} > 1" in msg and f"<= {int(20000 / ratio)} " in msg
    cold = _sim(1e-3)
    cold.add_particles([[0.0, 0.0, 0.0]], 1e-3, material="a", T=-10.0)
    cold.set_radiation({"a": 0.5})
    with pytest.raises(GsiInputError, match="absolute temperatures"):
        cold.step(1)


def test_radiation_is_off_by_default():
    sim = _sim(1e-3)
    assert sim.radiation is None
    sim.add_particles([[0.0, 0.0, 0.0]], 1e-3, material="a", T=1000.0)
    sim.step(3)
    assert sim.T[0] == 1000.0


ROOT = pathlib.Path(__file__).resolve().parents[2]
SILO = ROOT / "demos" / "thermal_silo_radiation.toml"


def test_case_keys_reach_the_simulation():
    from gsi.case import load_case
    from gsi.run import build_simulation
    case = load_case(SILO)
    sim, _, _ = build_simulation(case, dt=case.check())
    rad = sim.radiation
    assert (rad.cutoff, rad.every, rad.T_enclosure) == (1.5, 50, None)
    eps = dict(zip(sim.material_names, rad.eps_type))
    assert eps["clinker"] == 0.9 and eps["steel"] == 0.8
    assert rad.stability(sim.dt) == pytest.approx(
        50 * 3e-5 * 4 * SIGMA * 800.0 ** 3 * 3 * 0.9 / (0.0035 * 3150.0 * 1000.0 / 200.0),
        rel=0.02)                       # the smallest radius drawn is near 3.5 mm


@pytest.mark.slow
def test_silo_bed_radiation_share_quick(tmp_path):
    """The study of benchmarks/silo_radiation_share.py in its quick form: the coupling's
    books close with particle radiation on, and the bed's radiation adds to the wall's
    heat. Measured (2 cores): 7.674 kJ from the bed into the wall (physical; 60 s of
    heating), 34.9 % of it radiated; 5.256 kJ without the bed's radiation."""
    import tomllib
    from gsi.case import case_from_table
    from gsi.run import run_case
    out = {}
    for name, on in (("rad", True), ("ref", False)):
        t = tomllib.loads(SILO.read_text())
        if not on:
            for key in ("radiation", "radiation_cutoff", "radiation_every"):
                t["dem"].pop(key)
        run_case(case_from_table(t, base_dir=SILO.parent), out=tmp_path / name, quick=True,
                 verbose=False, pictures=False)
        out[name] = np.genfromtxt(tmp_path / name / "bin_energy.csv", delimiter=",",
                                  names=True)
    h, ref = out["rad"], out["ref"]
    Q, Q_rad = h["Q_particles"].sum(), h["Q_radiation"].sum()
    print(f"silo quick: bed -> wall {200 * Q / 1e3:.4g} kJ, radiated {100 * Q_rad / Q:.1f} %; "
          f"without bed radiation {200 * ref['Q_particles'].sum() / 1e3:.4g} kJ")
    assert np.abs(h["drift"]).max() <= 1e-10 * Q
    assert np.abs(h["balance_error"]).max() <= 1e-12 * np.abs(h["Q_particles"]).max()
    assert np.all(h["Q_radiation"] >= 0.0) and (ref["Q_radiation"] == 0.0).all()
    assert 0.2 < Q_rad / Q < 0.5
    assert Q > 1.2 * ref["Q_particles"].sum()
