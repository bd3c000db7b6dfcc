"""Contact conductance models (DESIGN.md "Heat in particles") evaluated directly."""
import math

import pytest

from gsi.dem import heat
from gsi.dem.materials import Material, pair_table

A = Material(E=1e9, nu=0.3, rho=2000, k=2.0)
B = Material(E=1e9, nu=0.3, rho=2000, k=8.0)


@pytest.mark.parametrize("name,expected", [
    ("area", lambda a2: 4 * 2 * 8 / 10 * math.sqrt(math.pi * a2)),
    ("radius", lambda a2: 4 * 2 * 8 / 10 * math.sqrt(a2)),
    ("constant", lambda a2: 0.3),
])
def test_models(name, expected):
    tab = pair_table([A, B], h_c=0.3).reshape(4, -1)
    fn = getattr(heat, heat.HEAT_MODELS[name][1])
    for a2 in (1e-8, 2.5e-7):
        assert fn(a2, tab, 1) == pytest.approx(expected(a2), rel=1e-14)
    if name != "constant":
        assert fn(0.0, tab, 1) == 0.0 and fn(-1e-9, tab, 1) == 0.0
