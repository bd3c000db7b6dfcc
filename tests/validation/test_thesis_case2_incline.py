"""Seed 001 (thesis), chapter III, case 2: a copper particle bounces off an inclined wall.

The case is ``demos/graded/case2_incline.toml`` (Table III.1: linear law K = 6000 N/m,
e_pw = 0.5, copper r = 2 mm; a 45 degree plane with mu_pw = 0.1, which the thesis does not
give); the test drives its DEM step by step through the contact.

Expected values (n: the plane's normal, t: down the slope; contact from delta = 0 to 0):

* normal: the linear spring-dashpot returns v_n' = e v_n without gravity; with the
  component g cos(phi) of gravity during the 0.72 ms contact the exact exit speed is the
  closed form of :func:`contact_history`, 0.49 % below e v_n here.
* tangential: the particle arrives without spin, so the contact point slips down the
  slope at v_t. While it slides, the tangential force is the Coulomb cap mu |F_n| against
  the slip (the history spring is reset onto the cap every step), with F_n the contact
  force k delta + gamma delta' (tension near the end of the contact, as the law allows).
  Sliding lasts the whole contact if the slip never stops: the slip speed drops by
  (1/m + R^2/I) mu int|F_n| dt = 3.5 mu J (J = int|F_n| dt / m) and gains g sin(phi) t_c,
  so the regime is sliding when 3.5 mu J < v_t + g sin(phi) t_c (here 0.23 < 0.42 m/s,
  asserted below; above it the contact would stick and the spring would decide). Then
  exactly v_t' = v_t + g sin(phi) t_c - mu J and omega' R = 2.5 mu J_R (lever R - delta).
  J is integrated from the closed-form delta(t) of the contact.
Targets: each within 1 % (the issue); the run must also follow the exact gravity-aware
values to its O(dt) contact-onset error.
"""
import math
import pathlib

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from gsi.case import load_case
from gsi.run import build_simulation

CASE = pathlib.Path(__file__).resolve().parents[2] / "demos" / "graded" / "case2_incline.toml"
G = 9.81


def contact_history(v, m, k, e, g, R):
    """(exit normal speed, contact time t_c, J = int |F_n| dt / m, J_R = int (1 -
    delta/R) |F_n| dt / m) of the linear spring-dashpot hit at normal speed v with the
    normal gravity component g (J_R: the friction torque's lever R - delta)."""
    le = math.log(e)
    beta = le / math.sqrt(le * le + math.pi ** 2)
    w0 = math.sqrt(k / m)
    a = -beta * w0
    wd = math.sqrt(w0 * w0 - a * a)
    dg = g / w0 ** 2
    A, B = -dg, (v - a * dg) / wd

    def delta(t):
        return dg + math.exp(-a * t) * (A * math.cos(wd * t) + B * math.sin(wd * t))

    def rate(t):
        return math.exp(-a * t) * ((wd * B - a * A) * math.cos(wd * t)
                                   - (a * B + wd * A) * math.sin(wd * t))

    t1 = brentq(delta, 0.5 * math.pi / wd, 1.5 * math.pi / wd)
    def force(t):
        return abs(w0 * w0 * delta(t) + 2 * a * rate(t))

    J = quad(force, 0.0, t1, limit=200)[0]
    J_R = quad(lambda t: (1.0 - delta(t) / R) * force(t), 0.0, t1, limit=200)[0]
    return -rate(t1), t1, J, J_R


def bounce(case):
    """Velocity and spin before and after the contact with the incline."""
    dt = case.time_step()
    sim, walls, _ = build_simulation(case, dt=dt)
    w = next(x for x in case.walls if x.name == "incline")
    p, n = np.asarray(w.point), np.asarray(w.normal) / np.linalg.norm(w.normal)
    R = float(sim.radius[0])

    def gap():
        return float((sim.x[0] - p) @ n) - R

    while gap() > 5e-4:
        sim.step(100)
    while gap() >= 0.0:
        v_in = sim.v[0].copy()
        sim.step(1)
    while gap() < 0.0:
        sim.step(1)
    return sim, n, R, v_in, sim.v[0].copy(), sim.omega[0].copy()


def test_incline_normal_and_tangential_velocity(record_validation):
    case = load_case(CASE)
    pair = next(p for p in case.pairs if "incline" in p.materials)
    e, mu, k = pair.e, pair.mu, case.dem.k_n
    sim, n, R, v_in, v_out, w_out = bounce(case)
    m = float(sim.mass[0])
    g = np.asarray(case.dem.gravity)
    t = g - (g @ n) * n
    t /= np.linalg.norm(t)                                   # down the slope
    phi = math.acos(n[2])
    vn, vt = -float(v_in @ n), float(v_in @ t)
    vn_out, vt_out = float(v_out @ n), float(v_out @ t)
    vn_exact, tc, J, J_R = contact_history(vn, m, k, e, G * math.cos(phi), R)
    # the regime: sliding throughout (the slip never stops)
    slip_end = vt + G * math.sin(phi) * tc - mu * J - 2.5 * mu * J_R
    assert slip_end > 0.25 * vt                      # measured 0.18 m/s = 0.45 v_t
    vt_exact = vt + G * math.sin(phi) * tc - mu * J
    # the targets (1 %)
    src = "seed 001 case 2 (thesis, chapter III): v_n'/v_n = e, v_t' = v_t + g sin(phi) t_c - mu J"
    record_validation("seed 001 case 2, incline: normal restitution v_n'/v_n", reference=e,
                      measured=vn_out / vn, tolerance=1e-2, source=src)
    record_validation("seed 001 case 2, incline: tangential exit speed", reference=vt_exact,
                      measured=vt_out, tolerance=1e-2, unit="m/s", source=src)
    assert vn_out / vn == pytest.approx(e, rel=1e-2)
    assert vt_out == pytest.approx(vt_exact, rel=1e-2)
    # the exact contact of the law under gravity, to the O(dt) onset error (the dashpot
    # switches on within one step: at most 2 zeta w0 dt / e = 0.39 % of the exit speed;
    # measured -0.14 % normal, +0.005 % tangential)
    assert vn_out == pytest.approx(vn_exact, rel=3e-3)
    assert vt_out == pytest.approx(vt_exact, rel=3e-3)
    # the spin of the friction torque mu |F_n| (R - delta): omega R = 2.5 mu J_R
    axis = np.cross(n, t)
    assert abs(float(w_out @ axis)) * R == pytest.approx(2.5 * mu * J_R, rel=3e-3)
    # friction matters here: without it v_t' would be 19 % higher
    assert (vt + G * math.sin(phi) * tc) / vt_exact > 1.15
