"""Seed 001 (thesis), chapter III, case 4: heat between two particles at rest; and the
two-body validation of the ``radius`` and ``area`` conductance models.

The case is ``demos/graded/case4_two_particles.toml``: two particles (r = 2 mm) at
373.15 and 273.15 K (100 and 0 degC), centres L = 3.8 mm apart, held in place with
``sim.fix`` (the thesis: "at rest"; the case model has no key for fixed particles).

Contact radius of two spheres r_c^2 = R^2 - (L/2)^2 (0.6245 mm); conductance of the
``radius`` model (thesis eq. II.5) H = 2 k r_c, of the ``area`` model H = 2 k sqrt(pi)
r_c (same material: 4 k k/(k + k) = 2 k). Heat capacities C = m c_p (equal), so
D = T1 - T2 obeys C dD/dt = -2 H D:

* continuous: D(t) = D0 exp(-t/tau), tau = C/(2 H) (copper, radius: 0.0533 s);
* the DEM's explicit update T += dt Q/C (gsi.dem.integrate) gives exactly
  D_n = D0 (1 - r)^n with r = dt/tau;
* the two differ by at most D0 c/e with c = -ln(1 - r)/r - 1 (= r/2 + O(r^2)):
  (1 - r)^n = exp(-x (1 + c)), x = n r, and exp(-x)(1 - exp(-c x)) <= c x exp(-x) <= c/e.

Targets (the issue): discrete solution to 1e-9 K, the exponential within D0 c/e, the
final common temperature 323.15 K (50 degC) to 1e-12 K.

Round-off decides the last two digits, and the 1e-12 K target on the final temperatures
is out of reach of float64 (measured: 5.05e-10 K). The explicit update stops changing a
temperature once its increment r D/2 is below half the spacing u of doubles at T
(u = 5.7e-14 K in [256, 512) K): D stalls at D_floor = u/r (1.01e-9 K for copper at
dt = 3e-6 s; measured 1.0106e-9 K), so each temperature stays within D_floor/2 of
323.15 K. Tested instead, and met: the discrete solution to 1e-9 K while D_n > 10
D_floor (measured 3.3e-11 K over 23 tau); the final temperatures within D_floor/2 of
323.15 K; the mean (T1 + T2)/2 = 323.15 K to 1e-12 K at every sample (measured 0: both
temperatures lie in [256, 512) K, where the grids coincide, so T1 + a and T2 - a round
alike and the sum is conserved exactly).
"""
import dataclasses
import math
import pathlib

import numpy as np
import pytest

from gsi.case import load_case
from gsi.run import build_simulation

CASE = (pathlib.Path(__file__).resolve().parents[2] / "demos" / "graded"
        / "case4_two_particles.toml")


def two_body(*, material="copper", heat=None, dt=None, duration, sample_steps=1000):
    """Run the case's two fixed particles; returns (t, T1, T2, case, sim)."""
    case = load_case(CASE)
    case.particles = [dataclasses.replace(p, material=material) for p in case.particles]
    if heat is not None:
        case.dem = dataclasses.replace(case.dem, heat=heat)
    if dt is not None:
        case.run = dataclasses.replace(case.run, dt=dt)
    sim, _, _ = build_simulation(case, dt=case.time_step())
    sim.fix(sim.ids)
    n = int(round(duration / sim.dt))
    t, T1, T2 = [0.0], [float(sim.T[0])], [float(sim.T[1])]
    done = 0
    while done < n:
        k = min(sample_steps, n - done)
        sim.step(k)
        done += k
        t.append(sim.time)
        T1.append(float(sim.T[0]))
        T2.append(float(sim.T[1]))
    return np.array(t), np.array(T1), np.array(T2), case, sim


def conductance(case, sim, model):
    """H (W/K) of the two-sphere contact from the geometry, independent of the DEM."""
    k = case.materials[case.particles[0].material].k
    R = float(sim.radius[0])
    L = float(np.linalg.norm(sim.x[1] - sim.x[0]))
    rc = math.sqrt(R * R - 0.25 * L * L)
    return {"radius": 2 * k * rc, "area": 2 * k * math.sqrt(math.pi) * rc}[model], rc


def check_two_body(t, T1, T2, case, sim, model, *, tau_expected):
    H, rc = conductance(case, sim, model)
    C = float(sim.heat_capacity[0])
    tau = C / (2 * H)
    assert tau == pytest.approx(tau_expected, rel=2e-3)
    D0 = T1[0] - T2[0]
    assert D0 == pytest.approx(100.0, abs=1e-12)
    r = sim.dt / tau
    n = np.rint(t / sim.dt)
    D = T1 - T2
    discrete = D0 * (1.0 - r) ** n
    floor = np.spacing(0.5 * (T1[0] + T2[0])) / r      # the round-off stall of D (K)
    resolved = discrete > 10 * floor
    assert np.abs(D - discrete)[resolved].max() < 1e-9
    bound = D0 * (-math.log1p(-r) / r - 1.0) / math.e
    err = np.abs(D - D0 * np.exp(-t / tau)).max()
    assert err <= bound
    assert err > 0.5 * bound                    # the O(dt) error is there, and of that size
    mean0 = 0.5 * (T1[0] + T2[0])
    assert np.abs(0.5 * (T1 + T2) - mean0).max() <= 1e-12
    return H, rc, C, tau, err, bound, floor


def test_copper_radius_model_thesis_numbers(record_validation):
    t, T1, T2, case, sim = two_body(duration=1.8)     # 34 tau: D < 1e-12 K
    H, rc, C, tau, err, bound, floor = check_two_body(t, T1, T2, case, sim, "radius",
                                                      tau_expected=0.0533)
    src = "seed 001 case 4 (thesis, Table III.1, eq. II.5)"
    record_validation("seed 001 case 4, copper: contact radius r_c", reference=0.6245e-3,
                      measured=rc, tolerance=1e-4, unit="m", source=src)
    record_validation("seed 001 case 4, copper: conductance H = 2 k r_c", reference=0.481,
                      measured=H, tolerance=1e-3, unit="W/K", source=src)
    record_validation("seed 001 case 4, copper: heat capacity m c_p", reference=0.0513,
                      measured=C, tolerance=1e-3, unit="J/K", source=src)
    record_validation("seed 001 case 4, copper: time constant tau", reference=0.0533,
                      measured=tau, tolerance=2e-3, unit="s", source=src)
    assert rc == pytest.approx(0.6245e-3, rel=1e-4)
    assert H == pytest.approx(0.481, rel=1e-3)
    assert C == pytest.approx(0.0513, rel=1e-3)
    assert floor < 1.1e-9
    # the final 50 degC to the round-off floor (the 1e-12 K: see the docstring)
    assert abs(T1[-1] - 323.15) <= 0.5 * floor
    assert abs(T2[-1] - 323.15) <= 0.5 * floor


def test_alumina_radius_model():
    # Table III.1's alumina step 5e-6 s; 1.2 tau (the DEM step count, not the physics, limits it)
    t, T1, T2, case, sim = two_body(material="alumina", dt=5e-6, duration=1.5,
                                    sample_steps=5000)
    check_two_body(t, T1, T2, case, sim, "radius", tau_expected=1.27)


def test_copper_area_model():
    t, T1, T2, case, sim = two_body(heat="area", duration=0.3)
    H, *_ = check_two_body(t, T1, T2, case, sim, "area", tau_expected=0.0533 / math.sqrt(math.pi))
    assert H == pytest.approx(0.481 * math.sqrt(math.pi), rel=1e-3)
