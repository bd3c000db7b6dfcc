"""The energy book beyond the closed box (:mod:`gsi.dem.energy`, docs/design.md,
"Energy audit"): the spring of a mesh-triangle contact that ends, the particles lost from
the domain and those added to it, and the book across a restart.

Mostly one sphere or a few in free flight (R = 1 mm, E = 5 MPa, mu = 0.5, e = 0.5):
small enough to run in seconds, and free of chaos, so a trajectory is compared with
another run's bit for bit or to round-off (no ensemble needed); the hopper outflow, a
dense flow, is judged on an ensemble.

- A triangle contact that ends (the sphere leaves the mesh, or slides onto the next
  triangle of the same surface): its tangential spring's energy should become heat.  NOT
  BOOKED today: the first implementation (in the triangle selection, which then took the
  particle state, material table and normal law) slowed the engine by 40-45 % on small
  plane-only cases (thesis case 3: 22.9 -> 32.5 s, even with the booking call removed:
  the longer signatures alone), so it was taken out; these two tests are strict xfails
  that measure the gap and will pass (and so fail as XPASS) once it is booked again.  A bounce
  off a flat two-triangle mesh is the same contact as a bounce off a plane, whose
  spring's end is already booked: the drifts must agree to round-off (before the
  booking they differed by exactly the spring's energy at the contact's last step:
  1.915e-8 J linear, 1.13e-12 J Hertz).  A sphere sliding 4 mm across a mesh of
  0.5 mm triangles restarts its spring at each edge: the drift must fall with dt (time
  integration), its part that does not (extrapolated to dt -> 0) below the energy of one
  spring at the Coulomb cap (before the booking: 12.9 such springs linear, 16.1 Hertz,
  the drift -2.93e-10 / -2.95e-10 J (linear) at dt = 2e-6 / 1e-6 s, not falling).
- Particles that leave the domain take their energy out (``lost``), those added bring
  theirs in (``added``): in free flight the book closes to round-off (velocity Verlet
  is exact under a constant force), and a hopper's outflow leaves only time
  integration in the drift.
- A run restored from its state continues the book bit for bit (the CLI's ``--resume``:
  tests/reliability/test_restart.py, whose case has an ``energy`` monitor).
"""
import numpy as np
import pytest

from gsi.dem import Simulation, Material
from gsi.dem.energy import EnergyAudit

R = 1e-3
MG = 2500.0 * 4.0 / 3.0 * np.pi * R ** 3 * 9.81       # the sphere's weight (N)


def sphere(wall, contact, *, dt, x, v, mu=0.5, domain=0.01):
    """One sphere at ``x`` with velocity ``v`` above a floor z = 0: a ``plane``, a flat
    ``square`` of two triangles (10 mm), or a ``grid`` of 800 triangles (0.5 mm)."""
    m = Material(E=5e6, nu=0.3, rho=2500.0, e=0.5, mu=mu, mu_r=0.0)
    kw = {"k_n": 200.0} if contact == "linear" else {}
    sim = Simulation({"g": m}, contact=contact, gravity=(0, 0, -9.81), dt=dt, skin=0.4 * R,
                     domain=((-domain, -domain, -domain), (domain, domain, domain)),
                     frictional_heating=True, **kw)
    sim.add_particles([x], R, material="g", v=[v], T=[0.0])
    if wall == "plane":
        sim.add_plane((0, 0, 0), (0, 0, 1), material="g")
    else:
        n = 1 if wall == "square" else 20
        g = np.linspace(-0.005, 0.005, n + 1)
        X, Y = np.meshgrid(g, g, indexing="ij")
        V = np.c_[X.ravel(), Y.ravel(), np.zeros(X.size)]
        p = (np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]).ravel()
        T = np.r_[np.c_[p, p + n + 1, p + n + 2], np.c_[p, p + n + 2, p + 1]]
        sim.add_mesh_wall(V, T, material="g")
    return sim


@pytest.mark.xfail(strict=True, reason="the ended triangle spring's energy is not booked "
                   "(docs/design.md, Energy audit: what is not covered)")
@pytest.mark.parametrize("contact", ["linear", "hertz"])
def test_a_triangle_contact_that_ends_books_its_spring(contact, record_validation):
    """An oblique bounce (v = (0.2, 0.1, -0.3) m/s) off a flat mesh and off a plane:
    the same contact, so the same drift to round-off; the spring's energy at the
    contact's last step (read from the book, step by step) is what a missing booking
    would leave."""
    dt, steps = 2e-6, 3000
    runs = {}
    for wall in ("plane", "square"):
        sim = sphere(wall, contact, dt=dt, x=(0.0, 0.0, 1.1 * R), v=(0.2, 0.1, -0.3))
        audit = EnergyAudit(sim)
        spring_end = 0.0
        for _ in range(steps):
            sim.step(1)
            if sim.ncontact[0] and wall == "square":
                spring_end = audit.sample()["elastic_tangential"]
        runs[wall] = audit.sample(), spring_end, sim.ncontact[0]
    (plane, _, _), (mesh, spring_end, touching) = runs["plane"], runs["square"]
    in_play = mesh["heat_generated"] + mesh["kinetic"]
    diff = abs(mesh["drift"] - plane["drift"])
    record_validation(f"Energy audit, a sphere bouncing off a flat mesh vs a plane "
                      f"({contact}, mu = 0.5): |drift difference| / energy in play",
                      reference=0.0, measured=diff / in_play, tolerance=1e-12, kind="abs",
                      source="energy conservation (docs/design.md, Energy audit)",
                      note=f"the ended spring's energy {spring_end:.3e} J = "
                           f"{spring_end / in_play:.2e} of the energy in play (before "
                           f"its booking, the difference)")
    assert touching == 0 and spring_end > 1e-6 * in_play     # it left with a loaded spring
    assert diff <= 1e-12 * in_play


@pytest.mark.xfail(strict=True, reason="the ended triangle spring's energy is not booked "
                   "(docs/design.md, Energy audit: what is not covered)")
@pytest.mark.parametrize("contact", ["linear", "hertz"])
def test_sliding_across_triangle_edges_drift_falls_with_dt(contact, record_validation):
    """A sphere sliding (v0 = (0.3, 0.1, 0) m/s, 15 ms, still sliding at the end) across
    a mesh of 0.5 mm triangles: at each edge the contact moves to the next triangle and
    the spring restarts.  The drift at dt and dt/2 extrapolated to dt -> 0 (first order:
    D0 = 2 D(dt/2) - D(dt)) is what the bookkeeping misses; it must stay below the energy
    of ONE spring at the Coulomb cap (the plane's tangential energy while sliding), while
    the sphere crosses more than a dozen edges."""
    t = 0.015
    drift = []
    for dt in (2e-6, 1e-6):
        sim = sphere("grid", contact, dt=dt, x=(0.0, 0.0, R), v=(0.3, 0.1, 0.0))
        audit = EnergyAudit(sim)
        sim.step(int(round(t / dt)))
        drift.append(audit.sample()["drift"])
    plane = sphere("plane", contact, dt=1e-6, x=(0.0, 0.0, R), v=(0.3, 0.1, 0.0))
    plane.step(int(round(t / 1e-6)))
    cap = EnergyAudit(plane).sample()["elastic_tangential"]
    v = np.linalg.norm(plane.v[0, :2])
    D0 = 2.0 * drift[1] - drift[0]
    record_validation(f"Energy audit, a sphere sliding across 0.5 mm mesh triangles "
                      f"({contact}, mu = 0.5): drift extrapolated to dt -> 0 / one capped "
                      "spring's energy", reference=1.0, measured=abs(D0) / cap,
                      tolerance=1.0, kind="bound",
                      source="energy conservation (docs/design.md, Energy audit)",
                      note=f"drift {drift[0]:.3e}, {drift[1]:.3e} J at dt = 2e-6, 1e-6 s; "
                           f"one spring at the cap {cap:.3e} J")
    if contact == "linear":     # the cap: (mu m g)^2 / (2 k_t), k_t = 2/7 k_n
        assert cap == pytest.approx((0.5 * MG) ** 2 / (2.0 * 2.0 / 7.0 * 200.0), rel=1e-3)
    assert v > 5.0 / 7.0 * np.hypot(0.3, 0.1) * 1.02          # still sliding at the end
    assert abs(D0) < cap


@pytest.mark.parametrize("frictional_heating", [False, True])
def test_particles_leaving_the_domain_take_their_energy_out(frictional_heating,
                                                           record_validation):
    """Twelve spheres thrown in free flight (random velocities up to 1 m/s in the y-z
    plane, each in its own plane x = const 2.9 mm or more apart, so they never touch;
    random spins, temperatures 1-3 K, c_p = 1 J/(kg K)) in a 40 mm box: most leave it,
    at different steps.  In free flight velocity Verlet conserves 1/2 m v^2 + 1/2 I w^2 - m g.x
    exactly (a constant force), and T and w are constant, so the energy a sphere takes
    out is its initial E_i = 1/2 m v0^2 + 1/2 I w0^2 - m g.x0 + m c_p T0: the book's
    ``lost`` must equal the sum over the spheres that left, and the drift must stay at
    round-off (before ``lost`` was booked: the drift was minus that sum)."""
    rng = np.random.default_rng(5)
    n, L, dt = 12, 0.02, 1e-5
    m = Material(E=5e6, nu=0.3, rho=2500.0, e=0.5, mu=0.5, cp=1.0)
    sim = Simulation({"g": m}, contact="hertz", gravity=(0.0, 0.0, -9.81), dt=dt,
                     skin=0.4 * R, domain=((-L, -L, -L), (L, L, L)),
                     frictional_heating=frictional_heating)
    x0 = np.c_[np.linspace(-0.8, 0.8, n) * L, rng.uniform(-0.5, 0.5, (n, 2)) * L]
    v0 = np.c_[np.zeros(n), rng.uniform(-1.0, 1.0, (n, 2))]
    w0 = rng.uniform(-50.0, 50.0, (n, 3))
    T0 = rng.uniform(1.0, 3.0, n)
    ids = sim.add_particles(x0, R, material="g", v=v0, omega=w0, T=T0)
    mass = 2500.0 * 4.0 / 3.0 * np.pi * R ** 3
    E0 = (0.5 * mass * (v0 ** 2).sum(1) + 0.5 * 0.4 * mass * R ** 2 * (w0 ** 2).sum(1)
          + mass * 9.81 * x0[:, 2] + mass * 1.0 * T0)
    audit = EnergyAudit(sim)
    sim.step(int(round(0.025 / dt)))
    p = audit.sample()
    left = ~np.isin(ids, sim.ids)
    scale = np.abs(E0).sum()
    record_validation(f"Energy audit, {n} spheres thrown out of the domain in free flight "
                      f"(frictional heating {'on' if frictional_heating else 'off'}): "
                      "|drift| / |energy|", reference=0.0, measured=abs(p["drift"]) / scale,
                      tolerance=1e-12, kind="abs",
                      source="velocity Verlet's exact free flight (docs/design.md, Energy "
                             "audit)",
                      note=f"{left.sum()} of {n} left at different steps; lost "
                           f"{p['lost']:.6e} J, their initial energy {E0[left].sum():.6e} J "
                           "(before the booking: the drift)")
    assert 3 <= sim.n_lost == left.sum() < n
    assert sim.contact_count() == 0 and p["elastic"] == 0.0
    assert p["lost"] == pytest.approx(E0[left].sum(), rel=0.0, abs=1e-12 * scale)
    assert abs(p["drift"]) <= 1e-12 * scale




def test_a_stream_in_and_out_of_the_domain_closes_the_book(record_validation):
    """An inserter feeds spheres (2000/s, all at 1 m/s downwards, 300 K, c_p = 1 J/(kg K))
    into the top of the domain for 25 ms; they fall together, never touching, and leave
    through the bottom 20 mm lower.  The energy the stream brings in (``added``, booked at
    insertion) and takes out (``lost``) closes the book to round-off (before either was
    booked the drift was their difference, and each alone moved the book by itself)."""
    from gsi.dem.insertion import Box
    m = Material(E=5e6, nu=0.3, rho=2500.0, e=0.5, mu=0.5, cp=1.0)
    L, dt = 0.01, 1e-5
    sim = Simulation({"g": m}, contact="hertz", gravity=(0.0, 0.0, -9.81), dt=dt,
                     skin=0.4 * R, domain=((-L, -L, -L), (L, L, L)), seed=3)
    sim.add_inserter(Box((-0.8 * L, -0.8 * L, 0.6 * L), (0.8 * L, 0.8 * L, 0.9 * L)), 2000.0,
                     radius=R, material="g", velocity=(0.0, 0.0, -1.0), T=300.0)
    audit = EnergyAudit(sim)
    sim.step(int(round(0.025 / dt)))
    p = audit.sample()
    scale = p["added"] + p["lost"]
    record_validation("Energy audit, a stream of spheres inserted into and lost from the "
                      "domain in free flight: |drift| / energy through the book",
                      reference=0.0, measured=abs(p["drift"]) / scale, tolerance=1e-12,
                      kind="abs", source="velocity Verlet's exact free flight "
                                         "(docs/design.md, Energy audit)",
                      note=f"{sim.n_lost} of {sim.n_lost + sim.n} left; added "
                           f"{p['added']:.4e} J, lost {p['lost']:.4e} J")
    assert sim.n_lost >= 5 and sim.n >= 5 and sim.contact_count() == 0
    assert abs(p["drift"]) <= 1e-12 * scale


def hopper(realisation, dt):
    """54 spheres dropped into a wedge hopper (two 45 degree mesh faces, 8 mm deep
    between two planes, a 5 mm outlet) with frictional heating; they flow out and fall
    out of the domain 8 mm below the outlet.  A ``realisation`` > 0 moves each sphere
    by up to 0.1 nm.  The mesh faces are frictionless (``mu`` = 0 between the spheres
    and their material ``w``): the spring of a triangle contact that ends is not booked
    (the xfails above), and the faces' springs would put that gap into the drift (with
    mu = 0.5 on the faces too: up to 1.26e-3 of the energy in play at dt = 5e-6 s)."""
    m = Material(E=5e6, nu=0.3, rho=2500.0, e=0.5, mu=0.5, cp=1.0)
    W, H, gap = 8 * R, 10 * R, 5.0 * R
    sim = Simulation({"g": m, "w": m}, contact="hertz", gravity=(0, 0, -9.81), dt=dt,
                     skin=0.4 * R, domain=((-12 * R, -R, -8 * R), (12 * R, W + R, 30 * R)),
                     frictional_heating=True, pair_overrides={("g", "w"): {"mu": 0.0}})
    V = [(s * gap / 2 + s * a * H, y, a * H) for s in (-1, 1)
         for a, y in ((0, 0), (1, 0), (1, W), (0, W))]
    sim.add_mesh_wall(np.array(V, float), np.array([[0, 1, 2], [0, 2, 3], [4, 6, 5],
                                                   [4, 7, 6]]), material="w")
    sim.add_plane((0, 0, 0), (0, 1, 0), material="g")
    sim.add_plane((0, W, 0), (0, -1, 0), material="g")
    X = np.array(np.meshgrid((np.arange(6) - 2.5) * 2.3 * R, (np.arange(3) + 0.5) * 2.6 * R,
                             12 * R + np.arange(3) * 2.3 * R, indexing="ij")).reshape(3, -1).T
    X += np.random.default_rng(3).uniform(-0.05, 0.05, X.shape) * R
    if realisation:
        X += np.random.default_rng(1000 + realisation).uniform(-1e-10, 1e-10, X.shape)
    sim.add_particles(X, R, material="g", T=np.full(len(X), 1.0))
    return sim


def test_hopper_outflow_drift_is_time_integration(record_validation):
    """The hopper (:func:`hopper`) for 0.15 s, an ensemble of three realisations 0.1 nm
    apart: more than half the spheres leave, taking out several times the energy in
    play; the drift left is time integration, below 1e-3 of the energy in play in each
    member, the bound of the closed shaken box (measured with frictionless faces at
    5e-6 s: -1.84e-4 to -1.90e-4, 31-32 spheres lost, 5.5-5.8 times the energy in play;
    before the outflow was booked the drift was minus the energy lost, 6 times the
    energy in play)."""
    out = []
    for r in range(3):
        sim = hopper(r, 5e-6)
        audit = EnergyAudit(sim)
        sim.step(30000)
        p = audit.sample()
        out.append((p["drift_rel"], p["lost"] / (p["drift"] / p["drift_rel"]), sim.n_lost))
    drift, lost, n_lost = np.array(out).T
    record_validation("Energy audit, hopper outflow of 54 spheres (hertz, mu = 0.5, 3 "
                      "realisations): largest |drift| / energy in play", reference=1e-3,
                      measured=np.abs(drift).max(), tolerance=1e-3, kind="bound",
                      source="energy conservation (docs/design.md, Energy audit)",
                      note=f"lost {n_lost.min():.0f}-{n_lost.max():.0f} of 54, their energy "
                           f"{lost.min():.1f}-{lost.max():.1f} times the energy in play")
    assert n_lost.min() > 27 and lost.min() > 1.0
    assert np.abs(drift).max() < 1e-3


def _restart_case(frictional_heating):
    """Eight spheres dropped on a floor that slides along x at 5 mm/s (the wall works on
    them), damping and friction (without frictional heating the drift is the dissipated
    energy, far from 0), and four thrown out of the domain (through x = 10 mm after about
    42, 33, 17 and 8 ms) in lanes of their own."""
    m = Material(E=5e6, nu=0.3, rho=2500.0, e=0.5, mu=0.5, cp=1.0)
    L = 0.01
    sim = Simulation({"g": m}, contact="hertz", gravity=(0.0, 0.0, -9.81), dt=1e-5,
                     skin=0.4 * R, domain=((-L, -L, -1e-3), (L, L, L)),
                     frictional_heating=frictional_heating)
    g = (np.arange(4) - 1.5) * 2.5 * R
    x = np.c_[np.repeat(g, 2), np.tile([-2 * R, 2 * R], 4), np.linspace(1.2, 3.0, 8) * R]
    sim.add_particles(x, R, material="g", T=np.full(8, 2.0))
    x = np.c_[np.full(4, 0.5 * L), (np.arange(4) - 1.5) * 3 * R, np.full(4, 0.5 * L)]
    sim.add_particles(x, R, material="g", v=[(vx, 0.0, 0.2) for vx in (0.12, 0.15, 0.3, 0.6)],
                      T=np.full(4, 2.0))
    sim.add_plane((0, 0, 0), (0, 0, 1), material="g", velocity=(5e-3, 0.0, 0.0))
    return sim


@pytest.mark.parametrize("frictional_heating", [False, True])
def test_a_restored_run_continues_the_book_bitwise(frictional_heating):
    """The run's audit (EnergyAudit.of_run) of a run restored from its state at 0.03 s
    (particles lost, wall work done, heat booked by then) equals the uninterrupted run's
    at 0.07 s, every part bit for bit; a book started afresh at the restore (the monitor
    before the baseline was in the checkpoint) would differ by the drift at 0.03 s."""
    ref = _restart_case(frictional_heating)
    EnergyAudit.of_run(ref)
    ref.step(3000)
    saved = ref.state()
    mid = EnergyAudit.of_run(ref).sample()
    ref.step(4000)
    end = EnergyAudit.of_run(ref).sample()
    res = _restart_case(frictional_heating)
    res.set_state({k: np.array(v) for k, v in saved.items()})
    res.step(4000)
    got = EnergyAudit.of_run(res).sample()
    assert 0 < mid["lost"] < end["lost"] and ref.n_lost == 4 and mid["wall_work"] != 0.0
    assert mid["drift"] != 0.0
    assert got == end                    # every part, bit for bit
