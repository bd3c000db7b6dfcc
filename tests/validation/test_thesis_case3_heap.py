"""Seed 001 (thesis), chapter III, case 3: particles of random radii (1-2 mm) generated in
a rectangle collapse into "the final triangular shape formed by the particles at rest".

The case is ``demos/graded/case3_heap.toml`` (copper, linear law K = 6000 N/m, e_pp =
0.8, e_pw = 0.5, rolling resistance mu_r = 0.1; 134 discs of radius uniform in 1-2 mm on
the slab's mid-plane, placed by random sequential addition in a 36 x 36 mm rectangle,
``data/case3_rectangle.csv``), run by the runner at mu = 0.5 (the case) and mu = 0.1
(particle/particle and particle/floor).

Angle of the heap: the top surface h(x) of the union of the discs (exact, on a 0.25 mm
grid across the floor), its peak at the maximum of the 8 mm moving average of h; on each
flank a least-squares line through the surface points between 20 % and 80 % of the peak
height; the angle is atan |slope|, and the heap's angle the mean of the two flanks.

This is the final slope of a collapsed column, not a quasi-static angle of repose: the
soft (K = 6000 N/m), bouncy (e = 0.8) copper discs run out far, and 134 discs make a low
heap (13 mm), so the angles are small and a single particle moves them by a degree or
two. Measured (0.5 s, at rest): mu = 0.5: 8.0 and 9.1 degrees (mean 8.6); mu = 0.1:
0.8 and 4.0 (mean 2.4) (an earlier engine, with another floating-point summation order,
gave 7.5 / 9.8 and 0.4 / 3.6). The kinetic energy falls below 1e-8 J by 0.35-0.45 s,
depending on the last bounce (with mu = 0.1 one bounce gave 4e-7 J at 0.40 s and
1e-13 J at 0.45 s), so the case runs 0.5 s.

Since one particle moves an angle by a degree or two and one trajectory is one sample of
the collapse (the numbers above changed with the summation order), the test runs an
ensemble of M = 3 realisations at each mu (start positions moved by up to k x 0.5 nm in
the slab's plane, tests/validation/conftest.py) and asks that the ensemble mean angle
rise with mu on each flank and on the mean, and the peak height too, by more than three
standard errors of the difference (sqrt(SE_0.5^2 + SE_0.1^2)); every member must come
to rest. Measured (2026-12-04, M = 3 at dt; at dt (1 + 1e-12) in brackets), mean +- SE:
mu = 0.5 left 7.1 +- 1.7 (7.6 +- 1.0), right 8.7 +- 0.7 (9.2 +- 0.4); mu = 0.1 left
0.4 +- 0.3 (0.5 +- 0.3), right 2.3 +- 0.4 (1.8 +- 0.7) degrees.
"""
import dataclasses
import math
import pathlib

import numpy as np

from gsi.case import load_case

CASE = pathlib.Path(__file__).resolve().parents[2] / "demos" / "graded" / "case3_heap.toml"


def surface(x, z, r, grid):
    """Top of the union of discs (centres x, z, radii r) at the abscissae ``grid`` (m)."""
    h = np.zeros_like(grid)
    for xi, zi, ri in zip(x, z, r):
        m = np.abs(grid - xi) < ri
        h[m] = np.maximum(h[m], zi + np.sqrt(ri * ri - (grid[m] - xi) ** 2))
    return h


def heap_angles(x, z, r, *, lo, hi, dx=2.5e-4, smooth=8e-3, band=(0.2, 0.8)):
    """(left, right) flank angles (degrees) and the peak height (m); see the docstring."""
    grid = np.arange(lo, hi + 0.5 * dx, dx)
    h = surface(x, z, r, grid)
    k = max(1, int(round(smooth / dx)))
    ip = int(np.argmax(np.convolve(h, np.ones(k) / k, mode="same")))
    H = float(np.convolve(h, np.ones(k) / k, mode="same")[ip])
    angles = []
    for side in (slice(0, ip), slice(ip, len(grid))):
        g, hh = grid[side], h[side]
        m = (hh > band[0] * H) & (hh < band[1] * H)
        assert m.sum() > 10
        angles.append(float(np.degrees(np.arctan(abs(np.polyfit(g[m], hh[m], 1)[0])))))
    return angles, H


M = 3
#: sd floor (conftest) of one flank's angle (degrees): the smallest spread of two 3-member
#: ensembles per mu (at dt and at dt (1 + 1e-12), 2026-12-04: sd 0.5-2.9 degrees)
SD_ANGLE = 0.5


def _case(mu):
    case = load_case(CASE)
    case.materials["copper"] = dataclasses.replace(case.materials["copper"], mu=mu)
    case.pairs = [dataclasses.replace(p, mu=mu) if "floor" in p.materials else p
                  for p in case.pairs]
    return case


def heap_members(ens, out, mu):
    """(left, right, mean) angles (degrees) and peak heights (m) of M members at ``mu``."""
    angles, peaks = [], []
    for runner in ens.run_members(lambda: _case(mu), out / f"mu{mu}", M, plane="xz"):
        res, sim, case = runner.result, runner.sim, runner.case
        assert res.n_particles == 134 and res.n_lost == 0
        assert res.monitors["heap"]["kinetic_energy_J"][-1] < 1e-8   # at rest: v_rms < 1 mm/s
        floor = [w for w in case.walls if w.name in ("left", "right")]
        lo, hi = sorted(w.point[0] for w in floor)
        a, H = heap_angles(sim.x[:, 0], sim.x[:, 2], sim.radius, lo=lo, hi=hi)
        angles.append(a + [float(np.mean(a))])
        peaks.append(H)
    return np.array(angles), np.array(peaks)


def test_heap_angle_rises_with_friction(tmp_path, ens, record_validation):
    a_hi, H_hi = heap_members(ens, tmp_path, 0.5)
    a_lo, H_lo = heap_members(ens, tmp_path, 0.1)
    s_hi, s_lo = ens.stat(a_hi, SD_ANGLE), ens.stat(a_lo, SD_ANGLE)
    h_hi, h_lo = ens.stat(H_hi), ens.stat(H_lo)
    print(f"heap angles (left, right, mean), mu = 0.5: {s_hi.text()}; mu = 0.1: "
          f"{s_lo.text()}; peaks {h_hi.text()} and {h_lo.text()} m")
    diff = s_hi.mean - s_lo.mean
    se = np.sqrt(s_hi.se ** 2 + s_lo.se ** 2)
    record_validation("seed 001 case 3 (M = 3 per mu): mean heap angle rise mu 0.1 -> 0.5, "
                      "minus 3 SE", reference=0.0, measured=float(diff[2] - 3 * se[2]),
                      tolerance=0.0, kind="bound", unit="deg",
                      note="the ensemble mean angle rises with mu by more than 3 SE",
                      source="the thesis's case 3 (friction steepens the heap)")
    assert (diff - 3 * se > 0).all(), (diff, se)
    assert h_hi.mean - h_lo.mean > 3 * math.sqrt(h_hi.se ** 2 + h_lo.se ** 2)
