"""Seed 000 (the XDEM paper), eqs. 22-23: radiation, here its FE surface part -- a
radiative condition eps sigma (T^4 - T_amb^4) on heat surfaces by tag
(:meth:`gsi.fem.heat.Heat.set_radiation`, explicit in T: the flux of a step is taken at
T_n).

References:

* a lumped body cooling into a 0 K enclosure: m c dT/dt = -eps sigma A T^4 integrates to
  t = m c/(3 eps sigma A) (T^-3 - T0^-3) -- a 0.1 m cube of very conducting material
  (Biot 4 eps sigma T^3 L/k = 5e-7) radiating from all six faces; within 0.5 %;
* a radiating slab, steady: T_h fixed at x = 0, radiation at x = L into T_amb, the
  other faces insulated: k (T_h - T_s)/L = eps sigma (T_s^4 - T_amb^4) (root by brentq);
* energy: the stored heat changes by exactly the radiated heat the steps applied.
"""

import numpy as np
import pytest
import scipy.constants
import scipy.optimize

from gsi import meshes
from gsi.errors import GsiInputError
from gsi.fem.heat import Heat
from gsi.fem.materials import StructuralMaterial

SIGMA = scipy.constants.Stefan_Boltzmann


def cube(k, T0, dt, eps=0.8, T_amb=0.0):
    sm = meshes.build("box", length_x=0.1, length_y=0.1, length_z=0.1, h=0.05)
    mat = StructuralMaterial(E=1e9, nu=0.3, rho=1000.0, c=500.0, k=k)
    heat = Heat(sm, mat, dt=dt, theta=1.0, T_initial=T0)
    for tag in ("x0", "x1", "y0", "y1", "z0", "z1"):
        heat.set_radiation(tag, eps, T_amb)
    return heat


def test_lumped_cube_cools_into_a_0K_enclosure(record_validation):
    """rho c V = 500 J/K, A = 0.06 m^2, T0 = 1000 K: t(T) exact; measured max deviation
    of t at the sampled temperatures 0.26 % (dt = 1 s, explicit flux; 0.52 % at 2 s)."""
    T0, dt, eps = 1000.0, 1.0, 0.8
    heat = cube(1e4, T0, dt, eps)
    mc, A = 1000.0 * 500.0 * 1e-3, 0.06
    E0 = heat.stored_heat()
    radiated = 0.0
    worst = 0.0
    for n in range(1, 3001):
        heat.step()
        radiated += sum(heat.radiation_heat_flow(t) for t in heat.radiation) * dt
        if n % 600 == 0:
            T = heat.mean_temperature()
            t_exact = mc / (3 * eps * SIGMA * A) * (T ** -3 - T0 ** -3)
            worst = max(worst, abs(heat.t / t_exact - 1))
    print(f"lumped radiative cooling: max |t/t_exact - 1| = {worst:.3e}, T_end "
          f"{heat.mean_temperature():.2f} K")
    record_validation("radiating cube into a 0 K enclosure: max |t/t_exact - 1|", reference=0.0,
                      measured=worst, tolerance=0.005, kind="abs",
                      source="t = m c/(3 eps sigma A)(T^-3 - T0^-3) (XDEM paper's radiation, FE surface)")
    assert heat.mean_temperature() < 0.75 * T0          # it cooled substantially
    assert worst < 0.005
    assert heat.stored_heat() - E0 == pytest.approx(radiated, rel=1e-10)


@pytest.mark.parametrize("T_amb", [300.0, 0.0])
def test_radiating_slab_steady_state(T_amb, record_validation):
    """Bar 0.2 m, k = 20 W/(m K), rho c = 1e6 J/(m^3 K), T_h = 800 K, eps = 0.9: T_s from
    the balance. P1 is exact for the linear steady profile; what remains is the distance
    to steady state after 10 L^2/alpha."""
    L, k, T_h, eps = 0.2, 20.0, 800.0, 0.9
    sm = meshes.build("box", length_x=L, length_y=0.1, length_z=0.1, h=0.05)
    mat = StructuralMaterial(E=1e9, nu=0.3, rho=1000.0, c=1000.0, k=k)  # alpha 2e-5 m^2/s
    heat = Heat(sm, mat, dt=20.0, theta=1.0, T_initial=T_h)
    heat.fix_temperature("x0", T_h)
    heat.set_radiation("x1", eps, T_amb)
    T_s = scipy.optimize.brentq(lambda T: k * (T_h - T) / L - eps * SIGMA * (T ** 4 - T_amb ** 4),
                                T_amb, T_h, xtol=1e-12)
    for _ in range(1000):                                # 2e4 s = 10 L^2/alpha
        heat.step()
    x = heat.V.tabulate_dof_coordinates()[:, 0]
    Ts = heat.T.x.array[np.isclose(x, L)]
    assert np.allclose(Ts, T_s, rtol=1e-6)
    q = eps * SIGMA * (T_s ** 4 - T_amb ** 4) * 0.01
    src = "k (T_h - T_s)/L = eps sigma (T_s^4 - T_amb^4)"
    record_validation(f"radiating slab, steady (T_amb = {T_amb} K): surface temperature",
                      reference=T_s, measured=float(Ts.mean()), tolerance=1e-6, unit="K",
                      source=src)
    record_validation(f"radiating slab, steady (T_amb = {T_amb} K): radiated heat flow",
                      reference=q, measured=-heat.radiation_heat_flow("x1"), tolerance=1e-5,
                      unit="W", source=src)
    assert -heat.radiation_heat_flow("x1") == pytest.approx(q, rel=1e-5)
    assert heat.dirichlet_heat_flow("x0") == pytest.approx(q, rel=1e-5)


def test_radiation_inputs_and_the_explicit_limit():
    heat = cube(1e4, 1000.0, 2.0)
    with pytest.raises(GsiInputError, match=r"emissivity = 1.5: must be in \(0, 1\]"):
        heat.set_radiation("x0", 1.5, 300.0)
    with pytest.raises(GsiInputError, match=r"T_ambient = -1.0: must be >= 0 \(K\)"):
        heat.set_radiation("x0", 0.5, -1.0)
    hot = cube(1e4, 3000.0, 200.0)
    with pytest.raises(GsiInputError, match=r"^structure.heat.radiation.x0: the step dt = 200 s "
                                            r"is above the explicit radiation limit"):
        hot.step()
