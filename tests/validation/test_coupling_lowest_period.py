"""The structure time scale behind the default sub-cycling (gsi.coupling.staggered).

:func:`lowest_period` estimates T_1 by Rayleigh's quotient with the static deflection
under a uniform body force. Reference: the clamped circular Kirchhoff plate,
omega_1 = 10.2158 / a^2 sqrt(D / (rho h)), D = E h^3 / (12 (1 - nu^2)) (Leissa, *Vibration
of Plates*, NASA SP-160, 1969, Table 2.1). On P2 meshes the estimate approaches it from
below (the discrete plate is stiffer and the quotient bounds omega_1 from above):
measured -10.2, -6.2, -4.7 % for h = 60, 40, 30 mm. :func:`choose_n_sub` then takes the
largest whole number of DEM steps within T_1 / steps_per_period.
"""
import math

import pytest

from gsi import meshes
from gsi.coupling.staggered import choose_n_sub, lowest_period
from gsi.fem.elasticity import Elasticity


def test_rayleigh_period_of_a_clamped_circular_plate():
    a, t = 0.3, 0.015
    sm = meshes.build("membrane", shape="circle", radius=a, thickness=t, h=0.03, n_thickness=1)
    p = Elasticity(sm, "rubber", degree=2)
    p.clamp("support")
    T_1 = lowest_period(p)
    m = p.material
    D = m.E * t**3 / (12 * (1 - m.nu**2))
    T_plate = 2 * math.pi / (10.2158 / a**2 * math.sqrt(D / (m.rho * t)))
    assert T_1 == pytest.approx(T_plate, rel=0.06)
    assert T_1 < T_plate
    # the problem is left as it was: no gravity, zero displacement
    assert p.max_displacement() == 0.0
    assert p.load_sum() == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)


def test_n_sub_is_the_largest_whole_number_of_dem_steps():
    assert choose_n_sub(1e-4, 0.2, steps_per_period=20) == 100
    assert choose_n_sub(3e-4, 0.2, steps_per_period=20) == 33     # 33.3 -> 33
    assert choose_n_sub(1e-2, 0.2, steps_per_period=20) == 1      # never below one
