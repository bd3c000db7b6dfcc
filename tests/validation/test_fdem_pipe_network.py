"""Seed 002 (the FDEM contact-heat paper), section 5: Feng's pipe-network model.

1. The ``pipe`` conductance of the DEM (:func:`gsi.dem.contact.conductance.pipe`), H = w/(R_A + R_B +
   R_c*), R_A = (1/(pi k_A)) (-ln alpha_A + 3/2 + alpha_A^2/36), sin alpha_A = a/r_A,
   in a two-body run: two spheres held at a fixed overlap exchange heat with the exact
   explicit recursion (1 - 2 H dt/(m c_p))^n of the lumped pair (H from the formula,
   written out here).
2. The paper's comparison: two thin FE cylinders (r = 0.5 m, w = 0.1 m, here; the
   paper's Table 3 is not in its text) overlapping so that the theoretical contact is
   S_th = 2 alpha r w = 0.02 m^2 (alpha = 0.2 rad, the paper's S_th), at 1 and 0 degC,
   exchanging heat through R_c = 0.5 m^2 K/W (:mod:`gsi.fem.contact_heat`), against the
   lumped pipe ODE C dT_B/dt = (T_A - T_B)/R_AB, C = pi rho c r^2 (per length), with the
   paper's adjustment R_c* = R_c w/S_c - R_A - R_B and alpha = S_c/(2 w r) from the
   computed S_c, so that R_AB = R_c w/S_c.

   Error measure: the mean over the 300 steps (3 time constants) of |T_B - T_B,pipe| /
   (T_B,pipe - T_B(0)), B's mean temperature. The paper's figures and ours (measured):

   ==================================  ==============  ===================
   quantity                            paper           gsi
   ==================================  ==============  ===================
   contact area error, coarse / fine   4 % / 0.4 %     1.77 % / 0.039 %
                                                       (h 0.05 / 0.025 m)
   mean-Delta-T variant vs pipe ODE    0.63 %          0.32 %
   local variant vs pipe, low k        7.6 %           3.03 % (k = 10)
   local variant vs pipe, k x 100      0.7 %           0.19 %
   ==================================  ==============  ===================

   The local variant differs at low k because the resolved discs add their constriction
   resistance to R_c w/S_c; Feng's R_A is that resistance: with R_AB = R_c w/S_c + R_A +
   R_B the pipe ODE follows the local FE run to 0.62 % (k = 10). (At h = 0.1 m the area
   error is 0.74 %, below the 0.05 m one: the faceted arcs' intersection depends on where
   the polygon vertices fall, so the error is not monotone in h.)
"""
import math

import numpy as np
import pytest

from gsi import meshes
from gsi.dem import Material, Simulation
from gsi.fem import compat
from gsi.fem.contact_heat import ContactHeatSystem, ThermalContact
from gsi.fem.heat import Heat
from gsi.fem.materials import StructuralMaterial

R, W, ALPHA = 0.5, 0.1, 0.2                 # disc radius, width (m), contact half angle (rad)
PEN = 2 * R * (1 - math.cos(ALPHA))         # penetration giving the arc of half angle ALPHA
S_TH = 2 * ALPHA * R * W                    # 0.02 m^2
R_C = 0.5                                   # m^2 K/W
RHO_C = 1000.0                              # J/(m^3 K)


def feng_R(alpha, k):
    """Feng's pipe resistance per length (K m/W), written out independently."""
    return (-math.log(alpha) + 1.5 + alpha ** 2 / 36.0) / (math.pi * k)


# ---------------------------------------------------------------------------- DEM model
def test_dem_pipe_model_two_body_run():
    r, k, cp, rho = 1e-3, 50.0, 500.0, 7800.0
    w, R_star = 2e-3, 1e-3                   # pipe length (m), contact resistance (K m/W)
    mat = Material(E=1e9, nu=0.3, rho=rho, e=0.5, mu=0.3, k=k, cp=cp)
    dt = 1e-6
    sim = Simulation({"steel": mat}, heat="pipe", pipe_length=w, pipe_resistance=R_star,
                     gravity=(0, 0, 0), dt=dt, skin=1e-4, domain=((-0.01,) * 3, (0.01,) * 3))
    L = 2 * r - 0.02 * r
    ids = sim.add_particles([[0, 0, 0], [L, 0, 0]], r, material="steel", T=[100.0, 0.0])
    sim.fix(ids)
    a = math.sqrt(r * r - (L / 2) ** 2)
    alpha = math.asin(a / r)
    H = w / (2 * feng_R(alpha, k) + R_star)
    mc = rho * 4 / 3 * math.pi * r ** 3 * cp
    x = 2 * H * dt / mc
    assert sim.heat_stability() == pytest.approx(H * dt / mc, rel=1e-12)
    sim.step(20000)
    assert sim.T[0] - sim.T[1] == pytest.approx(100 * (1 - x) ** 20000, rel=1e-9)
    assert sim.T[0] - sim.T[1] < 95.0
    assert sim.T.mean() == pytest.approx(50.0, rel=1e-13)


def test_dem_pipe_model_needs_its_length():
    from gsi.errors import GsiInputError
    mat = Material(E=1e9, nu=0.3, rho=7800, k=50.0, cp=500.0)
    with pytest.raises(GsiInputError, match=r"^pipe_length = None: the pipe heat model needs"):
        Simulation({"s": mat}, heat="pipe", dt=1e-6, skin=1e-4,
                   domain=((-0.01,) * 3, (0.01,) * 3))


# ---------------------------------------------------------------------------- FE discs
def discs(h, k, temperature, dt=10.0):
    a = meshes.build("membrane", shape="circle", radius=R, thickness=W, h=h, n_thickness=2)
    b = meshes.build("membrane", shape="circle", radius=R, thickness=W, h=h, n_thickness=2)
    compat.geometry_x(b.mesh)[:, 0] += 2 * R - PEN
    mat = StructuralMaterial(E=1e9, nu=0.3, rho=RHO_C, c=1.0, k=k)
    ha = Heat(a, mat, dt=dt, T_initial=1.0)
    hb = Heat(b, mat, dt=dt, T_initial=0.0)
    c = ThermalContact(ha, hb, tags_a=["support"], tags_b=["support"], R_c=R_C,
                       temperature=temperature)
    return ha, hb, c


def test_contact_area_of_two_overlapping_discs():
    err = {}
    for h in (0.05, 0.025):
        _, _, c = discs(h, 10.0, "local")
        err[h] = abs(c.area / S_TH - 1)
        assert c.S_tar == pytest.approx(c.S_con, rel=2e-3)
    print("contact area error h 0.05, 0.025:", err)
    assert err[0.05] < 0.04 and err[0.025] < 0.004 and err[0.025] < err[0.05] / 4


def _pipe_error(k, temperature, *, with_constriction=False, n=300, dt=10.0):
    ha, hb, c = discs(0.05, k, temperature, dt)
    group = ContactHeatSystem([c])
    TB = []
    for _ in range(n):
        group.step()
        TB.append(hb.mean_temperature())
    alpha = c.area / (2 * W * R)                        # the paper's alpha from S_c
    R_A = feng_R(alpha, k)
    R_star = R_C * W / c.area - 2 * R_A                 # the paper's adjustment
    R_AB = 2 * R_A + R_star + (2 * R_A if with_constriction else 0.0)
    C = math.pi * RHO_C * R * R                          # per length, J/(m K)
    t = dt * np.arange(1, n + 1)
    ref = 0.5 * (1 - np.exp(-2 * t / (R_AB * C)))
    return float(np.mean(np.abs(np.array(TB) - ref) / ref))


def test_mean_temperature_variant_follows_the_pipe_ode():
    err = _pipe_error(10.0, "mean")
    print(f"mean variant vs pipe ODE: {err:.4%}")
    assert err < 0.01                                   # paper 0.63 %; measured 0.32 %


def test_local_variant_departs_at_low_k_and_agrees_at_high_k():
    low = _pipe_error(10.0, "local")
    with_R_A = _pipe_error(10.0, "local", with_constriction=True)
    high = _pipe_error(1000.0, "local")
    print(f"local vs pipe: k 10 {low:.4%} (with R_A + R_B: {with_R_A:.4%}); k 1000 {high:.4%}")
    assert low > 0.02                                   # paper 7.6 %; measured 3.03 %
    assert with_R_A < 0.01                              # Feng's R_A: measured 0.62 %
    assert high < 0.01                                  # paper 0.7 %; measured 0.19 %
