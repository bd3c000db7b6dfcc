"""The energy book of a shaken, closed, adiabatic box (issue 31, :mod:`gsi.dem.energy`).

Spheres in a box of six planes (no heat model: adiabatic; ``frictional_heating`` on),
damping (e = 0.5) and rolling resistance (mu_r = 0.1), given random velocities, shaken
vertically (the six planes move together, v(t) = A w cos(w t), A = 0.5 mm, 40 Hz,
Gamma = A w^2/g = 3.2, the velocity held over 0.1 ms pieces) and left to settle.  The
book kinetic + elastic + gravitational + thermal - wall work + walls' frictional heat
must stay constant.

- Without sliding friction (mu = 0) the drift is time-integration error alone (velocity
  Verlet: a force jump at a contact's start or at the rolling torque's stop makes it
  first order, the smooth parts second): it falls with dt, and is below 1e-3 of the
  energy in play at the smaller step.
- With friction (mu = 0.5) the measured drift is a few per cent and does not fall with
  dt: the incremental tangential spring is not a potential (Hertz: k_t = 8 G* sqrt(R*
  delta) changes under a stored spring; linear, with tension: a contact ends with a
  loaded spring whose energy vanishes).  The 1e-3 target is not met there; the test
  states it (strict xfail) instead of loosening it (docs/design.md, "Energy audit").
  Measured (2026-12-04): 64 spheres, dt = 1e-5 s: linear 4.5e-2, Hertz 2.1e-2; the
  @slow study of 2197 spheres (Hertz, dt = 2e-5 s, shaken 1 s, settled 1 s): 7.4e-3.
"""
import math

import numpy as np
import pytest

from gsi.dem import Simulation, Material
from gsi.dem.energy import EnergyAudit

R = 1e-3


def shaken_box(*, contact, mu, dt_factor, n_side=4, t_shake=0.05, t_settle=0.05, seed=1):
    """Run the box (module docstring); returns the audit sample at the end."""
    m = Material(E=5e6, nu=0.3, rho=2500.0, e=0.5, mu=mu, mu_r=0.1)
    L = n_side * 2.2 * R
    H = 2 * L
    kw = {"k_n": 200.0} if contact == "linear" else {}
    dt = 2e-5 * dt_factor
    sim = Simulation({"g": m}, contact=contact, rolling=True, gravity=(0, 0, -9.81), dt=dt,
                     skin=0.4 * R, domain=((-R, -R, -R), (L + R, L + R, H + R)),
                     frictional_heating=True, **kw)
    rng = np.random.default_rng(seed)
    g = (np.arange(n_side) + 0.5) * 2.2 * R
    X = np.array(np.meshgrid(g, g, g)).reshape(3, -1).T
    X += rng.uniform(-0.05, 0.05, X.shape) * R
    sim.add_particles(X, R, material="g", v=rng.normal(0, 0.05, X.shape),
                      T=np.full(len(X), 300.0))
    planes = [sim.add_plane(p, n, material="g") for p, n in [
        ((0, 0, 0), (0, 0, 1)), ((0, 0, H), (0, 0, -1)), ((0, 0, 0), (1, 0, 0)),
        ((L, 0, 0), (-1, 0, 0)), ((0, 0, 0), (0, 1, 0)), ((0, L, 0), (0, -1, 0))]]
    audit = EnergyAudit(sim)
    A, w = 0.5e-3, 2 * math.pi * 40.0
    chunk = max(1, int(round(1e-4 / dt)))
    for k in range(int(round(t_shake / (chunk * dt)))):
        vz = A * w * math.cos(w * (k + 0.5) * chunk * dt)
        for p in planes:
            p.set_motion((0.0, 0.0, vz))
        sim.step(chunk)
    for p in planes:
        p.set_motion((0.0, 0.0, 0.0))
    sim.step(int(round(t_settle / dt)))
    return audit.sample()


@pytest.mark.parametrize("contact, factors", [("linear", (1.0, 0.5)), ("hertz", (0.5, 0.25))])
def test_frictionless_box_drift_is_time_integration_error(contact, factors,
                                                          record_validation):
    runs = [shaken_box(contact=contact, mu=0.0, dt_factor=f) for f in factors]
    drift = [abs(p["drift_rel"]) for p in runs]
    p = runs[-1]
    record_validation(f"Energy audit, shaken box of 64 spheres ({contact}, mu = 0): "
                      "|drift| / energy in play", reference=1e-3, measured=drift[-1],
                      tolerance=1e-3, kind="bound",
                      source="energy conservation (docs/design.md, Energy audit)",
                      note=f"dt = {2e-5 * factors[0]:.0e}, {2e-5 * factors[1]:.0e} s: "
                           f"{drift[0]:.2e}, {drift[1]:.2e} (falls with dt); wall work "
                           f"{p['wall_work']:.3e} J, heat {p['heat_generated']:.3e} J")
    assert p["wall_work"] > 0.5 * p["heat_generated"] > 0.0      # the shaking did work
    assert drift[-1] < 1e-3
    assert drift[-1] < 0.5 * drift[0]


@pytest.mark.xfail(strict=True, raises=AssertionError,
                   reason="incremental tangential spring: the book misses the spring energy "
                          "k_t changes or a contact's end takes (a few %)")
@pytest.mark.parametrize("contact", ["linear", "hertz"])
def test_box_with_friction_drift_below_1e_3(contact, record_validation):
    p = shaken_box(contact=contact, mu=0.5, dt_factor=0.5)
    record_validation(f"Energy audit, shaken box of 64 spheres ({contact}, mu = 0.5): "
                      "|drift| / energy in play (NOT MET)", reference=1e-3,
                      measured=abs(p["drift_rel"]), tolerance=1e-3, kind="bound",
                      source="energy conservation (docs/design.md, Energy audit)",
                      note="the incremental tangential spring is not a potential; xfail")
    assert abs(p["drift_rel"]) < 1e-3


@pytest.mark.slow
@pytest.mark.xfail(strict=True, raises=AssertionError,
                   reason="as test_box_with_friction_drift_below_1e_3")
def test_2197_spheres_shaken_1s_drift_below_1e_3(record_validation):
    p = shaken_box(contact="hertz", mu=0.5, dt_factor=1.0, n_side=13, t_shake=1.0,
                   t_settle=1.0)
    record_validation("Energy audit, shaken box of 2197 spheres (hertz, mu = 0.5, 1 s + "
                      "1 s settling): |drift| / energy in play (NOT MET)", reference=1e-3,
                      measured=abs(p["drift_rel"]), tolerance=1e-3, kind="bound",
                      source="energy conservation (docs/design.md, Energy audit)")
    assert abs(p["drift_rel"]) < 1e-3
