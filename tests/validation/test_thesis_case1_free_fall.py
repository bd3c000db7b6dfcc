"""Seed 001 (thesis), chapter III, case 1: a copper particle falls on a flat floor.

The case is ``demos/graded/case1_free_fall.toml`` (Table III.1: linear law K = 6000 N/m,
e_pw = 0.5, copper r = 2 mm, the 0.05 x 0.0375 m box, quasi-2D between frictionless
planes); the test drives its DEM step by step (``gsi.run.build_simulation``).

Rebound height: the apex of the centre above the touch point z = R, taken in free flight
right after the contact ends as h = (z - R) + v_z^2/(2 g) (exact: velocity Verlet
integrates a constant acceleration exactly).

References:

* undamped (pair e = 1): the linear spring conserves energy, the particle returns to its
  start height (the thesis: "returns to exactly its initial position"); target 0.5 %.
* damped (e_pw = 0.5): without gravity during the contact, h_{k+1}/h_k = e^2 exactly.
  Gravity acts during the contact too (m g/k = 0.49 um of static overlap, t_c = 0.72
  ms), so the exact ratio of the linear spring-dashpot is below e^2 and drops as the
  impact slows; it is computed here in closed form (``exact_rebound``: the damped
  oscillator delta'' = g - w0^2 delta - 2 a delta', from delta = 0 to delta = 0 again).
  The thesis's target e^2 within 1 % holds for the first rebound only (exact 0.2481,
  -0.76 %); the later ones are 1.5, 3.1, 6.4 % below e^2 by the physics of the model.
  The run must follow the exact ratios to its O(dt) contact-onset error (the dashpot
  switches on at full strength within one step of the touch: 0.1 % at dt = 1e-6 s,
  0.7 % at 2e-6 s, 0.02 % at 5e-7 s, measured).
"""
import dataclasses
import math
import pathlib

import pytest
from scipy.optimize import brentq

from gsi.case import load_case
from gsi.run import build_simulation

CASE = pathlib.Path(__file__).resolve().parents[2] / "demos" / "graded" / "case1_free_fall.toml"
G = 9.81


def exact_rebound(v, m, k, e, g=G):
    """Exit speed (m/s) of the linear spring-dashpot (tension allowed) hit at speed v
    under gravity g: delta(t) = d_g + exp(-a t)(A cos w_d t + B sin w_d t)."""
    le = math.log(e) if e < 1.0 else 0.0
    beta = le / math.sqrt(le * le + math.pi ** 2)
    a = -beta * math.sqrt(k / m)                    # gamma/(2 m), gamma = -2 beta sqrt(k m)
    w0 = math.sqrt(k / m)
    wd = math.sqrt(w0 * w0 - a * a)
    dg = g / w0 ** 2
    A, B = -dg, (v - a * dg) / wd

    def delta(t):
        return dg + math.exp(-a * t) * (A * math.cos(wd * t) + B * math.sin(wd * t))

    t1 = brentq(delta, 0.5 * math.pi / wd, 1.5 * math.pi / wd)
    rate = math.exp(-a * t1) * ((wd * B - a * A) * math.cos(wd * t1)
                                - (a * B + wd * A) * math.sin(wd * t1))
    return -rate


def rebound_heights(case, duration, *, sample=1.0e-4):
    """Start height and the rebound heights (m above the touch point) of the run."""
    dt = case.time_step()
    sim, _, _ = build_simulation(case, dt=dt)
    R = float(sim.radius[0])
    h = [float(sim.x[0, 2]) - R]
    chunk = max(1, int(round(sample / dt)))
    touching = False
    for _ in range(int(round(duration / sample))):
        sim.step(chunk)
        z, vz = float(sim.x[0, 2]), float(sim.v[0, 2])
        if z < R:
            touching = True
        elif touching:
            touching = False
            h.append(z - R + vz * vz / (2 * G))
    return h, sim


def test_undamped_returns_to_start_height():
    case = load_case(CASE)
    case.pairs = [dataclasses.replace(p, e=1.0) if "floor" in p.materials else p
                  for p in case.pairs]
    h, _ = rebound_heights(case, 0.24)            # two rebounds (0.076 s fall, 0.151 s per bounce)
    assert len(h) >= 3
    for hk in h[1:3]:
        assert hk == pytest.approx(h[0], rel=5e-3)   # target 0.5 % (measured 3e-5)


def test_damped_rebounds_fall_by_e_squared(record_validation):
    case = load_case(CASE)
    e = next(p.e for p in case.pairs if "floor" in p.materials)
    assert e == 0.5
    h, sim = rebound_heights(case, 0.26)
    m, k = float(sim.mass[0]), case.dem.k_n
    ratios = [b / a for a, b in zip(h, h[1:])][:4]
    assert len(ratios) == 4
    # the thesis's target, first rebound (exact -0.76 % by gravity during the contact)
    record_validation("seed 001 case 1, e_pw = 0.5: first rebound height ratio h1/h0",
                      reference=e * e, measured=ratios[0], tolerance=1e-2,
                      source="the thesis's target e^2 (seed 001, chapter III)")
    assert ratios[0] == pytest.approx(e * e, rel=1e-2)
    # every rebound against the exact linear spring-dashpot under gravity
    for a, r in zip(h, ratios):
        v = math.sqrt(2 * G * a)
        r_exact = (exact_rebound(v, m, k, e) / v) ** 2
        assert r == pytest.approx(r_exact, rel=2.5e-3), (r, r_exact)
