"""The fused integration of the force pass (``gsi.dem.integrate.integrate_rows``).

``integrate_rows`` writes a particle's two half kicks, drift, clear and scan out in one
body (selects instead of branches) for speed; it must stay bitwise what the per-particle
pieces give: :func:`kick_one` (the second half kick), then, in mode 2,
:func:`drift_one` (the next first half kick, drift, clear) and :func:`scan_one` (of
which it returns the largest squared speed, not the displacement: the engine bounds
that, :func:`gsi.dem.integrate.displacement_bound`, tested below).  The rows here
include fixed particles, one outside the domain, one too fast and one with a NaN
velocity, and are visited in a shuffled row order.
"""
import numpy as np
import pytest

from gsi.dem import Material, Simulation
from gsi.dem.integrate import (displacement_bound, drift_one, integrate_rows, kick_one,
                               scan, scan_one)

LO = np.array([0.0, 0.0, 0.0])
HI = np.array([0.05, 0.05, 0.05])
VMAX2 = 4.0


def particles(seed):
    rng = np.random.default_rng(seed)
    sim = Simulation({"m": Material(E=5e6, nu=0.3, rho=2500.0)}, heat="area", dt=2e-6,
                     skin=4e-4, domain=(LO, HI))
    n = 40
    sim.add_particles(rng.uniform(0.005, 0.045, (n, 3)), rng.uniform(5e-4, 1e-3, n),
                      material="m", v=rng.uniform(-1.0, 1.0, (n, 3)),
                      omega=rng.uniform(-50.0, 50.0, (n, 3)), T=rng.uniform(300.0, 400.0, n))
    sim.fix(sim.ids[[3, 17]])
    P = sim.particles
    P.force[:] = rng.normal(0.0, 1e-3, (n, 3))
    P.torque[:] = rng.normal(0.0, 1e-7, (n, 3))
    P.q[:] = rng.normal(0.0, 1e-2, n)
    P.x0[:] = P.x + rng.uniform(-1e-4, 1e-4, (n, 3))
    P.x[5, 2] = 0.0499999                  # drifts out of the domain
    P.v[5, 2] = 30.0                       # and too fast
    P.v[9, 0] = np.nan
    P.ncontact[:] = 3
    return P


def copy(P):
    return type(P)(*[a.copy() for a in P])


@pytest.mark.parametrize("mode", [1, 2])
def test_integrate_rows_is_the_per_particle_pieces_bitwise(mode):
    P = particles(4)
    Q = copy(P)
    n = P.x.shape[0]
    rows = np.random.default_rng(5).permutation(n).astype(np.int64)
    half_dt, dt, g = 1e-6, 2e-6, (0.0, 0.0, -9.81)
    d2, nout, bad = integrate_rows(0, n, rows, mode, True, half_dt, dt, *g, P, LO, HI, VMAX2)
    # the reference: the pieces one by one
    dmax, nout_ref, bad_ref = 0.0, 0, -1
    for i in rows:
        kick_one(i, half_dt, Q)
        Q.T[i] += dt * Q.q[i] * Q.mcp_inv[i]
        if mode == 2:
            drift_one(i, half_dt, dt, *g, Q)
            di, si, out = scan_one(i, Q, LO, HI)
            dmax = max(dmax, si)            # the largest squared speed of the drift
            nout_ref += int(out)
            if not (si <= VMAX2) and (bad_ref < 0 or i < bad_ref):
                bad_ref = i
    for name, a, b in zip(P._fields, P, Q):
        np.testing.assert_array_equal(a, b, err_msg=name)
    if mode == 2:
        assert (d2, nout, bad) == (dmax, nout_ref, bad_ref)
        assert nout == 2 and bad == 5     # rows 5 and 9 (NaN) left; both bad, 5 first
        assert (P.x[[3, 17]] == particles(4).x[[3, 17]]).all()     # fixed rows stay
    else:
        assert (d2, nout, bad) == (0.0, 0, -1)


def test_displacement_bound_scans_only_near_half_the_skin():
    """Below 0.99 skin/2 the bound grows by dt max|v| and x0 is not read; above, the exact
    largest displacement since the build is returned and becomes the bound."""
    P = particles(6)
    P.v[9, 0] = 0.0
    P.x0[5] = P.x[5]                   # (moved out of the domain after x0 was set)
    exact = scan(P, LO, HI, VMAX2)[0]             # up to 3 (1e-4 m)^2: below (2e-4 m)^2
    half_skin2 = (2e-4) ** 2
    d2, b = displacement_bound(1e-5, 2e-6, 25.0, P, LO, HI, VMAX2, half_skin2)
    assert b == 1e-5 + 2e-6 * 5.0 and d2 == b * b          # no scan
    d2, b = displacement_bound(2e-4, 2e-6, 25.0, P, LO, HI, VMAX2, half_skin2)
    assert d2 == exact and b == np.sqrt(exact)           # the exact scan
    assert 0.0 < exact < half_skin2


@pytest.mark.parametrize("chunk", [1, 37, 400])
def test_rebuilds_keep_every_particle_within_half_the_skin(chunk):
    """A fast gas between walls: after every call of ``step`` no particle has moved more
    than skin/2 since the lists were built (else the bound let a rebuild slip), and the
    trajectory does not depend on how the steps are split into calls (the first drift
    of a call is scanned exactly, the later ones through the bound)."""
    def gas():
        rng = np.random.default_rng(3)
        sim = Simulation({"m": Material(E=5e6, nu=0.3, rho=2500.0, e=0.8, mu=0.3)},
                         dt=2e-6, skin=4e-4, domain=((0, 0, 0), (0.03, 0.03, 0.03)),
                         gravity=(0, 0, -9.81))
        g = np.arange(0.004, 0.027, 0.0035)
        x = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
        sim.add_particles(x, 1e-3, material="m", v=rng.normal(0.0, 0.5, x.shape))
        for p, nrm in [((0, 0, 0), (0, 0, 1)), ((0, 0, 0.03), (0, 0, -1)),
                       ((0, 0, 0), (1, 0, 0)), ((0.03, 0, 0), (-1, 0, 0)),
                       ((0, 0, 0), (0, 1, 0)), ((0, 0.03, 0), (0, -1, 0))]:
            sim.add_plane(p, nrm, material="m")
        return sim
    sim = gas()
    half_skin2 = (0.5 * 4e-4) ** 2
    for _ in range(1200 // chunk):
        sim.step(chunk)
        d = sim.particles.x - sim.particles.x0
        assert (d * d).sum(axis=1).max() <= half_skin2
    assert sim.n_rebuilds > 5
    ref = gas()
    ref.step(1200 // chunk * chunk)
    assert np.array_equal(sim.x, ref.x)
